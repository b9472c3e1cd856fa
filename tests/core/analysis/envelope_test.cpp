// SPDX-License-Identifier: MIT
#include "core/analysis/envelope.hpp"

#include <QtTest>
#include <cmath>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/analysis/analyzer.hpp"
#include "core/contract/pallet_metrics.hpp"
#include "core/inputs/pallet_source.hpp"
#include "core/inputs/random_pallet.hpp"
#include "core/physics/scene.hpp"
#include "core/physics/simulate.hpp"
#include "core/physics/step.hpp"
#include "tests/core/test_friction.hpp"
#include "tests/core/test_pallets.hpp"

using namespace pb;

namespace {

constexpr double g = kGravity;

Item carton(Vec3 dims, double kg) {
  Item item;
  item.sku = "test";
  item.weight_kg = kg;
  item.dims_m = dims;
  item.position = {0.0, 0.0, 0.15};
  return item;
}

// One load on an unwrapped EUR pallet, built, settled and bounded.
struct Settled {
  std::unique_ptr<Scene> scene;  // the Simulator keeps a pointer: never moves
  std::optional<Simulator> sim;
  RestState rest;
  QuasiStaticBounds bounds;
};

std::unique_ptr<Settled> settle(const PalletConfig& config, const test::ConstantMu& mu,
                                const SceneOptions& options = {}) {
  auto scene = build_scene(config, options, test::constant_friction(mu));
  if (!scene) qFatal("scene: %s", to_string(scene.diagnostics[0]).c_str());
  auto out = std::make_unique<Settled>();
  out->scene = std::make_unique<Scene>(std::move(*scene.value));
  auto sim = Simulator::create(*out->scene);
  if (!sim) qFatal("simulator: %s", to_string(sim.diagnostics[0]).c_str());
  out->sim.emplace(std::move(*sim.value));
  auto rest = out->sim->settle();
  if (!rest) qFatal("settle: %s", to_string(rest.diagnostics[0]).c_str());
  out->rest = std::move(*rest.value);
  out->bounds = quasi_static_bounds(out->scene->config, out->scene->friction);
  return out;
}

std::unique_ptr<Settled> settle(const Item& item, const test::ConstantMu& mu,
                                const SceneOptions& options = {}) {
  return settle(test::pallet({item}), mu, options);
}

// The same load with a belt drive Euler cannot integrate (kv dt / M = 4): every probe of it is
// unstable. Not settled: probes start from the stable scene's rest state.
std::unique_ptr<Settled> unstable_belt(const Settled& stable, const test::ConstantMu& mu) {
  SceneOptions options;
  options.belt_kv_ratio = 4.0;
  auto scene = build_scene(stable.scene->config, options, test::constant_friction(mu));
  if (!scene) return nullptr;
  auto out = std::make_unique<Settled>();
  out->scene = std::make_unique<Scene>(std::move(*scene.value));
  auto sim = Simulator::create(*out->scene);
  if (!sim) return nullptr;
  out->sim.emplace(std::move(*sim.value));
  return out;
}

// How far a load slides on its support in a probe that accelerates the support at `a` for `t`
// seconds and then holds its speed, with Coulomb friction mu g: it lags at (a - mu g) during the
// ramp, then catches up decelerating at mu g. Zero below mu g.
double slide(double a, double t, double mu_g) {
  if (a <= mu_g) return 0.0;
  const double lag_speed = (a - mu_g) * t;
  return 0.5 * (a - mu_g) * t * t + lag_speed * lag_speed / (2.0 * mu_g);
}

// The smallest `a` for which slide(a, ramp(a)) exceeds `distance` (bisection to 1e-9).
// Probes end early once the load rides with the belt; hold_s is their cap after the motion.
const double kHold = SearchConfig{}.hold_s;

template <class Ramp>
double slide_threshold(double mu_g, double distance, Ramp ramp) {
  double lo = mu_g, hi = 100.0;
  while (hi - lo > 1e-9) {
    const double mid = 0.5 * (lo + hi);
    (slide(mid, ramp(mid), mu_g) > distance ? hi : lo) = mid;
  }
  return hi;
}

// Two loads whose start-up limit lies inside the range and whose failure is monotone: a stack of
// two cartons that slides and a tall carton that tips.
std::vector<std::pair<PalletConfig, test::ConstantMu>> slider_and_tipper() {
  return {
      {test::pallet({test::carton(0, 0, 0.15), test::carton(0, 0, 0.35)}), {1.0, 0.3, 0.4}},
      {test::pallet({test::carton(0, 0, 0.15, {0.2, 0.2, 0.6})}), {1.0, 0.6, 0.6}},
  };
}

// The probes of `env` are `serial`'s, bit for bit, in the same order (a QCOMPARE failure ends the
// calling test: check QTest::currentTestFailed()).
void compare_probes(const Envelope& env, const Envelope& serial) {
  QCOMPARE(env.probes.size(), serial.probes.size());
  for (std::size_t i = 0; i < env.probes.size(); ++i) {
    const Probe &a = serial.probes[i], &b = env.probes[i];
    QCOMPARE(b.axis, a.axis);
    QCOMPARE(b.value, a.value);
    QCOMPARE(b.outcome, a.outcome);
    QCOMPARE(b.mode, a.mode);
    QCOMPARE(b.failure_time_s, a.failure_time_s);
    QCOMPARE(b.steps, a.steps);
    QCOMPARE(b.peak_ratio, a.peak_ratio);
    QCOMPARE(b.turn, a.turn);
  }
}

QByteArray describe(const AxisLimit& a) {
  return QByteArray::fromStdString("limit " + std::to_string(a.limit) + ", " +
                                   std::to_string(a.probes) + " probes, mode " +
                                   std::string(to_string(a.mode)));
}

}  // namespace

class EnvelopeTest : public QObject {
  Q_OBJECT

  const SearchConfig search_{};
  const LineDescription line_{};
  const double item_slide_m_ = DetectorThresholds{}.item_slide_m;

 private slots:
  void axisNames() {
    QCOMPARE(to_string(Axis::accel), std::string_view("accel"));
    QCOMPARE(to_string(Axis::decel), std::string_view("decel"));
    QCOMPARE(to_string(Axis::lateral), std::string_view("lateral"));
    QCOMPARE(to_string(Axis::speed), std::string_view("speed"));
  }

  // Ramp at a to speed_max (2 m/s), but for max_ramp_s (2 s) at most; then hold_s at most.
  void accelProbeRampsThenHolds() {
    const ConveyorProfile fast = accel_probe_profile(3.0, search_);
    QCOMPARE(fast.shape, ProfileShape::accel_hold);
    QCOMPARE(fast.accel_mps2, 3.0);
    QCOMPARE(fast.target_speed_mps, 2.0);
    QCOMPARE(fast.duration_s, 2.0 / 3.0 + kHold);
    QCOMPARE(fast.initial_speed_mps(), 0.0);
    QCOMPARE(fast.velocity_at(0.5), 1.5);
    QCOMPARE(fast.velocity_at(1.0), 2.0);
    const ConveyorProfile slow = accel_probe_profile(0.4, search_);
    QCOMPARE(slow.target_speed_mps, 0.8);  // capped by the 2 s ramp
    QCOMPARE(slow.duration_s, 2.0 + kHold);
    QVERIFY(validate_profile(fast).empty());
    QVERIFY(validate_profile(slow).empty());
    QVERIFY(validate_profile(accel_probe_profile(search_.accel_min_mps2, search_)).empty());
  }

  // At speed from t = 0; 50 ms later the belt stops at d; then hold_s.
  void decelProbeStopsFromSpeed() {
    const ConveyorProfile p = decel_probe_profile(4.0, 2.0, search_);
    QCOMPARE(p.shape, ProfileShape::estop);
    QCOMPARE(p.decel_mps2, 4.0);
    QCOMPARE(p.target_speed_mps, 2.0);
    QCOMPARE(p.initial_speed_mps(), 2.0);
    QCOMPARE(p.decel_start_s, 0.05);
    QCOMPARE(p.duration_s, 0.05 + 0.5 + kHold);
    QCOMPARE(p.velocity_at(0.05), 2.0);
    QCOMPARE(p.velocity_at(0.55), 0.0);
    QVERIFY(validate_profile(p).empty());
    QVERIFY(validate_profile(decel_probe_profile(search_.decel_min_mps2, 2.0, search_)).empty());
  }

