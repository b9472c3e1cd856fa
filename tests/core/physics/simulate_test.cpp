// SPDX-License-Identifier: MIT
// The simulator against closed form, through real scenes: slip, pallet slip, tipping, the
// frost-melt penalty and an e-stop slide; wrap holding a load; and the runs that must never give
// a verdict (divergence, overflowing buffers, a load that does not settle). Friction is constant
// per contact (tests/core/test_friction.hpp), so every expected value is exact. Any MuJoCo warning
// makes the simulator report Outcome::unstable, which every physics check rejects.
#include "core/physics/simulate.hpp"

#include <QtTest>

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/physics/quasi_static.hpp"
#include "tests/core/test_friction.hpp"

using namespace pb;
using pb::test::ConstantMu;

namespace {

constexpr double kG = kGravity;  // the core's g, which the closed forms use too
constexpr double kDeck = 0.15;   // top of the EUR base
constexpr double kRampS = 1.5;   // threshold probes hold a constant acceleration this long
constexpr double kSlideM = DetectorThresholds{}.item_slide_m;        // 5 cm
constexpr double kPalletSlipM = DetectorThresholds{}.pallet_slip_m;  // 30 cm

QString q(const std::string& s) {
  return QString::fromStdString(s);
}

std::string describe(const Diagnostics& diagnostics) {
  std::string out;
  for (const auto& d : diagnostics) out += (out.empty() ? "" : "; ") + to_string(d);
  return out;
}

Item carton(const Vec3& dims, double kg, double z = kDeck) {
  Item item;
  item.sku = "TEST";
  item.weight_kg = kg;
  item.dims_m = dims;
  item.position = {0.0, 0.0, z};
  return item;
}

// An EUR pallet (25 kg) on a rubber belt, outside the frost-melt zone unless told otherwise.
PalletConfig pallet_of(std::vector<Item> items, WrapType wrap = WrapType::none) {
  PalletConfig config;
  config.pallet_id = "simulate-test";
  config.items = std::move(items);
  config.wrap = wrap;
  config.env = Environment::thawed;
  config.body_temp_c = 20.0;
  config.seconds_since_temp_change = 3600.0;
  return config;
}

// A compiled scene, its simulator and the rest state it settled to (error empty) or why not.
struct Rig {
  std::unique_ptr<Scene> scene;
  std::unique_ptr<Simulator> sim;
  RestState rest;
  std::string error;
};

Rig build(const PalletConfig& config, const ConstantMu& mu, const SceneOptions& options = {}) {
  Rig rig;
  const FrictionModel friction = test::constant_friction(mu);
  auto scene = build_scene(config, options, friction);
  if (!scene) {
    rig.error = "build_scene: " + describe(scene.diagnostics);
    return rig;
  }
  rig.scene = std::make_unique<Scene>(std::move(*scene.value));
  auto sim = Simulator::create(*rig.scene);
  if (!sim) {
    rig.error = "Simulator::create: " + describe(sim.diagnostics);
    return rig;
  }
  rig.sim = std::make_unique<Simulator>(std::move(*sim.value));
  return rig;
}

Rig settled(const PalletConfig& config, const ConstantMu& mu, const SceneOptions& options = {}) {
  Rig rig = build(config, mu, options);
  if (!rig.error.empty()) return rig;
  auto rest = rig.sim->settle();
  if (!rest) {
    rig.error = "settle: " + describe(rest.diagnostics);
    return rig;
  }
  rig.rest = std::move(*rest.value);
  return rig;
}

// Constant acceleration `a` for the whole run of `ramp_s` (target_speed = a * ramp_s, duration
// ramp_s): the belt never stops accelerating before the run ends.
ConveyorProfile constant_accel(double a, double ramp_s = kRampS) {
  ConveyorProfile p;
  p.shape = ProfileShape::accel_hold;
  p.accel_mps2 = a;
  p.target_speed_mps = a * ramp_s;
  p.duration_s = ramp_s;
  return p;
}

// A probe of a bisection: stop at the first failure, no early stop, no trace.
SimOptions probe_options() {
  SimOptions o;
  o.fail_fast = true;
  o.early_stop = false;
  o.record_trace = false;
  return o;
}

// The smallest failing value of a monotone probe family, to `tolerance`: [lo, hi] must start
// safe at lo and failed at hi. Every probe must be safe or failed (an unstable probe, or a
// failure of another mode than `mode`, is an error).
struct Threshold {
  double value = 0.0;
  int probes = 0;
  std::string error;
};

Threshold bisect(Rig& rig, const std::function<ConveyorProfile(double)>& profile, double lo,
                 double hi, FailureMode mode, double tolerance = 1e-4) {
  Threshold t;
  auto failed = [&](double x) -> std::optional<bool> {
    ++t.probes;
    const SimResult r = rig.sim->run(rig.rest, profile(x), probe_options());
    if (r.outcome == Outcome::unstable) {
      t.error = "probe at " + std::to_string(x) + " unstable: " + r.reason;
      return std::nullopt;
    }
    if (r.outcome == Outcome::failed && r.failure->mode != mode) {
      t.error = "probe at " + std::to_string(x) + ": " + describe(*r.failure);
      return std::nullopt;
    }
    return r.outcome == Outcome::failed;
  };
  const auto at_lo = failed(lo);
  if (!at_lo) return t;
  const auto at_hi = failed(hi);
  if (!at_hi) return t;
  if (*at_lo || !*at_hi) {
    t.error = "the bracket [" + std::to_string(lo) + ", " + std::to_string(hi) +
              "] does not hold the threshold";
    return t;
  }
  while (hi - lo > tolerance) {
    const double mid = 0.5 * (lo + hi);
    const auto f = failed(mid);
    if (!f) return t;
    (*f ? hi : lo) = mid;
  }
  t.value = 0.5 * (lo + hi);
  return t;
}

double error_pct(double measured, double expected) {
  return 100.0 * (measured - expected) / expected;
}

// A rigid block of footprint length b (along the belt) and height H on a surface that
// accelerates at a constant `a`: the acceleration at which its centre of mass has moved `d` (in
// the surface's frame) after `t_s`, when it pivots on its rear edge without slipping. RK4 on
// I_p theta'' = m r (a cos(alpha - theta) - g sin(alpha - theta)), alpha = atan(b / H),
// r = |centre - edge|; the block stays put while the right-hand side is negative at theta = 0.
double tip_threshold_rigid(double b, double height, double d, double t_s) {
  const double r = 0.5 * std::hypot(b, height);
  const double alpha = std::atan2(b, height);
  const double inertia_over_m = (b * b + height * height) / 12.0 + r * r;
  auto moved = [&](double a) {
    auto accel = [&](double theta) {
      const double rhs = r * (a * std::cos(alpha - theta) - kG * std::sin(alpha - theta));
      return (theta <= 0.0 && rhs < 0.0) ? 0.0 : rhs / inertia_over_m;
    };
    double theta = 0.0, omega = 0.0;
    const long steps = std::lround(t_s / 1e-4);
    const double h = t_s / static_cast<double>(steps);
    for (long k = 0; k < steps; ++k) {
      const double k1v = accel(theta), k1x = omega;
      const double k2v = accel(theta + 0.5 * h * k1x), k2x = omega + 0.5 * h * k1v;
      const double k3v = accel(theta + 0.5 * h * k2x), k3x = omega + 0.5 * h * k2v;
      const double k4v = accel(theta + h * k3x), k4x = omega + h * k3v;
      theta += h / 6.0 * (k1x + 2 * k2x + 2 * k3x + k4x);
      omega += h / 6.0 * (k1v + 2 * k2v + 2 * k3v + k4v);
      theta = std::max(theta, 0.0);
    }
    return 2.0 * r * std::sin(0.5 * theta);  // chord swept by the centre
  };
  double lo = kG * b / height, hi = 2.0 * lo;
  for (int i = 0; i < 40; ++i) {
    const double mid = 0.5 * (lo + hi);
    (moved(mid) > d ? hi : lo) = mid;
  }
  return 0.5 * (lo + hi);
}

const Vec3 kCarton{0.4, 0.3, 0.2};  // a 10 kg case on the deck, far from tipping (2 g)

}  // namespace

