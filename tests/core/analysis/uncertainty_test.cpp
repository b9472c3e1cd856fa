// SPDX-License-Identifier: MIT
#include "core/analysis/uncertainty.hpp"

#include <QtTest>
#include <cmath>
#include <memory>
#include <optional>

#include "core/analysis/analyzer.hpp"
#include "core/analysis/envelope.hpp"
#include "core/base/text.hpp"
#include "core/contract/json_io.hpp"
#include "tests/core/test_friction.hpp"
#include "tests/core/test_pallets.hpp"

using namespace pb;

namespace {

struct Settled {
  std::unique_ptr<Scene> scene;
  RestState rest;
};

std::unique_ptr<Settled> settle(const test::ConstantMu& mu) {
  const PalletConfig config = test::pallet({test::carton(0.0, 0.0, 0.15)});
  auto scene = build_scene(config, {}, test::constant_friction(mu));
  if (!scene) qFatal("scene: %s", to_string(scene.diagnostics[0]).c_str());
  auto out = std::make_unique<Settled>();
  out->scene = std::make_unique<Scene>(std::move(*scene.value));
  auto sim = Simulator::create(*out->scene);
  if (!sim) qFatal("simulator");
  auto rest = sim.value->settle();
  if (!rest) qFatal("settle: %s", to_string(rest.diagnostics[0]).c_str());
  out->rest = std::move(*rest.value);
  return out;
}

// The start-up acceleration at which a carton with friction mu slides exactly 5 cm in the
// bisection's start-up probe (ramp 2/a s to 2 m/s, then hold): closed form, bisected.
double slide_onset(double mu_g) {
  auto slide = [&](double a) {
    const double t = 2.0 / a, lag = (a - mu_g) * t;
    return a <= mu_g ? 0.0 : 0.5 * (a - mu_g) * t * t + lag * lag / (2.0 * mu_g);
  };
  double lo = mu_g, hi = 50.0;
  while (hi - lo > 1e-9) ((slide(0.5 * (lo + hi)) > 0.05) ? hi : lo) = 0.5 * (lo + hi);
  return hi;
}

}  // namespace

class UncertaintyTest : public QObject {
  Q_OBJECT

 private slots:
  void wilsonInterval() {
    auto [lo, hi] = wilson_interval(50, 100);
    QVERIFY(std::abs(lo - 0.4038) < 1e-3 && std::abs(hi - 0.5962) < 1e-3);
    auto [z0, z1] = wilson_interval(0, 20);
    QCOMPARE(z0, 0.0);
    QVERIFY(std::abs(z1 - 0.1611) < 1e-3);
  }

  void badOptionsNameTheField() {
    auto s = settle({1.0, 0.3, 0.4});
    UncertaintyOptions o;
    o.samples = 0;
    auto r = failure_probability(*s->scene, s->rest, {accel_probe_profile(1.0, {})}, o);
    QVERIFY(!r);
    QCOMPARE(r.diagnostics[0].pointer, std::string("/samples"));
    o = {};
    o.spread.friction_sigma = -0.1;
    r = failure_probability(*s->scene, s->rest, {accel_probe_profile(1.0, {})}, o);
    QVERIFY(!r);
    QCOMPARE(r.diagnostics[0].pointer, std::string("/spread/friction_sigma"));
  }

  // A carton whose slide onset (mu = 0.3) sits exactly at the operating point fails about half
  // the time when mu varies by a lognormal 10 %; far below and above, never and always.
  void onsetAtTheOperatingPointFailsHalfTheTime() {
    const test::ConstantMu mu{1.0, 0.3, 0.4};
    auto s = settle(mu);
    const double onset = slide_onset(mu.item_pallet * kGravity);
    UncertaintyOptions o;
    o.samples = 64;
    o.seed = 7;
    auto at = failure_probability(*s->scene, s->rest, {accel_probe_profile(onset, {})}, o);
    QVERIFY2(at, at ? "" : to_string(at.diagnostics[0]).c_str());
    qInfo("onset %.3f m/s^2: p_fail %.3f [%.3f, %.3f], %d sims in %.0f ms", onset, at->p_fail,
          at->ci_low, at->ci_high, at->sims, at->wall_ms);
    QCOMPARE(at->unstable, 0);
    QVERIFY(at->ci_low < 0.5 && at->ci_high > 0.5);
    QVERIFY(at->p_fail > 0.25 && at->p_fail < 0.75);
    QCOMPARE(at->modes.size(), std::size_t(1));
    QCOMPARE(at->modes.begin()->first, FailureMode::top_item_slide);
    // mu g = 2.94: 1.5 m/s^2 is 4 sigma below the onset, 4.5 m/s^2 far above.
    o.samples = 16;
    auto low = failure_probability(*s->scene, s->rest, {accel_probe_profile(1.5, {})}, o);
    auto high = failure_probability(*s->scene, s->rest, {accel_probe_profile(4.5, {})}, o);
    QVERIFY(low && high);
    QCOMPARE(low->failures, 0);
    QCOMPARE(high->failures, 16);
    QVERIFY(low->ci_high < 0.25);
  }