  void stopProbeIsTheLineEstop() {
    LineDescription line;
    line.estop_decel_mps2 = 3.5;
    QCOMPARE(stop_probe_profile(1.2, line, search_), decel_probe_profile(3.5, 1.2, search_));
  }

  // The curve is taken at the speed that gives the lateral acceleration, v = sqrt(a r); an arc
  // that would take longer than max_ramp_s is cut to that time.
  void lateralProbeTakesTheCurve() {
    const ConveyorProfile tight = lateral_probe_profile(0.5, line_, search_);
    QCOMPARE(tight.shape, ProfileShape::curve);
    QCOMPARE(tight.curve_radius_m, 3.0);
    QVERIFY(std::abs(tight.lateral_accel_mps2() - 0.5 * g) < 1e-12);
    const double arc = 3.0 * std::numbers::pi / 2.0 / tight.target_speed_mps;  // 1.23 s
    QVERIFY(arc < search_.max_ramp_s);
    QCOMPARE(tight.curve_angle_deg, 90.0);
    QCOMPARE(tight.curve_start_s, 0.05);
    QVERIFY(std::abs(tight.duration_s - (0.05 + arc + kHold)) < 1e-12);
    QCOMPARE(tight.initial_speed_mps(), tight.target_speed_mps);

    const ConveyorProfile gentle = lateral_probe_profile(0.1, line_, search_);
    QVERIFY(std::abs(gentle.lateral_accel_mps2() - 0.1 * g) < 1e-12);
    const double full_arc = 3.0 * std::numbers::pi / 2.0 / gentle.target_speed_mps;  // 2.75 s
    QVERIFY(full_arc > search_.max_ramp_s);
    QVERIFY(std::abs(gentle.curve_angle_deg - 90.0 * 2.0 / full_arc) < 1e-9);
    QVERIFY(std::abs(gentle.duration_s - (0.05 + 2.0 + kHold)) < 1e-12);
    // The belt moves sideways for exactly max_ramp_s.
    QVERIFY(std::abs(gentle.lateral_velocity_at(gentle.duration_s) - 0.1 * g * 2.0) < 1e-9);
    for (const double lat : {search_.lateral_min_g, 0.1, 0.5}) {
      QVERIFY(validate_profile(lateral_probe_profile(lat, line_, search_)).empty());
    }
  }

  // A low 10 kg carton (mu 0.3 on the deck, tips only beyond 1.5 g) on a pallet that cannot slip
  // (mu 1 on the belt). Each limit must sit within one precision step below the closed-form
  // threshold of its probe (Coulomb sliding, finite detection distance, finite ramp).
  void singleCartonLimitsMatchClosedForm() {
    auto s = settle(carton({0.4, 0.3, 0.2}, 10.0), {1.0, 0.3, 0.4});
    const double mu_g = 0.3 * g;
    QVERIFY(std::abs(s->bounds.weakest_along().accel_mps2 - mu_g) < 1e-12);
    auto env = search_envelope(*s->sim, s->rest, s->bounds, line_, search_);
    QVERIFY2(env.ok(), env.ok() ? "" : to_string(env.diagnostics[0]).c_str());

    // Start-up and stop: the load changes speed by 2 m/s at a, for 2 / a seconds (3.18 m/s^2).
    const double ramp_threshold =
        slide_threshold(mu_g, item_slide_m_, [](double a) { return 2.0 / a; });
    QVERIFY(ramp_threshold > 3.1 && ramp_threshold < 3.25);
    for (const AxisLimit* axis : {&env->accel, &env->decel}) {
      QVERIFY2(axis->limit <= ramp_threshold + 0.01 && axis->limit >= ramp_threshold - 0.1,
               describe(*axis));
      QCOMPARE(axis->mode, FailureMode::top_item_slide);
      QCOMPARE(axis->slide, SlideKind::item_slid);  // it slides flat
      QVERIFY(!axis->at_ceiling && !axis->at_floor);
      // Seeded just above mu g, the walk up in steps of 0.1 brackets the threshold one step wide
      // in 3 probes (seed, +0.1, +0.1 more) and one bisection halves that bracket: 4 (5 while
      // the walk doubled its step at once).
      QVERIFY2(axis->probes <= 4, describe(*axis));
    }
    // Curve: lateral mu g, for the arc's time at v = sqrt(a r) (0.304 g).
    const double curve_threshold =
        slide_threshold(
            mu_g, item_slide_m_,
            [](double a) { return 3.0 * std::numbers::pi / 2.0 / std::sqrt(a * 3.0); }) /
        g;
    QVERIFY2(env->lateral.limit <= curve_threshold + 0.002 &&
                 env->lateral.limit >= curve_threshold - 0.01,
             describe(env->lateral));
    QCOMPARE(env->lateral.mode, FailureMode::top_item_slide);
    QVERIFY2(env->lateral.probes <= 4, describe(env->lateral));
    // A 2 m/s^2 e-stop is below mu g: the carton never slides, from any speed; the stop search
    // found a harder stop from speed_max safe, so no probe is needed.
    QVERIFY(env->speed.at_ceiling && env->speed.derived);
    QCOMPARE(env->speed.limit, search_.speed_max_mps);
    QCOMPARE(env->speed.mode, FailureMode::no_failure);
    QCOMPARE(env->speed.probes, 0);

    const SafetyResult& r = env->result;
    QCOMPARE(r.verdict, Verdict::ok);
    QCOMPARE(r.max_accel_mps2, env->accel.limit);
    QCOMPARE(r.max_decel_mps2, env->decel.limit);
    QCOMPARE(r.max_lateral_g, env->lateral.limit);
    QCOMPARE(r.accel_mode, FailureMode::top_item_slide);
    // The curve at 0.3 g allows sqrt(0.3 g 3) = 2.97 m/s > 2: the speed is the ceiling.
    QCOMPARE(r.max_speed_mps, 2.0);
    QCOMPARE(r.speed_governed_by, SpeedGovernor::ceiling);
    QCOMPARE(r.line_estop_decel_mps2, 2.0);
    QCOMPARE(r.line_curve_radius_m, 3.0);
    // The tightest axis relative to its range is the curve: (0.30 - 0.01) / 0.49 = 59 %.
    QCOMPARE(r.dominant_failure_mode, FailureMode::top_item_slide);
    QVERIFY(std::abs(r.margin_pct - 100.0 * (env->lateral.limit - 0.01) / 0.49) < 1e-9);
    QCOMPARE(r.sims_run, static_cast<int>(env->probes.size()));
    QCOMPARE(r.sims_run,
             env->accel.probes + env->decel.probes + env->lateral.probes + env->speed.probes);
    QCOMPARE(env->rest.state.qpos, s->rest.state.qpos);
    // Probes are recorded in search order, each with the failure it saw.
    QCOMPARE(env->probes.front().axis, Axis::accel);
    QCOMPARE(env->probes.back().axis, Axis::lateral);
    for (const Probe& p : env->probes) {
      QCOMPARE(p.outcome == Outcome::failed, p.mode != FailureMode::no_failure);
      if (p.axis == Axis::accel) {
        QCOMPARE(p.outcome == Outcome::failed, p.value > env->accel.limit);
      }
    }
  }