class SimulateTest : public QObject {
  Q_OBJECT

  // A diverging run is unstable, with a reason and no failure, whether or not it stops at the
  // first failure (searches stop there: a detector firing on a diverging state is no verdict).
  void expect_unstable(Rig& rig, const RestState& rest, const ConveyorProfile& profile) {
    SimOptions o = probe_options();
    o.fail_fast = false;
    const SimResult full = rig.sim->run(rest, profile, o);
    QCOMPARE(full.outcome, Outcome::unstable);
    QVERIFY(!full.reason.empty());
    QVERIFY(!full.failure);
    const SimResult fast = rig.sim->run(rest, profile, probe_options());
    if (fast.failure) qInfo("fail_fast run: %s", describe(*fast.failure).c_str());
    // A detector would fire on the growing motion long before MuJoCo's 1e10 limit trips (kv 4:
    // pallet_slip at 22 ms; banded dt 0.05: top_item_slide at 0.25 s): the simulator's own
    // guards must call it unstable first.
    QCOMPARE(fast.outcome, Outcome::unstable);
    QVERIFY(!fast.failure);
  }

 private slots:
  // 1. A carton slides on the pallet once a > mu g. With the 5 cm detector and the acceleration
  // held for T, the relative slide is (a - mu g) T^2 / 2, so the detected threshold is
  // mu g + 2 (0.05) / T^2.
  void cartonSlidesAtMuG() {
    const ConstantMu mu{1.0, 0.3, 0.4};
    Rig rig = settled(pallet_of({carton(kCarton, 10.0)}), mu);
    QVERIFY2(rig.error.empty(), rig.error.c_str());
    const double expected = mu.item_pallet * kG + 2.0 * kSlideM / (kRampS * kRampS);
    const Threshold t = bisect(
        rig, [](double a) { return constant_accel(a); }, 0.9 * expected, 1.1 * expected,
        FailureMode::top_item_slide);
    QVERIFY2(t.error.empty(), t.error.c_str());
    qInfo("carton slide: expected %.4f, measured %.4f (%+.3f %%), %d probes", expected, t.value,
          error_pct(t.value, expected), t.probes);
    QVERIFY(std::abs(error_pct(t.value, expected)) < 1.0);
  }