  void reproducibleBySeedAtAnyThreadCount() {
    auto s = settle({1.0, 0.3, 0.4});
    const double onset = slide_onset(0.3 * kGravity);
    UncertaintyOptions o;
    o.samples = 24;
    o.seed = 11;
    o.threads = 1;
    auto a = failure_probability(*s->scene, s->rest, {accel_probe_profile(onset, {})}, o);
    o.threads = 2;
    auto b = failure_probability(*s->scene, s->rest, {accel_probe_profile(onset, {})}, o);
    o.seed = 12;
    auto c = failure_probability(*s->scene, s->rest, {accel_probe_profile(onset, {})}, o);
    QVERIFY(a && b && c);
    QCOMPARE(a->failures, b->failures);
    QCOMPARE(a->modes, b->modes);
    qInfo("seed 11: %d/24, seed 12: %d/24", a->failures, c->failures);
    QVERIFY(a->failures > 0 && a->failures < 24);
  }

  // The analyzer's confidence: off by default (null, no extra simulations); with M samples it is
  // 1 - p_fail of the reported limits and costs 4 M simulations more.
  void analyzerConfidenceIsOptIn() {
    const FrictionModel friction = test::constant_friction({1.0, 0.3, 0.4});
    const PalletConfig config = test::pallet({test::carton(0.0, 0.0, 0.15)});
    AnalyzerOptions options;
    options.fidelity = Fidelity::full;
    Analyzer plain(options, friction);
    auto base = plain.analyze(config);
    QVERIFY2(base, base ? "" : to_string(base.diagnostics[0]).c_str());
    QVERIFY(!base->confidence);
    QVERIFY(safety_result_to_json(*base)["confidence"].is_null());
    options.confidence.samples = 8;
    Analyzer with(options, friction);
    auto env = with.envelope(config);
    QVERIFY(env);
    const SafetyResult& r = env->result;
    QCOMPARE(r.verdict, Verdict::ok);
    QCOMPARE(r.max_accel_mps2, base->max_accel_mps2);
    QCOMPARE(r.sims_run, base->sims_run + 4 * 8);
    QVERIFY(r.confidence && *r.confidence >= 0.0 && *r.confidence <= 1.0);
    // Recompute it: the same seed gives the same samples.
    auto again = limits_confidence(*with.prepare(config).value.value()->scene, *env, options.line,
                                   options.search, options.confidence);
    QVERIFY(again);
    QCOMPARE(*r.confidence, 1.0 - again->p_fail);
    // The reason says it in a sentence a supervisor reads: how many copies failed, the score, and
    // below 0.5 to run below the limits. Without the estimate the sentence is absent.
    const std::string sentence = " At these limits " + std::to_string(again->failures) +
                                 " of 8 copies of the load with friction and masses varied (10 % " +
                                 "and 5 %) fail: confidence " + fixed(*r.confidence, 2) + ".";
    QVERIFY2(r.reason.find(sentence) != std::string::npos, r.reason.c_str());
    QCOMPARE(r.reason.find("Run this pallet below") != std::string::npos, *r.confidence < 0.5);
    QCOMPARE(base->reason + sentence +
                 (*r.confidence < 0.5 ? " Run this pallet below its limits, not at them." : ""),
             r.reason);
    qInfo(
        "carton: limits accel %.2f decel %.2f lateral %.2f speed %.2f; confidence %.3f [%d of "
        "8 samples fail; modes %d]",
        r.max_accel_mps2, r.max_decel_mps2, r.max_lateral_g, r.max_speed_mps, *r.confidence,
        again->failures, int(again->modes.size()));
  }
};

QTEST_APPLESS_MAIN(UncertaintyTest)
#include "uncertainty_test.moc"