  // A 0.2 x 0.2 x 1 m carton that cannot slip (mu 0.8 on the deck) tips at g (b/2)/h =
  // 1.962 m/s^2. The detectors' contract calls that top_item_slide (its centre moves 5 cm, at
  // 5.6 deg); the limit says it tipped, and so does the reason a supervisor reads.
  void aTallCartonTipsAndIsSaidToTip() {
    auto s = settle(carton({0.2, 0.2, 1.0}, 20.0), {1.0, 0.8, 0.4});
    auto env = search_envelope(*s->sim, s->rest, s->bounds, line_, search_);
    QVERIFY2(env.ok(), env.ok() ? "" : to_string(env.diagnostics[0]).c_str());
    const double onset = g * 0.1 / 0.5;
    QVERIFY2(env->accel.limit <= onset + 0.01 && env->accel.limit >= onset - 0.15,
             describe(env->accel));
    QCOMPARE(env->accel.mode, FailureMode::top_item_slide);
    QCOMPARE(env->accel.slide, SlideKind::item_tipped);
    QCOMPARE(env->lateral.slide, SlideKind::item_tipped);
    for (const Probe& p : env->probes) {
      if (p.outcome == Outcome::failed) QCOMPARE(p.slide, SlideKind::item_tipped);
    }
    // The result says it for a machine too (its mode stays the contract's top_item_slide).
    QCOMPARE(env->result.accel_mode, FailureMode::top_item_slide);
    QVERIFY(env->result.accel_item_tipped);
    QCOMPARE(env->result.decel_item_tipped, env->decel.slide == SlideKind::item_tipped);
    QVERIFY(env->result.lateral_item_tipped);
    QCOMPARE(env->result.dominant_slide, SlideKind::item_tipped);
    QVERIFY(!env->result.accel_load_as_one && !env->result.lateral_load_as_one);
    const std::string& why = env->result.reason;
    QVERIFY2(why.find("(above it, an item tips over;") != std::string::npos, why.c_str());
    // Each axis says what fails above it; only the closed-form level says it was not simulated.
    // Limits are floored, never rounded up (1.962 m/s^2 reads 1.96, 0.195 g reads 0.195).
    QVERIFY2(why.find("Start-up at up to 1.96 m/s^2") != std::string::npos, why.c_str());
    QVERIFY2(
        why.find("m/s; above it, an item tips over); curves up to 0.195 g (on 3.0 m curves;") !=
            std::string::npos,
        why.c_str());
    QVERIFY2(why.find("m curves; above it, an item tips over). Top speed") != std::string::npos,
             why.c_str());
    QVERIFY(why.find("predicted") == std::string::npos);
    const Envelope predicted = closed_form_envelope(s->bounds, line_, search_, {});
    QVERIFY2(
        predicted.result.reason.find("predicted, not simulated, for ramping") != std::string::npos,
        predicted.result.reason.c_str());
  }

  // The reference system's plain bisection over the whole range (no closed-form seed) finds the
  // same limits within one precision step, with more probes.
  void plainBisectionAgreesWithSeededSearch() {
    auto s = settle(carton({0.4, 0.3, 0.2}, 10.0), {1.0, 0.3, 0.4});
    auto seeded = search_envelope(*s->sim, s->rest, s->bounds, line_, search_);
    SearchConfig plain = search_;
    plain.seed_with_closed_form = false;
    plain.confirm_from_peak = 2.0;  // the bisection's probes alone: no confirmation
    auto bisected = search_envelope(*s->sim, s->rest, s->bounds, line_, plain);
    QVERIFY(seeded.ok() && bisected.ok());
    QVERIFY2(std::abs(seeded->accel.limit - bisected->accel.limit) <= 0.1 + 1e-9,
             describe(bisected->accel));
    QVERIFY2(std::abs(seeded->decel.limit - bisected->decel.limit) <= 0.1 + 1e-9,
             describe(bisected->decel));
    QVERIFY2(std::abs(seeded->lateral.limit - bisected->lateral.limit) <= 0.01 + 1e-9,
             describe(bisected->lateral));
    QCOMPARE(bisected->accel.mode, FailureMode::top_item_slide);
    QCOMPARE(bisected->lateral.mode, FailureMode::top_item_slide);
    // The e-stop axis is safe everywhere: bisection never fails, so the ceiling is tried.
    QVERIFY(bisected->speed.at_ceiling);
    // Bisection of 4.9 m/s^2 to 0.1 takes 6 probes; the seeded search at most 5.
    QCOMPARE(bisected->accel.probes, 6);
    QVERIFY(bisected->result.sims_run > seeded->result.sims_run);
  }

  // A slipping pallet carries its load: a carton (mu 0.29 on the deck, kinetic 0.2175) on a
  // pallet whose belt holds it to 0.30 g (kinetic 0.225) slides off at start-ups between its own
  // onset (2.85 m/s^2) and the pallet's (2.94), and holds at 3.1-3.4 where the pallet slips and
  // drags it at 0.225 g; the pallet's own 30 cm slide fails it above. Plain bisection lands in the
  // safe band above the pallet's onset (3.16 holds); the check below that onset fails, and the
  // search goes on below it, to the limit the seeded search finds from the carton's onset.
  void aLoadThatFailsBelowItsPalletsOnsetIsAnsweredThere() {
    auto s = settle(carton({0.4, 0.3, 0.2}, 10.0), {0.30, 0.29, 0.4, 0.75});
    SearchConfig plain = search_;
    plain.seed_with_closed_form = false;
    plain.confirm_from_peak = 2.0;  // the bisection's probes alone: no confirmation
    auto bisected = search_envelope(*s->sim, s->rest, s->bounds, line_, plain);
    auto seeded = search_envelope(*s->sim, s->rest, s->bounds, line_, search_);
    QVERIFY(bisected.ok() && seeded.ok());
    const double onset = 0.30 * g, check = kConeSaturated * onset;
    bool safe_above = false, check_failed = false;
    for (const Probe& p : bisected->probes) {
      if (p.axis != Axis::accel) continue;
      safe_above = safe_above || (p.value > onset && p.outcome == Outcome::safe);
      check_failed = check_failed || (p.value == check && p.outcome == Outcome::failed);
    }
    QVERIFY(safe_above);  // the band the search would otherwise have answered from
    QVERIFY(check_failed);
    QVERIFY2(bisected->accel.limit < 0.29 * g, describe(bisected->accel));
    QCOMPARE(bisected->accel.mode, FailureMode::top_item_slide);
    QVERIFY2(std::abs(bisected->accel.limit - seeded->accel.limit) <= 0.1 + 1e-9,
             describe(seeded->accel));
  }

  // Carton mu 0.005: it slides 5 cm even at the gentlest start-up (0.1 m/s^2 for 2 s).
  void slipperyCartonIsRejected() {
    auto s = settle(carton({0.4, 0.3, 0.2}, 10.0), {1.0, 0.005, 0.4});
    auto env = search_envelope(*s->sim, s->rest, s->bounds, line_, search_);
    QVERIFY(env.ok());
    QVERIFY(env->accel.at_floor);
    QCOMPARE(env->accel.limit, 0.0);
    QCOMPARE(env->accel.mode, FailureMode::top_item_slide);
    // Seeded at 0.049 + 0.1 (an item can slide: the walk starts above the onset): fails, and the
    // floor is the only probe left. The closed form predicts the 5 cm slide below the floor.
    QVERIFY(env->accel.closed_form < search_.accel_min_mps2 + 1e-6);
    QCOMPARE(env->accel.probes, 2);
    const SafetyResult& r = env->result;
    QCOMPARE(r.verdict, Verdict::reject);
    QCOMPARE(r.dominant_failure_mode, FailureMode::top_item_slide);
    // Every limit is 0: no axis holds for a pallet that cannot start.
    QCOMPARE(r.max_speed_mps, 0.0);
    QCOMPARE(r.max_accel_mps2, 0.0);
    QCOMPARE(r.max_decel_mps2, 0.0);
    QCOMPARE(r.max_lateral_g, 0.0);
    QCOMPARE(r.margin_pct, 0.0);
    QCOMPARE(r.speed_governed_by, SpeedGovernor::reject);
    QVERIFY2(r.reason.starts_with("Reject: unsafe at any motion; it fails at the gentlest start-up "
                                  "tried (an item slides off)."),
             r.reason.c_str());
    // The closed-form level says its reject was predicted, with the same zeros.
    const SafetyResult predicted = closed_form_envelope(s->bounds, line_, search_, {}).result;
    QCOMPARE(predicted.verdict, Verdict::reject);
    QCOMPARE(predicted.max_lateral_g, 0.0);
    QVERIFY2(predicted.reason.starts_with("Reject: unsafe at any motion; it is predicted (closed "
                                          "form, not simulated) to fail at the gentlest"),
             predicted.reason.c_str());
    // Stopped from 0.1 m/s by the line's 2 m/s^2 e-stop, the carton slides
    // v^2 / 2 (1 / (mu g) - 1 / d) = 9.9 cm: the e-stop axis fails at its floor too.
    // Regression: a stop probe must follow the carton until it stops sliding (it slid 4.5 cm
    // by the end of a fixed 0.5 s hold, and 9.9 cm in all).
    QVERIFY2(env->speed.at_floor, describe(env->speed));
  }