  // 2. The pallet slips on the belt once a > mu_belt g (cartons held by high friction); the 30 cm
  // detector over T adds 2 (0.30) / T^2.
  void palletSlipsAtMuBeltG() {
    const ConstantMu mu{0.3, 1.0, 1.0};
    Rig rig = settled(pallet_of({carton(kCarton, 10.0)}), mu);
    QVERIFY2(rig.error.empty(), rig.error.c_str());
    const double expected = mu.belt_pallet * kG + 2.0 * kPalletSlipM / (kRampS * kRampS);
    const Threshold t = bisect(
        rig, [](double a) { return constant_accel(a); }, 0.9 * expected, 1.1 * expected,
        FailureMode::pallet_slip);
    QVERIFY2(t.error.empty(), t.error.c_str());
    qInfo("pallet slip: expected %.4f, measured %.4f (%+.3f %%), %d probes", expected, t.value,
          error_pct(t.value, expected), t.probes);
    QVERIFY(std::abs(error_pct(t.value, expected)) < 1.0);
  }

  // 3. A slender carton (0.2 x 0.2 x 1.0 m, 20 kg, mu 1.0 so it cannot slip before 9.81 m/s^2)
  // tips backwards once a > g (b/2) / h_com = 1.962 m/s^2. Tipping is detected by top_item_slide
  // when its centre has moved 5 cm on the pallet; within T that takes slightly more than the
  // static bound, which the rigid-body solution gives (within 0.5 % of the static bound).
  void slenderCartonTipsAtGbOver2h() {
    const Vec3 dims{0.2, 0.2, 1.0};
    Rig rig = settled(pallet_of({carton(dims, 20.0)}), {1.0, 1.0, 1.0});
    QVERIFY2(rig.error.empty(), rig.error.c_str());
    const double static_bound = kG * (dims[0] / 2) / (dims[2] / 2);
    const double expected = tip_threshold_rigid(dims[0], dims[2], kSlideM, kRampS);
    QVERIFY(expected > static_bound && expected < 1.005 * static_bound);
    const Threshold t = bisect(
        rig, [](double a) { return constant_accel(a); }, 0.9 * static_bound, 1.1 * static_bound,
        FailureMode::top_item_slide);
    QVERIFY2(t.error.empty(), t.error.c_str());
    qInfo(
        "tip: static %.4f, rigid-body %.4f, measured %.4f (%+.3f %% vs rigid body, %+.3f %% vs "
        "static)",
        static_bound, expected, t.value, error_pct(t.value, expected),
        error_pct(t.value, static_bound));
    QVERIFY(std::abs(error_pct(t.value, expected)) < 1.0);
    QVERIFY(std::abs(error_pct(t.value, static_bound)) < 1.0);
  }