  // The closed form of a probe: a load that moves as one body (wrapped: only the pallet can slip
  // or the whole load tip) on a belt of mu 0.2 slides 0.30 m after a ramp to 2 m/s at a when
  // v^2 / 2 (1 / (mu g) - 1 / a) = 0.30 (the e-stop from 2 m/s likewise): a = 2.780 m/s^2. Its
  // search starts there; MuJoCo's slip lands within one step of it, in at most three probes.
  void oneBodyLoadIsSearchedFromItsPrediction() {
    auto s = settle(test::pallet({test::carton(-0.25, 0, 0.15), test::carton(0.25, 0, 0.15)},
                                 WrapType::stretch),
                    {0.2, 0.5, 0.5});
    const double expected = 1.0 / (1.0 / (0.2 * kGravity) - 2.0 * 0.30 / (2.0 * 2.0));
    const AxisPredictions p = predict_envelope(s->bounds, line_, search_, {});
    QVERIFY2(std::abs(p.accel.value - expected) < 1e-6, std::to_string(p.accel.value).c_str());
    QVERIFY2(std::abs(p.decel.value - expected) < 1e-6, std::to_string(p.decel.value).c_str());
    QCOMPARE(p.accel.mode, FailureMode::pallet_slip);
    auto env = search_envelope(*s->sim, s->rest, s->bounds, line_, search_);
    QVERIFY(env.ok());
    for (const AxisLimit* a : {&env->accel, &env->decel}) {
      QCOMPARE(a->mode, FailureMode::pallet_slip);
      QCOMPARE(a->closed_form, p.accel.value);
      QVERIFY2(std::abs(a->limit - expected) <= search_.accel_precision_mps2, describe(*a));
      QVERIFY2(a->probes <= 3, describe(*a));
    }
    // The reason says what the slip above the limit is: past its allowance, not its onset (mu g
    // is 1.96 m/s^2 here, the limit 2.78), in the detectors' own allowance.
    const std::string& why = env->result.reason;
    QVERIFY2(
        why.find("(above it, the pallet slides more than 0.30 m on the belt;") != std::string::npos,
        why.c_str());
    DetectorThresholds strict;
    strict.pallet_slip_m = 0.05;
    const Envelope predicted = closed_form_envelope(s->bounds, line_, search_, strict);
    QCOMPARE(predicted.accel.mode, FailureMode::pallet_slip);
    QVERIFY2(predicted.result.reason.find("the pallet slides more than 0.05 m on the belt") !=
                 std::string::npos,
             predicted.result.reason.c_str());
  }

  // A tip fails at its onset; a slip that cannot slide its allowance inside the range, nowhere.
  void predictionOfTipsAndOfSlipsThatHold() {
    const std::vector<QuasiStaticLimit> tip{
        {2.5, FailureMode::tip_over, Mechanism::load_tip, "tips", -1},
        {1.0, FailureMode::pallet_slip, Mechanism::pallet_slip, "slips", -1}};
    auto ramp = [](double a) { return 2.0 / a; };
    const AxisPrediction t = predict_axis(tip, 1.0, 0.1, 5.0, ramp, {});
    // mu g = 1: the pallet slides 0.30 m well below 2.5, so the slip governs.
    QCOMPARE(t.mode, FailureMode::pallet_slip);
    QVERIFY(t.value < 2.5);
    const std::vector<QuasiStaticLimit> held{
        {2.5, FailureMode::tip_over, Mechanism::load_tip, "tips", -1},
        {4.0, FailureMode::pallet_slip, Mechanism::pallet_slip, "slips", -1}};
    const AxisPrediction h = predict_axis(held, 1.0, 0.1, 5.0, ramp, {});
    QCOMPARE(h.mode, FailureMode::tip_over);
    QCOMPARE(h.value, 2.5);
    const AxisPrediction none = predict_axis({held[1]}, 1.0, 0.1, 5.0, ramp, {});
    QCOMPARE(none.mode, FailureMode::no_failure);  // 4 -> 5 m/s^2 for 0.4 s slides < 0.30 m
    QCOMPARE(none.value, 5.0);
  }

  // A low 150 kg slab with mu 1 everywhere survives the top of every range: one probe per axis,
  // each at its ceiling (every seed is above the range and is clamped to its top), and none for
  // the stop (the slab is its own mirror image: the start-up's full ramp answers it) or the e-stop
  // speed (the stop search found 5 m/s^2 from speed_max safe, so the line's 2 m/s^2 is).
  void lowHeavySlabIsAtEveryCeiling() {
    auto s = settle(carton({1.1, 0.7, 0.1}, 150.0), {1.0, 1.0, 1.0});
    auto env = search_envelope(*s->sim, s->rest, s->bounds, line_, search_);
    QVERIFY2(env.ok(), env.ok() ? "" : to_string(env.diagnostics[0]).c_str());
    for (const AxisLimit* axis : {&env->accel, &env->decel, &env->lateral, &env->speed}) {
      QVERIFY2(axis->at_ceiling, describe(*axis));
      QCOMPARE(axis->mode, FailureMode::no_failure);
      QCOMPARE(axis->probes, axis == &env->decel || axis == &env->speed ? 0 : 1);
    }
    QVERIFY(env->decel.derived && env->speed.derived);
    QCOMPARE(env->probes.size(), std::size_t{2});
    const SafetyResult& r = env->result;
    QCOMPARE(r.verdict, Verdict::ok);
    QCOMPARE(r.dominant_failure_mode, FailureMode::no_failure);
    QCOMPARE(r.margin_pct, 100.0);
    QCOMPARE(r.max_accel_mps2, 5.0);
    QCOMPARE(r.max_decel_mps2, 5.0);
    QCOMPARE(r.max_lateral_g, 0.5);
    QCOMPARE(r.max_speed_mps, 2.0);
    QCOMPARE(r.speed_governed_by, SpeedGovernor::ceiling);
  }

  // A probe MuJoCo breaks (here: a belt drive that Euler cannot integrate, kv dt / M = 4) gives
  // no verdict at all.
  void unstableProbeGivesNoVerdict() {
    auto s = settle(carton({0.4, 0.3, 0.2}, 10.0), {1.0, 0.3, 0.4});
    auto broken = unstable_belt(*s, {1.0, 0.3, 0.4});
    QVERIFY(broken);
    Simulator& sim = *broken->sim;
    auto env = search_envelope(sim, s->rest, s->bounds, line_, search_);
    QVERIFY(!env.ok());
    QCOMPARE(env.diagnostics.size(), std::size_t{1});
    QVERIFY2(env.diagnostics[0].message.starts_with(
                 "the simulation became numerically unstable, so no verdict is given: accel "
                 "probe at "),
             env.diagnostics[0].message.c_str());
  }
  // k-section (parallel_probes k > 1: k probes of the bisection grid per round, one batched call)
  // finds bitwise the same limits and modes as serial bisection (k = 1) when failure is monotone:
  // a stack of two cartons that slides and a tall carton that tips.
  void kSectionMatchesBisection() {
    for (const auto& [config, mu] : slider_and_tipper()) {
      auto s = settle(config, mu);
      auto serial = search_envelope(*s->sim, s->rest, s->bounds, line_, search_);
      QVERIFY2(serial.ok(), serial.ok() ? "" : to_string(serial.diagnostics[0]).c_str());
      // The start-up limit is bracketed inside its range, so rounds of k-section do run.
      QVERIFY2(!serial->accel.at_ceiling && !serial->accel.at_floor, describe(serial->accel));
      for (const int k : {2, 3}) {
        SearchConfig parallel = search_;
        parallel.parallel_probes = k;
        auto env = search_envelope(*s->sim, s->rest, s->bounds, line_, parallel);
        QVERIFY2(env.ok(), env.ok() ? "" : to_string(env.diagnostics[0]).c_str());
        const std::pair<const AxisLimit*, const AxisLimit*> axes[] = {
            {&serial->accel, &env->accel},
            {&serial->decel, &env->decel},
            {&serial->lateral, &env->lateral},
            {&serial->speed, &env->speed}};
        for (const auto& [a, b] : axes) {
          QVERIFY2(a->limit == b->limit, describe(*a) + " vs k-section " + describe(*b));
          QCOMPARE(b->mode, a->mode);
          QCOMPARE(b->at_ceiling, a->at_ceiling);
          QCOMPARE(b->at_floor, a->at_floor);
        }
        QCOMPARE(env->result.verdict, serial->result.verdict);
        QCOMPARE(env->result.max_speed_mps, serial->result.max_speed_mps);
        QCOMPARE(env->result.dominant_failure_mode, serial->result.dominant_failure_mode);
        // Every probe run is kept and counted.
        QCOMPARE(env->result.sims_run, static_cast<int>(env->probes.size()));
        QCOMPARE(env->result.sims_run,
                 env->accel.probes + env->decel.probes + env->lateral.probes + env->speed.probes);
        // Monotone: every probe above an axis limit failed, every one at or below it was safe.
        for (const Probe& p : env->probes) {
          const AxisLimit& limit = p.axis == Axis::accel     ? env->accel
                                   : p.axis == Axis::decel   ? env->decel
                                   : p.axis == Axis::lateral ? env->lateral
                                                             : env->speed;
          QCOMPARE(p.outcome == Outcome::failed, limit.at_floor || p.value > limit.limit);
        }
      }
    }
  }

  // The plain (unseeded) search is k-sectioned from its first probe: same limits as bisection.
  void kSectionOfPlainSearchMatchesBisection() {
    auto s = settle(carton({0.4, 0.3, 0.2}, 10.0), {1.0, 0.3, 0.4});
    SearchConfig plain = search_;
    plain.seed_with_closed_form = false;
    plain.confirm_from_peak = 2.0;  // the rounds' probes alone: no confirmation
    auto serial = search_envelope(*s->sim, s->rest, s->bounds, line_, plain);
    plain.parallel_probes = 3;
    auto env = search_envelope(*s->sim, s->rest, s->bounds, line_, plain);
    QVERIFY(serial.ok() && env.ok());
    QVERIFY2(serial->accel.limit == env->accel.limit, describe(env->accel));
    QVERIFY2(serial->lateral.limit == env->lateral.limit, describe(env->lateral));
    QCOMPARE(env->accel.mode, serial->accel.mode);
    QVERIFY(env->speed.at_ceiling);
    // 4.9 m/s^2 to 0.1: the bisection grid has 65 points; 3 probes a round take 3 rounds (64 ->
    // 16 -> 4 -> 1 intervals): 9 probes for bisection's 6, in half the rounds.
    QCOMPARE(env->accel.probes, 9);
  }

  // An unstable probe inside a batched round still makes the envelope fail with its reason; a
  // negative k is refused, naming the field.
  void kSectionUnstableProbeAndBadK() {
    auto s = settle(carton({0.4, 0.3, 0.2}, 10.0), {1.0, 0.3, 0.4});
    auto broken = unstable_belt(*s, {1.0, 0.3, 0.4});
    QVERIFY(broken);
    Simulator& sim = *broken->sim;
    SearchConfig plain = search_;
    plain.seed_with_closed_form = false;  // the first probes are a batched round
    plain.parallel_probes = 2;
    auto env = search_envelope(sim, s->rest, s->bounds, line_, plain);
    QVERIFY(!env.ok());
    QVERIFY2(env.diagnostics[0].message.starts_with(
                 "the simulation became numerically unstable, so no verdict is given: accel "
                 "probe at "),
             env.diagnostics[0].message.c_str());

    SearchConfig bad = search_;
    bad.parallel_probes = -1;
    auto refused = search_envelope(*s->sim, s->rest, s->bounds, line_, bad);
    QVERIFY(!refused.ok());
    QCOMPARE(refused.diagnostics[0].pointer, std::string("/search/parallel_probes"));
  }

  // The axes searched side by side (axis_threads), with or without probes run ahead on spare
  // cores (SearchConfig::speculate), run bitwise the probes of one axis after another, reported in
  // axis order: a sliding two-carton stack and a tall carton that tips, and the stack off the
  // centre line, whose curve is searched in both turns (the right turn's first probe may run
  // beside the left search's last one: AxisTask::follow_up).
  void axisThreadsRunTheSameProbes() {
    int ran_ahead = 0, ran_ahead_for_nothing = 0;
    auto loads = slider_and_tipper();
    loads.push_back(
        {test::pallet({test::carton(0, 0.2, 0.15), test::carton(0, 0.2, 0.35)}), {1.0, 0.3, 0.4}});
    for (const auto& [config, mu] : loads) {
      auto s = settle(config, mu);
      SearchConfig one = search_;
      one.axis_threads = 1;
      auto serial = search_envelope(*s->sim, s->rest, s->bounds, line_, one);
      QVERIFY(serial.ok());
      QCOMPARE(serial->speculative, 0);
      for (const auto& [threads, speculate] :
           {std::pair{2, true}, std::pair{4, true}, std::pair{4, false}}) {
        SearchConfig side_by_side = search_;
        side_by_side.axis_threads = threads;
        side_by_side.speculate = speculate;
        side_by_side.speculate_after_ms = 0.0;  // these probes are short: run ahead anyway
        auto env = search_envelope(*s->sim, s->rest, s->bounds, line_, side_by_side);
        QVERIFY(env.ok());
        if (!speculate) QCOMPARE(env->speculative, 0);
        ran_ahead += env->ran_ahead;
        ran_ahead_for_nothing += env->speculative;
        compare_probes(*env, *serial);
        if (QTest::currentTestFailed()) return;
        QCOMPARE(env->result.max_accel_mps2, serial->result.max_accel_mps2);
        QCOMPARE(env->result.max_decel_mps2, serial->result.max_decel_mps2);
        QCOMPARE(env->result.max_lateral_g, serial->result.max_lateral_g);
        QCOMPARE(env->result.max_speed_mps, serial->result.max_speed_mps);
        QCOMPARE(env->result.dominant_failure_mode, serial->result.dominant_failure_mode);
      }
    }
    qInfo("probes run ahead on spare cores: %d, not needed: %d", ran_ahead, ran_ahead_for_nothing);
    SearchConfig bad = search_;
    bad.axis_threads = -1;
    auto s = settle(carton({0.4, 0.3, 0.2}, 10.0), {1.0, 0.3, 0.4});
    auto refused = search_envelope(*s->sim, s->rest, s->bounds, line_, bad);
    QVERIFY(!refused.ok());
    QCOMPARE(refused.diagnostics[0].pointer, std::string("/search/axis_threads"));
  }