  // 4. The frost-melt penalty multiplies every friction coefficient: at 2 C (inside the danger
  // zone) 60 s after the change the onset of slip (threshold minus the detector's 2 d / T^2)
  // is FrostMeltPenalty::multiplier times the onset 3600 s after it (fully recovered).
  void frostMeltPenaltyScalesTheSlipThreshold() {
    const ConstantMu mu{1.0, 0.3, 0.4};
    const double detection = 2.0 * kSlideM / (kRampS * kRampS);
    struct Onset {
      double accel = 0.0;
      double penalty = 0.0;
      std::string error;
    };
    auto onset = [&](double seconds_since_change) {
      PalletConfig config = pallet_of({carton(kCarton, 10.0)});
      config.env = Environment::transitioning;
      config.body_temp_c = 2.0;
      config.seconds_since_temp_change = seconds_since_change;
      Rig rig = settled(config, mu);
      if (!rig.error.empty()) return Onset{0.0, 0.0, rig.error};
      const FrictionValue& item_pallet = rig.scene->friction.item_pallet;
      const double guess = item_pallet.mu_s * kG + detection;
      const Threshold t = bisect(
          rig, [](double a) { return constant_accel(a); }, 0.9 * guess, 1.1 * guess,
          FailureMode::top_item_slide);
      return Onset{t.value - detection, item_pallet.penalty, t.error};
    };
    const double multiplier = test::kTestPenalty.multiplier(2.0, 60.0);
    QCOMPARE(multiplier, 1.0 - 0.8 * 0.9 * 0.35);  // zone factor 0.8, recovery factor 0.9
    const Onset fresh = onset(60.0);
    QVERIFY2(fresh.error.empty(), fresh.error.c_str());
    QCOMPARE(fresh.penalty, multiplier);
    const Onset recovered = onset(3600.0);
    QVERIFY2(recovered.error.empty(), recovered.error.c_str());
    QCOMPARE(recovered.penalty, 1.0);
    const double ratio = fresh.accel / recovered.accel;
    qInfo("frost melt: multiplier %.4f, onset %.4f / %.4f = %.4f (%+.3f %%)", multiplier,
          fresh.accel, recovered.accel, ratio, error_pct(ratio, multiplier));
    QVERIFY(std::abs(error_pct(ratio, multiplier)) < 1.0);
  }

  // 5. An e-stop from v at d > mu g: the belt (and the pallet, held by mu 1.0) stops in v / d, the
  // carton in v / (mu g), so it slides v^2 / 2 (1 / (mu g) - 1 / d) forward on the pallet.
  void estopSlideMatchesClosedForm() {
    const ConstantMu mu{1.0, 0.3, 0.4};
    Rig rig = settled(pallet_of({carton(kCarton, 10.0)}), mu);
    QVERIFY2(rig.error.empty(), rig.error.c_str());
    const double v = 1.5, d = 5.0;
    ConveyorProfile p;
    p.shape = ProfileShape::estop;
    p.target_speed_mps = v;
    p.decel_mps2 = d;
    p.decel_start_s = 0.05;
    p.duration_s = p.decel_start_s + v / (mu.item_pallet * kG) + 0.3;
    SimOptions o;
    o.fail_fast = false;
    o.early_stop = false;
    o.record_trace = true;
    o.thresholds = {.tip_deg = 90.0,
                    .item_slide_m = 10.0,
                    .load_shift_m = 10.0,
                    .pallet_slip_m = 10.0};  // nothing fires
    const SimResult r = rig.sim->run(rig.rest, p, o);
    QVERIFY2(r.outcome == Outcome::safe, r.reason.c_str());
    QVERIFY(!r.stopped_early);
    const std::size_t last = r.trace.size() - 1;
    QCOMPARE(r.trace.time(last), r.sim_time_s);
    const Vec3 start = to_frame(rig.rest.pallet, rig.rest.items[0].pos);
    const Vec3 end = to_frame(r.trace.pallet(last), r.trace.items(last)[0].pos);
    const double slide = end[0] - start[0];
    const double expected = v * v / 2.0 * (1.0 / (mu.item_pallet * kG) - 1.0 / d);
    qInfo("e-stop slide: expected %.4f m, measured %.4f m (%+.3f %%); lateral %.2e m", expected,
          slide, error_pct(slide, expected), end[1] - start[1]);
    QVERIFY(std::abs(error_pct(slide, expected)) < 5.0);
    QVERIFY(std::abs(end[1] - start[1]) < 1e-3);
    // At rest on the pallet at the end: the carton no longer moves relative to it over the last
    // 0.1 s (found by time: a co-moving skip leaves one frame for the steps it jumps).
    std::size_t earlier = last;
    while (earlier > 0 && r.trace.time(earlier) > r.trace.time(last) - 0.1) --earlier;
    const Vec3 before = to_frame(r.trace.pallet(earlier), r.trace.items(earlier)[0].pos);
    QVERIFY(std::abs(end[0] - before[0]) < 1e-3);
  }