  // Galilean invariance: in the belt's frame a full start-up ramp and a stop from the same speed
  // are the same pulse, mirrored. A load that is its own mirror image takes its stop limit from the
  // start-up search (no stop probes); searched on its own, the stop lands within one step of it
  // (a two-carton stack sliding on each other at mu g = 2.94 m/s^2: ramps of 2 / a s). A load off
  // the mirror plane is searched on every axis.
  // Two cartons that grip each other (mu 0.4) better than the deck (0.3), on a pallet that cannot
  // slip: above 2.94 m/s^2 they slide off the deck together. The mode stays the contract's
  // top_item_slide; the limit and the reason say the load slid on its pallet as one.
  void aStackSlidingOffTheDeckTogetherIsTheLoadSliding() {
    auto s =
        settle(test::pallet({test::carton(0, 0, 0.15), test::carton(0, 0, 0.35)}), {1.0, 0.3, 0.4});
    auto env = search_envelope(*s->sim, s->rest, s->bounds, line_, search_);
    QVERIFY(env.ok());
    QCOMPARE(env->accel.mode, FailureMode::top_item_slide);
    QCOMPARE(env->accel.slide, SlideKind::load_as_one);
    QVERIFY(!env->result.accel_item_tipped);
    // The result says so per axis, and for the governing mode.
    QVERIFY(env->result.accel_load_as_one);
    QCOMPARE(env->result.decel_load_as_one, env->decel.slide == SlideKind::load_as_one);
    QCOMPARE(env->result.dominant_failure_mode, FailureMode::top_item_slide);
    QCOMPARE(env->result.dominant_slide, SlideKind::load_as_one);
    const std::string& why = env->result.reason;
    QVERIFY2(why.find("above it, the load slides on its pallet") != std::string::npos, why.c_str());
    int as_one = 0;
    for (const Probe& p : env->probes) {
      if (p.outcome == Outcome::failed && p.mode == FailureMode::top_item_slide) {
        QCOMPARE(p.slide, SlideKind::load_as_one);
        ++as_one;
      }
    }
    QVERIFY(as_one > 0);
  }

  void mirrorImageLoadTakesItsStopFromTheStartUp() {
    auto s =
        settle(test::pallet({test::carton(0, 0, 0.15), test::carton(0, 0, 0.35)}), {1.0, 0.3, 0.4});
    auto mirrored = search_envelope(*s->sim, s->rest, s->bounds, line_, search_);
    QVERIFY(mirrored.ok());
    QVERIFY(mirrored->decel.derived);
    QCOMPARE(mirrored->decel.probes, 0);
    QCOMPARE(mirrored->decel.limit, mirrored->accel.limit);
    QCOMPARE(mirrored->decel.mode, mirrored->accel.mode);
    for (const Probe& p : mirrored->probes) QVERIFY(p.axis != Axis::decel);
    SearchConfig each = search_;
    each.derive_axes = false;
    auto separate = search_envelope(*s->sim, s->rest, s->bounds, line_, each);
    QVERIFY(separate.ok());
    QVERIFY(!separate->decel.derived && separate->decel.probes > 0);
    QCOMPARE(separate->accel.limit, mirrored->accel.limit);
    QVERIFY2(std::abs(separate->decel.limit - mirrored->decel.limit) <=
                 search_.decel_precision_mps2 + 1e-9,
             describe(separate->decel));
    QCOMPARE(separate->lateral.limit, mirrored->lateral.limit);

    auto off = settle(test::pallet({test::carton(0.2, 0, 0.15), test::carton(0.2, 0, 0.35)}),
                      {1.0, 0.3, 0.4});
    auto env = search_envelope(*off->sim, off->rest, off->bounds, line_, search_);
    QVERIFY(env.ok());
    QVERIFY(!env->decel.derived && env->decel.probes > 0);
  }

  // The axes derived from others follow on the thread that found what they derive from, while
  // the other searches go on: a mirror-image stack that slides on its deck at 0.15 g (1.47 m/s^2)
  // stops below the line's 2 m/s^2 e-stop, so its e-stop speed is searched from its stop, which is
  // its start-up's. Side by side, with the default budget and with one that holds only the model's
  // own mjData (every axis on the calling thread), the probes are bitwise the serial search's.
  void derivedAxesFollowTheSearchTheyDeriveFrom() {
    auto s = settle(test::pallet({test::carton(0, 0, 0.15), test::carton(0, 0, 0.35)}),
                    {1.0, 0.15, 0.4});
    QVERIFY(s);
    SearchConfig one = search_;
    one.axis_threads = 1;
    auto serial = search_envelope(*s->sim, s->rest, s->bounds, line_, one);
    QVERIFY2(serial.ok(), serial.ok() ? "" : serial.diagnostics[0].message.c_str());
    QVERIFY(serial->decel.derived);
    QVERIFY2(serial->decel.limit < line_.estop_decel_mps2, describe(serial->decel));
    QVERIFY(!serial->speed.derived && serial->speed.probes > 0);  // searched from the stop
    for (const double budget : {s->sim->data_bytes(), search_.axis_memory_bytes}) {
      SearchConfig side_by_side = search_;
      side_by_side.axis_memory_bytes = budget;
      auto env = search_envelope(*s->sim, s->rest, s->bounds, line_, side_by_side);
      QVERIFY(env.ok());
      compare_probes(*env, *serial);
      if (QTest::currentTestFailed()) return;
      QCOMPARE(env->decel.limit, serial->decel.limit);
      QCOMPARE(env->speed.limit, serial->speed.limit);
      QCOMPARE(env->speed.mode, serial->speed.mode);
      QCOMPARE(env->lateral.limit, serial->lateral.limit);
    }
  }

  // A load off the mirror plane whose pallet slips on its belt before any item moves, both ways
  // (belt mu 0.3, the cartons' 0.6 and 0.7): once the pallet slips the load slides as one body,
  // so its stop is the start-up's, taken on the same thread after it and checked once below the
  // pallet's onset (0.98 of 0.3 g), where an item could fail one way only. Searched on its own,
  // the stop lands within one step of it, with the same mode.
  void aLoadItsPalletCarriesBothWaysTakesItsStopFromTheStartUp() {
    const test::ConstantMu grip{0.3, 0.6, 0.7, 0.8};
    const PalletConfig off = test::pallet({test::carton(0.2, 0, 0.15), test::carton(0.2, 0, 0.35)});
    QVERIFY(!mirror_symmetric_along(off));
    auto s = settle(off, grip);
    auto env = search_envelope(*s->sim, s->rest, s->bounds, line_, search_);
    QVERIFY2(env.ok(), env.ok() ? "" : env.diagnostics[0].message.c_str());
    QCOMPARE(env->accel.mode, FailureMode::pallet_slip);
    QVERIFY(env->decel.derived);
    QCOMPARE(env->decel.limit, env->accel.limit);
    QCOMPARE(env->decel.mode, FailureMode::pallet_slip);
    std::vector<double> stops;
    for (const Probe& p : env->probes) {
      if (p.axis == Axis::decel) stops.push_back(p.value);
    }
    QCOMPARE(stops.size(), std::size_t(1));
    QCOMPARE(env->decel.probes, 1);
    QVERIFY2(std::abs(stops[0] - kConeSaturated * 0.3 * kGravity) < 1e-9,
             qPrintable(QString::number(stops[0])));
    SearchConfig each = search_;
    each.derive_axes = false;
    auto separate = search_envelope(*s->sim, s->rest, s->bounds, line_, each);
    QVERIFY(separate.ok());
    QVERIFY(!separate->decel.derived && separate->decel.probes > 1);
    QCOMPARE(separate->decel.mode, FailureMode::pallet_slip);
    QVERIFY2(
        std::abs(separate->decel.limit - env->decel.limit) <= search_.decel_precision_mps2 + 1e-9,
        describe(separate->decel));
  }