  // 6. Two cartons stacked (item on item mu 0.2 -> slips at 1.96 m/s^2; on the pallet 0.6; belt
  // 1.0) at 3.5 m/s^2: the unwrapped top carton slides off; stretch wrap holds both.
  void wrapHoldsWhatUnwrappedLoses() {
    const ConstantMu mu{1.0, 0.6, 0.2};
    const std::vector<Item> column{carton(kCarton, 10.0), carton(kCarton, 10.0, kDeck + 0.2)};
    const ConveyorProfile p = constant_accel(3.5, 0.5);
    SimOptions o = probe_options();

    Rig loose = settled(pallet_of(column, WrapType::none), mu);
    QVERIFY2(loose.error.empty(), loose.error.c_str());
    const SimResult fails = loose.sim->run(loose.rest, p, o);
    QVERIFY2(fails.outcome == Outcome::failed, fails.reason.c_str());
    QVERIFY(fails.failure->mode == FailureMode::top_item_slide ||
            fails.failure->mode == FailureMode::load_shift);
    QVERIFY(fails.failure->items == std::vector<int>{1} ||
            fails.failure->items == (std::vector<int>{0, 1}));
    qInfo("unwrapped: %s", describe(*fails.failure).c_str());

    Rig wrapped = settled(pallet_of(column, WrapType::stretch), mu);
    QVERIFY2(wrapped.error.empty(), wrapped.error.c_str());
    QCOMPARE(wrapped.scene->layout.welds, 2);
    const SimResult holds = wrapped.sim->run(wrapped.rest, p, o);
    QVERIFY2(holds.outcome == Outcome::safe, holds.reason.c_str());
    QVERIFY(!holds.failure);
    QCOMPARE(holds.sim_time_s, p.duration_s);
  }

  // 7a. Euler integration of the belt's velocity actuator diverges for kv dt / M > 2 (here 4:
  // every step triples any belt velocity error, from round-off on). Probes start from the rest
  // state of the same pallet settled with the default kv.
  void stiffBeltActuatorIsUnstable() {
    const PalletConfig config = pallet_of({carton(kCarton, 10.0)});
    const Rig good = settled(config, {});
    QVERIFY2(good.error.empty(), good.error.c_str());
    SceneOptions options;
    options.belt_kv_ratio = 4.0;
    Rig rig = build(config, {}, options);
    QVERIFY2(rig.error.empty(), rig.error.c_str());
    expect_unstable(rig, good.rest, constant_accel(1.0, 1.0));
  }

  // 7b. A timestep 25 times too large: at dt = 0.05 s the banded wrap's weld (sqrt(K') dt = 2.7)
  // diverges. (Without wrap, dt = 0.05 s does not diverge: see unsettledLoadIsABuildDefect.)
  void hugeTimestepIsUnstable() {
    const PalletConfig config = pallet_of({carton(kCarton, 10.0)}, WrapType::banded);
    const Rig good = settled(config, {});
    QVERIFY2(good.error.empty(), good.error.c_str());
    SceneOptions options;
    options.timestep_s = 0.05;
    Rig rig = build(config, {}, options);
    QVERIFY2(rig.error.empty(), rig.error.c_str());
    auto rest = rig.sim->settle();
    QVERIFY(!rest);
    QCOMPARE(rest.diagnostics.size(), std::size_t{1});
    QVERIFY2(q(rest.diagnostics[0].message).contains(QStringLiteral("timestep")),
             rest.diagnostics[0].message.c_str());
    expect_unstable(rig, good.rest, constant_accel(3.0, 1.0));
  }

  // 7b'. Below the timestep cap, a wrap weld too stiff for its timestep: at dt = 10 ms a banded
  // weld made 50 times stiffer (sqrt(K') dt from 0.54 to 3.8) is refused before it runs.
  void weldTooStiffForTheTimestepIsUnstable() {
    const PalletConfig config = pallet_of({carton(kCarton, 10.0)}, WrapType::banded);
    const Rig good = settled(config, {});
    QVERIFY2(good.error.empty(), good.error.c_str());
    SceneOptions options;
    options.timestep_s = 0.01;
    Rig rig = build(config, {}, options);
    QVERIFY2(rig.error.empty(), rig.error.c_str());
    QVERIFY(!numerical_limits_problem(*rig.scene));
    rig.scene->model->eq_solref[0] *= 50.0;
    const auto problem = numerical_limits_problem(*rig.scene);
    QVERIFY(problem.has_value());
    QVERIFY2(q(*problem).contains(QStringLiteral("too stiff")), problem->c_str());
    expect_unstable(rig, good.rest, constant_accel(3.0, 1.0));
  }

  // 7c. A contact buffer too small for the scene (the belt-pallet contact alone needs 4): the
  // settle fails, and a probe from a good rest state is unstable at its first step.
  void tinyContactBufferIsUnstable() {
    const PalletConfig config = pallet_of({carton(kCarton, 10.0)});
    const Rig good = settled(config, {});
    QVERIFY2(good.error.empty(), good.error.c_str());
    SceneOptions options;
    options.nconmax = 2;
    Rig rig = build(config, {}, options);
    QVERIFY2(rig.error.empty(), rig.error.c_str());
    auto rest = rig.sim->settle();
    QVERIFY(!rest);
    QCOMPARE(rest.diagnostics.size(), std::size_t{1});
    QVERIFY2(q(rest.diagnostics[0].message).contains(QStringLiteral("contact buffer")),
             rest.diagnostics[0].message.c_str());
    for (bool fail_fast : {false, true}) {
      SimOptions o = probe_options();
      o.fail_fast = fail_fast;
      const SimResult r = rig.sim->run(good.rest, constant_accel(1.0, 1.0), o);
      QCOMPARE(r.outcome, Outcome::unstable);
      QVERIFY2(q(r.reason).contains(QStringLiteral("contact buffer")), r.reason.c_str());
      QVERIFY(!r.failure);
      QCOMPARE(r.steps, 1);
    }
  }

  // 8. A load still moving when the settle time runs out cannot stand (a build defect, not a
  // verdict): a carton placed 0.5 mm above the deck (within validation's 1 mm support tolerance)
  // is still falling or bouncing after 20 ms; given the default 3 s it settles, and is held at
  // rest for hold_s before it is declared settled.
  void unsettledLoadIsABuildDefect() {
    Rig rig = build(pallet_of({carton(kCarton, 10.0, kDeck + 0.0005)}), {});
    QVERIFY2(rig.error.empty(), rig.error.c_str());
    SettleOptions tiny;
    tiny.min_time_s = 0.0;
    tiny.max_time_s = 0.02;
    auto rest = rig.sim->settle(tiny);
    QVERIFY2(rest, describe(rest.diagnostics).c_str());
    QVERIFY(rest->cannot_stand.has_value());
    QCOMPARE(rest->cannot_stand->event.mode, FailureMode::no_failure);  // nothing moved far
    QCOMPARE(rest->cannot_stand->item, 0);
    QVERIFY2(q(rest->cannot_stand->sentence).contains(QStringLiteral("does not come to rest")),
             rest->cannot_stand->sentence.c_str());
    QVERIFY(q(rest->cannot_stand->sentence).contains(QStringLiteral("build defect")));
    // A probe from it is refused, never run.
    ConveyorProfile p;
    p.shape = ProfileShape::constant;
    p.target_speed_mps = 0.0;
    p.duration_s = 0.5;
    const SimResult refused = rig.sim->run(*rest, p);
    QCOMPARE(refused.outcome, Outcome::unstable);
    QCOMPARE(refused.steps, 0);
    auto normal = rig.sim->settle();
    QVERIFY2(normal, describe(normal.diagnostics).c_str());
    QVERIFY(!normal->cannot_stand);
    QVERIFY(normal->settle_time_s > 0.02 && normal->settle_time_s < 3.0);
    QVERIFY(normal->residual_speed_mps < SettleOptions{}.rest_speed_mps);
  }