  // A load its pallet carries (the cartons grip at 0.6 and 0.7, the belt at 0.3) is seeded from
  // its pallet's predicted slide, above 0.98 of the pallet's onset, where it is checked. Judged
  // by a pallet slip of 2 mm, it fails there (soft contacts creep a few millimetres a second under
  // a sustained load inside the cone): the check runs first and the start-up is searched below it
  // at once, with no probe above it. The reference's plain bisection, which searches first and
  // checks after, finds the same limit within a step.
  void aCarriedLoadIsCheckedBelowItsPalletsOnsetFirst() {
    const test::ConstantMu grip{0.3, 0.6, 0.7, 0.8};
    auto s = settle(test::pallet({test::carton(0.2, 0, 0.15), test::carton(0.2, 0, 0.35)}), grip);
    SimOptions creep;
    creep.thresholds.pallet_slip_m = 0.002;
    auto env = search_envelope(*s->sim, s->rest, s->bounds, line_, search_, creep);
    QVERIFY2(env.ok(), env.ok() ? "" : env.diagnostics[0].message.c_str());
    const double check = kConeSaturated * 0.3 * g;
    std::vector<const Probe*> start_ups;
    for (const Probe& p : env->probes) {
      if (p.axis == Axis::accel) start_ups.push_back(&p);
    }
    QVERIFY(start_ups.size() > 1);
    QCOMPARE(start_ups[0]->value, check);
    QCOMPARE(start_ups[0]->outcome, Outcome::failed);
    for (const Probe* p : start_ups)
      QVERIFY2(p->value <= check, qPrintable(QString::number(p->value)));
    QCOMPARE(env->accel.mode, FailureMode::pallet_slip);
    QVERIFY2(env->accel.limit < check, describe(env->accel));
    SearchConfig plain = search_;
    plain.seed_with_closed_form = false;
    auto bisected = search_envelope(*s->sim, s->rest, s->bounds, line_, plain, creep);
    QVERIFY(bisected.ok());
    QVERIFY2(
        std::abs(bisected->accel.limit - env->accel.limit) <= search_.accel_precision_mps2 + 1e-9,
        describe(bisected->accel));
  }

  // A carried load's curve is seeded from its pallet's slide in the arc, a hair above 0.98 of the
  // pallet's onset where its check runs: a seed within half a step above the check starts at it,
  // so the check is the search's first probe (one simulation fewer), and every curve probe lies
  // on the check's grid of half steps.
  void aSeedJustAboveItsCheckStartsAtTheCheck() {
    const test::ConstantMu grip{0.3, 0.6, 0.7, 0.8};
    auto s = settle(test::pallet({test::carton(0.2, 0, 0.15), test::carton(0.2, 0, 0.35)}), grip);
    auto env = search_envelope(*s->sim, s->rest, s->bounds, line_, search_, SimOptions{});
    QVERIFY2(env.ok(), env.ok() ? "" : env.diagnostics[0].message.c_str());
    std::vector<double> curve;
    for (const Probe& p : env->probes) {
      if (p.axis == Axis::lateral && !p.confirmation) curve.push_back(p.value);
    }
    QVERIFY(curve.size() > 1);
    QCOMPARE(env->lateral.mode, FailureMode::pallet_slip);
    const double half = 0.5 * search_.lateral_precision_g;
    for (double x : curve) {
      const double steps = (x - curve[0]) / half;
      QVERIFY2(std::abs(steps - std::round(steps)) < 1e-6, qPrintable(QString::number(x)));
    }
    QCOMPARE(std::count(curve.begin(), curve.end(), curve[0]), std::ptrdiff_t{1});
  }

  // A check below the pallet's onset that holds but came near failing does not vouch for the band
  // above it: h3102 of the hold-out set (two columns of six cartons, each column tipping at 3.41
  // m/s^2, its pallet slipping at 3.40) holds at 0.98 of the pallet's onset with peak ratio 0.54
  // and fails at 0.985 of it; the search went on to 5.0 m/s^2, safe above the breakaway, where
  // the reference configuration answers 3.31. The band is probed and the start-up searched below
  // its failure. The band is MuJoCo's pyramidal cone's (its loads chatter near their onsets); in
  // the shipped elliptic cone h3102 holds up to its onset (breakaway_study_test), so the pyramid
  // is where the follow-up is exercised. Which timestep shows the case is chaotic: the case was
  // found at 1 ms; since the box-box filter drops contacts deeper than their boxes overlap
  // (session 37: h3102's columns had phantom ones), at 1 ms the check fails outright, at 0.9-1.1
  // and 1.5 ms it holds far from failing, and at 1.2 ms it holds at 0.79 and the band's 0.995
  // fails.
  void aCheckThatCameNearFailingProbesTheBandAboveIt() {
    auto source =
        read_pallet_source(PB_SOURCE_DIR "/docs/studies/unwrapped-holdout/pallets/h3102.json");
    QVERIFY(source.ok());
    AnalyzerOptions pyramid;  // the model its case was found in, at 1.2 ms
    pyramid.scene = with_mujoco_solver(pyramid.scene);
    pyramid.full_model_timestep_s = 0.0012;
    Analyzer analyzer(pyramid);
    auto prepared = analyzer.prepare(source->pallet);
    QVERIFY(prepared.ok());
    const double onset = (*prepared.value)->bounds.weakest_along().accel_mps2;
    QCOMPARE((*prepared.value)->bounds.weakest_along().mechanism, Mechanism::pallet_slip);
    auto env = analyzer.envelope(source->pallet);
    QVERIFY(env.ok());
    const Probe* check = nullptr;
    const Probe* band = nullptr;
    for (const Probe& p : env->probes) {
      if (p.axis != Axis::accel) continue;
      if (p.value == kConeSaturated * onset) check = &p;
      if (p.value > kConeSaturated * onset && p.value < onset && p.outcome == Outcome::failed &&
          band == nullptr) {
        band = &p;
      }
    }
    QVERIFY(check != nullptr);
    QCOMPARE(check->outcome, Outcome::safe);
    // Near failing by its load's own detectors (the columns rock towards their tip).
    QVERIFY2(check->load_peak_ratio >= 0.5, qPrintable(QString::number(check->load_peak_ratio)));
    QVERIFY(band != nullptr);
    QVERIFY2(env->accel.limit < band->value, describe(env->accel));
    QVERIFY2(env->decel.limit < onset, describe(env->decel));
    QVERIFY(env->accel.mode != FailureMode::no_failure);
  }

  // The band is for a load that fails and holds by turns while its pallet passes on nearly all it
  // can; a pallet that came near slipping its allowance at the check is not that: its slip grows
  // with the demand, and the search above the onset finds where it fails. Seven layers of four
  // cartons, pinwheeled, frozen, on a CHEP pallet (the scanner's seed 4): its start-up check holds
  // with its pallet having slipped about two thirds of its allowance (the tall load rocks the
  // pallet's grip on its belt) while no carton came near a threshold, and the search goes on above
  // the onset without probing the band. (Until session 36 any detector's peak sent the search
  // into the band: three probes more on each axis of a 64-carton load of the same kind.)
  void aCheckNearFailingByItsPalletsSlipAloneSkipsTheBand() {
    RandomPalletOptions r;
    r.seed = 4;
    r.min_layers = r.max_layers = 7;
    r.min_items_per_layer = r.max_items_per_layer = 4;
    r.wrap = WrapType::none;
    r.anomaly_rate = 0.0;
    auto config = random_pallet(r, Catalog::builtin());
    QVERIFY(config.ok());
    Analyzer analyzer;
    auto prepared = analyzer.prepare(*config.value);
    QVERIFY(prepared.ok());
    QCOMPARE((*prepared.value)->bounds.weakest_along().mechanism, Mechanism::pallet_slip);
    const double onset = (*prepared.value)->bounds.weakest_along().accel_mps2;
    auto env = analyzer.envelope(*config.value);
    QVERIFY(env.ok());
    const Probe* check = nullptr;
    for (const Probe& p : env->probes) {
      if (p.axis != Axis::accel) continue;
      if (p.value == kConeSaturated * onset) check = &p;
      QVERIFY2(p.value <= kConeSaturated * onset || p.value >= onset,
               qPrintable(QString("a probe in the band: %1").arg(p.value)));
    }
    QVERIFY(check != nullptr);
    QCOMPARE(check->outcome, Outcome::safe);
    QVERIFY2(check->peak_ratio >= 0.5, qPrintable(QString::number(check->peak_ratio)));
    QVERIFY2(check->load_peak_ratio < 0.5, qPrintable(QString::number(check->load_peak_ratio)));
    QVERIFY2(env->accel.limit > onset, describe(env->accel));
    QCOMPARE(env->accel.mode, FailureMode::pallet_slip);
  }