  // 8a. A load quiet at some checks but never for a whole hold, whose items stay put, stands:
  // contact chatter is not motion. Here the hold cannot fit in the settle time at all.
  void aLoadThatStaysPutStandsWithoutAWholeHold() {
    Rig rig = build(pallet_of({carton(kCarton, 10.0)}), {});
    QVERIFY2(rig.error.empty(), rig.error.c_str());
    SettleOptions o;
    o.hold_s = 1.0;
    o.max_time_s = 0.5;
    auto rest = rig.sim->settle(o);
    QVERIFY2(rest, describe(rest.diagnostics).c_str());
    QVERIFY(!rest->cannot_stand);
    auto normal = rig.sim->settle();
    QVERIFY(normal.ok());
    QCOMPARE(rest->state.qpos, normal->state.qpos);  // the first rest, whatever the hold
    QCOMPARE(rest->settle_time_s, normal->settle_time_s);
  }

  // 8a'. Contact chatter: six eight-high columns of dairy cases at the full model's numerics rock
  // by a tenth of a millimetre at about the rest speed and, until session 29, were never quiet
  // for a whole hold: the settle ran its whole 3 s (9 s of CPU for 96 such cartons). Items that
  // stay within what the rest speed carries them over the hold have held on average no faster
  // than it: settled one hold after the first rest, at that rest. The chatter is MuJoCo's CG's
  // (it stops 1e-4 from the converged solve); solved by ours (Solver::pcg) the same load is
  // quiet enough for the speed rule alone to settle it within a second of its first rest.
  void aChatteringLoadIsSettledOneHoldAfterItsFirstRest() {
    std::vector<Item> items;
    for (double x : {-0.45, -0.15}) {
      for (double y : {-0.25, 0.0, 0.25}) {
        for (int level = 0; level < 8; ++level) {
          Item c = carton({0.3, 0.25, 0.2}, 10.0, kDeck + 0.2 * level);
          c.position[0] = x;
          c.position[1] = y;
          items.push_back(c);
        }
      }
    }
    SceneOptions full;
    full.timestep_s = 0.001;
    full.contact_solref[0] = 0.01;
    {
      Rig quiet = build(pallet_of(items), {1.0, 0.5, 0.4}, full);
      QVERIFY2(quiet.error.empty(), quiet.error.c_str());
      SettleOptions speed_only;
      speed_only.calm_hold = false;
      auto rest = quiet.sim->settle(speed_only);
      QVERIFY2(rest, describe(rest.diagnostics).c_str());
      QVERIFY2(
          rest->settle_run_s <= rest->settle_time_s + 1.0,
          (std::to_string(rest->settle_time_s) + " " + std::to_string(rest->settle_run_s)).c_str());
    }
    full.solver = Solver::cg;
    Rig rig = build(pallet_of(items), {1.0, 0.5, 0.4}, full);
    QVERIFY2(rig.error.empty(), rig.error.c_str());
    const SettleOptions o;
    auto rest = rig.sim->settle(o);
    QVERIFY2(rest, describe(rest.diagnostics).c_str());
    QVERIFY(!rest->cannot_stand);
    // One hold, then the first check at rest: a few checks at most.
    QVERIFY2(rest->settle_run_s <= rest->settle_time_s + o.hold_s + 0.1,
             std::to_string(rest->settle_run_s).c_str());
    // The load does chatter: by the speed rule alone it is never at rest for a whole hold and
    // is settled only by the 3 s fallback, at the same rest.
    SettleOptions speed_only = o;
    speed_only.calm_hold = false;
    auto slow = rig.sim->settle(speed_only);
    QVERIFY2(slow, describe(slow.diagnostics).c_str());
    QVERIFY(!slow->cannot_stand);
    QVERIFY2(slow->settle_run_s > rest->settle_time_s + 1.0,
             std::to_string(slow->settle_run_s).c_str());
    QCOMPARE(slow->state.qpos, rest->state.qpos);
  }

  // 8b. A carton whose centre of mass is beyond the end of the carton under it (the standing rule
  // off, to reach the simulation) tips on a still belt: a detector crossing against the as-built
  // poses, named at the carton that moved, and no rest state to probe.
  void aCartonOverTheEdgeCannotStand() {
    SceneOptions options;
    options.require_standing = false;
    Item top = carton(kCarton, 10.0, kDeck + kCarton[2]);
    top.position[0] = 0.3;  // its centre of mass 0.1 m beyond the end of the carton under it
    Rig rig = build(pallet_of({carton(kCarton, 10.0), top}), {1.0, 0.6, 0.4}, options);
    QVERIFY2(rig.error.empty(), rig.error.c_str());
    auto rest = rig.sim->settle();
    QVERIFY2(rest, describe(rest.diagnostics).c_str());
    QVERIFY(rest->cannot_stand.has_value());
    const StandFailure& f = *rest->cannot_stand;
    QVERIFY(f.event.mode != FailureMode::no_failure);  // a detector crossed, on a still belt
    QCOMPARE(f.item, 1);
    QCOMPARE(f.moved, 1);
    QVERIFY2(q(f.sentence)
                 .startsWith(QStringLiteral("item 1 (TEST) cannot stand: with the belt "
                                            "standing still")),
             f.sentence.c_str());
    QVERIFY(rest->settle_time_s < 1.0);  // it goes at once
  }

  // 8c. A carton whose centre of mass is barely beyond the edge under it tips slowly from near
  // balance: it passes the chatter rule's distance for a while, but it is not at rest when the
  // hold ends, and it cannot stand (the full model's numerics, the standing rule off).
  void aCartonBarelyOverTheEdgeStillCannotStand() {
    for (double beyond : {0.0005, 0.002}) {
      SceneOptions options;
      options.require_standing = false;
      options.timestep_s = 0.001;
      options.contact_solref[0] = 0.01;
      Item top = carton(kCarton, 10.0, kDeck + kCarton[2]);
      top.position[0] = kCarton[0] / 2 + beyond;
      Rig rig = build(pallet_of({carton(kCarton, 10.0), top}), {1.0, 0.6, 0.4}, options);
      QVERIFY2(rig.error.empty(), rig.error.c_str());
      auto rest = rig.sim->settle();
      QVERIFY2(rest, describe(rest.diagnostics).c_str());
      QVERIFY2(rest->cannot_stand.has_value(), std::to_string(beyond).c_str());
      QCOMPARE(rest->cannot_stand->item, 1);
    }
  }

  // 9. After its last breakpoint a co-moving load stops early with the same outcome.
  void earlyStopKeepsTheOutcome() {
    Rig rig = settled(pallet_of({carton(kCarton, 10.0)}), {1.0, 0.3, 0.4});
    QVERIFY2(rig.error.empty(), rig.error.c_str());
    ConveyorProfile p;
    p.shape = ProfileShape::accel_hold;
    p.accel_mps2 = 1.0;
    p.target_speed_mps = 0.5;
    p.duration_s = 3.0;
    SimOptions on = probe_options();
    on.early_stop = true;
    const SimResult early = rig.sim->run(rig.rest, p, on);
    const SimResult full = rig.sim->run(rig.rest, p, probe_options());
    qInfo("early stop: %.3f s vs %.3f s", early.sim_time_s, full.sim_time_s);
    QCOMPARE(early.outcome, Outcome::safe);
    QCOMPARE(full.outcome, Outcome::safe);
    QVERIFY(early.stopped_early);
    QVERIFY(!full.stopped_early);
    QVERIFY(early.sim_time_s > 0.5 && early.sim_time_s < 1.0);
    QCOMPARE(full.sim_time_s, p.duration_s);
  }

  // 9b. A carton still sliding when the ramp ends must not stop early: it fails in the hold.
  void earlyStopWaitsForASlidingLoad() {
    Rig rig = settled(pallet_of({carton(kCarton, 10.0)}), {1.0, 0.3, 0.4});
    QVERIFY2(rig.error.empty(), rig.error.c_str());
    ConveyorProfile p;
    p.shape = ProfileShape::accel_hold;
    p.accel_mps2 = 6.0;
    p.target_speed_mps = 0.9;  // 0.15 s ramp: 3.4 cm slid, then 3.6 cm more while it catches up
    p.duration_s = 1.0;
    SimOptions on = probe_options();
    on.early_stop = true;
    const SimResult early = rig.sim->run(rig.rest, p, on);
    const SimResult full = rig.sim->run(rig.rest, p, probe_options());
    QCOMPARE(early.outcome, Outcome::failed);
    QCOMPARE(full.outcome, Outcome::failed);
    QVERIFY(!early.stopped_early);
    QVERIFY(*early.failure == *full.failure);
    qInfo("sliding load: %s", describe(*early.failure).c_str());
    QCOMPARE(early.failure->mode, FailureMode::top_item_slide);
    QVERIFY(early.failure->time_s > 0.15);
  }
};

QTEST_APPLESS_MAIN(SimulateTest)
#include "simulate_test.moc"