  // A limit of a load whose items can move whose own probe came within a tenth of failing is run
  // once more along another numerical path (SearchConfig::confirm_from_peak). h3003 of the
  // hold-out set holds its start-up at 4.368 m/s^2 with peak ratio 0.99 on the searches' reduced
  // model, where the whole load fails at 4.360 and 4.368 and holds at 4.365; the reference
  // configuration answers 4.234. Along the other path it fails, and the search goes on below. A
  // load that moves as one body is not confirmed: its seed is near failing by design. Measured in
  // MuJoCo's pyramidal cone, whose loads chatter near their onsets (in the shipped elliptic cone
  // h3003's start-up probes come nowhere near failing below its limit).
  void aLimitThatCameNearFailingIsConfirmed() {
    auto source =
        read_pallet_source(PB_SOURCE_DIR "/docs/studies/unwrapped-holdout/pallets/h3003.json");
    QVERIFY(source.ok());
    AnalyzerOptions pyramid;  // the model its case was found in (the full model then at 1 ms)
    pyramid.scene = with_mujoco_solver(pyramid.scene);
    pyramid.full_model_timestep_s = 0.001;
    AnalyzerOptions unconfirmed = pyramid;
    unconfirmed.search.confirm_from_peak = 2.0;
    auto before = Analyzer(unconfirmed).envelope(source->pallet);
    QVERIFY(before.ok());
    const double held = before->accel.limit;
    const Probe* at_limit = nullptr;
    for (const Probe& p : before->probes) {
      if (p.axis == Axis::accel && p.value == held) at_limit = &p;
      QVERIFY(!p.confirmation);
    }
    QVERIFY(at_limit != nullptr);
    QVERIFY2(at_limit->peak_ratio >= 0.9, qPrintable(QString::number(at_limit->peak_ratio)));
    auto env = Analyzer(pyramid).envelope(source->pallet);
    QVERIFY(env.ok());
    const Probe* confirmation = nullptr;
    for (const Probe& p : env->probes) {
      if (p.axis == Axis::accel && p.confirmation && p.value == held) confirmation = &p;
    }
    QVERIFY(confirmation != nullptr);
    QCOMPARE(confirmation->outcome, Outcome::failed);
    QVERIFY2(env->accel.limit < held, describe(env->accel));
    auto slab = read_pallet_source("stable-dairy-slab");
    QVERIFY(slab.ok());
    auto one_body = Analyzer().envelope(slab->pallet);
    QVERIFY(one_body.ok());
    for (const Probe& p : one_body->probes) QVERIFY(!p.confirmation);
  }

  // A load that slips both ways whose start-up fails its check below the pallet's onset cannot
  // take its stop from the start-up: the stop is searched beside it, on a thread of its own. And
  // axis threads make their own mjData only within the memory budget, the models' own counted:
  // with room for none, the calling thread searches every axis. The probes are the serial
  // search's, bit for bit, in every case (the stack of
  // aCarriedLoadIsCheckedBelowItsPalletsOnsetFirst).
  void aStopIsSearchedBesideAStartUpThatFailsItsCheck() {
    const test::ConstantMu grip{0.3, 0.6, 0.7, 0.8};
    auto s = settle(test::pallet({test::carton(0.2, 0, 0.15), test::carton(0.2, 0, 0.35)}), grip);
    SimOptions creep;
    creep.thresholds.pallet_slip_m = 0.002;
    SearchConfig one = search_;
    one.axis_threads = 1;
    auto serial = search_envelope(*s->sim, s->rest, s->bounds, line_, one, creep);
    QVERIFY(serial.ok());
    QVERIFY(serial->accel.limit < kConeSaturated * 0.3 * g);  // it failed its check
    QVERIFY(!serial->decel.derived);
    const double model_bytes = s->sim->data_bytes();
    for (const double budget : {model_bytes, 3.5 * model_bytes, search_.axis_memory_bytes}) {
      SearchConfig side_by_side = search_;
      side_by_side.axis_memory_bytes = budget;
      side_by_side.speculate_after_ms = 0.0;
      auto env = search_envelope(*s->sim, s->rest, s->bounds, line_, side_by_side, creep);
      QVERIFY(env.ok());
      compare_probes(*env, *serial);
      if (QTest::currentTestFailed()) return;
      QCOMPARE(env->accel.limit, serial->accel.limit);
      QCOMPARE(env->decel.limit, serial->decel.limit);
      QCOMPARE(env->decel.mode, serial->decel.mode);
      QCOMPARE(env->lateral.limit, serial->lateral.limit);
      if (budget == model_bytes) QCOMPARE(env->ran_ahead, 0);  // no mjData to run ahead on
    }
  }

  // The line's curves turn both ways. A 200 kg block towards the pallet's +Y edge takes the whole
  // loaded pallet over that edge at g (0.4 - y_com) / z_com = 0.38 g in a right turn (which pushes
  // the load towards +Y); a left turn only tips the block over its own -Y edge, at
  // g (0.15 + 0.1) / 0.6 = 0.42 g. The limit is the right turn's, and the mirror image of the load
  // has the same limit from its left turn. A load that is its own mirror image across the belt
  // is run in one turn only.
  void curvesAreSearchedInBothTurns() {
    const test::ConstantMu grip{1.0, 0.8, 0.8};  // nothing slides below 0.8 g
    auto block = [](double y) { return test::carton(0, y, 0.15, {0.4, 0.5, 1.2}, 200.0); };
    // The load's centre of mass, 0.133 m off the centre line, tips at g (b/2 - y) / z = 0.378 g of
    // its own lateral acceleration; the curve turns the load, so the centre line's v^2 / r is
    // (r + y) / r times less there (turning_frame.hpp): 0.362 g on the 3 m line.
    const double com_y = 200.0 * 0.15 / 225.0;
    const double whole_load_tip = (0.4 - com_y) / ((25.0 * 0.075 + 200.0 * 0.75) / 225.0) /
                                  (1.0 + com_y / line_.curve_radius_m);
    std::optional<double> limits[2];
    for (const double y : {0.15, -0.15}) {
      auto s = settle(test::pallet({block(y)}), grip);
      QVERIFY(s);
      auto env = search_envelope(*s->sim, s->rest, s->bounds, line_, search_);
      QVERIFY2(env.ok(), env.ok() ? "" : env.diagnostics[0].message.c_str());
      const CurveTurn weak = y > 0 ? CurveTurn::right : CurveTurn::left;
      QCOMPARE(env->lateral.turn, weak);
      QCOMPARE(env->lateral.mode, FailureMode::tip_over);
      QVERIFY2(std::abs(env->lateral.limit - whole_load_tip) <= 1.5 * search_.lateral_precision_g,
               describe(env->lateral));
      bool right = false;
      for (const Probe& p : env->probes) right = right || p.turn == CurveTurn::right;
      QVERIFY(right);
      limits[y > 0 ? 0 : 1] = env->lateral.limit;
    }
    QVERIFY(std::abs(*limits[0] - *limits[1]) <= search_.lateral_precision_g + 1e-9);
    auto centred = settle(test::pallet({block(0.0)}), grip);
    auto env = search_envelope(*centred->sim, centred->rest, centred->bounds, line_, search_);
    QVERIFY(env.ok());
    for (const Probe& p : env->probes) QCOMPARE(p.turn, CurveTurn::left);
  }
};

QTEST_APPLESS_MAIN(EnvelopeTest)
#include "envelope_test.moc"
