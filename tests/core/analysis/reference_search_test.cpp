// SPDX-License-Identifier: MIT
#include "core/analysis/reference_search.hpp"

#include <QtTest>
#include <cmath>

#include "tests/core/test_friction.hpp"
#include "tests/core/test_pallets.hpp"

using namespace pb;

namespace {

constexpr double g = kGravity;

// Coulomb slide of a carton of onset mu g left behind by a belt ramping at a for T seconds: it
// lags at a - mu g during the ramp and catches up at mu g after it.
double slide(double a, double t, double mu_g) {
  if (a <= mu_g) return 0.0;
  const double lag = (a - mu_g) * t;
  return 0.5 * lag * t + lag * lag / (2.0 * mu_g);
}

// Where `slides(x)` (increasing in x) first reaches the 5 cm detector of an item on the deck.
template <class F>
double closed_form_threshold(double lo, double hi, const F& slides) {
  while (hi - lo > 1e-9) {
    const double mid = 0.5 * (lo + hi);
    (slides(mid) > DetectorThresholds{}.item_slide_m ? hi : lo) = mid;
  }
  return hi;
}

// Probes of one plain bisection that fails at its top and holds at its floor: those two, then
// one per halving until the bracket is within the precision.
int bisection_probes(double lo, double hi, double precision) {
  return 2 + static_cast<int>(std::ceil(std::log2((hi - lo) / precision)));
}

// A limit found by bisection is the last safe grid point: at most one precision below the
// threshold, never above it (a hundredth of slack for the soft contacts' creep).
bool brackets(double found, double threshold, double precision) {
  return found <= threshold + 0.01 && found >= threshold - precision - 0.01;
}

QString why(const char* axis, double found, double threshold) {
  return QString("%1: found %2, closed form %3").arg(axis).arg(found).arg(threshold);
}

}  // namespace

class ReferenceSearchTest : public QObject {
  Q_OBJECT

 private slots:
  // One 10 kg carton, mu 0.3 on the deck, on a pallet that cannot slip: a ramp at 1 m/s^2 is
  // below mu g, so every speed is safe (the top probe settles it); the acceleration towards 1 m/s
  // fails where the Coulomb slide of the ramp (T = 1 / a) reaches the 5 cm detector. Plain
  // bisection of [0.1, 5.0] to 0.2: the top, the floor, then five halvings.
  void findsTheClosedFormThresholdsByPlainBisection() {
    const FrictionModel friction = test::constant_friction({1.0, 0.3, 0.4});
    Analyzer analyzer(reference_search_options(), friction);
    auto r = reference_search(analyzer, test::pallet({test::carton(0, 0, 0.15)}));
    QVERIFY2(r.ok(), r.ok() ? "" : r.diagnostics.front().message.c_str());
    QCOMPARE(r->max_speed_mps, 2.0);
    const double mu_g = 0.3 * g;
    const double a =
        closed_form_threshold(mu_g, 20.0, [&](double x) { return slide(x, 1 / x, mu_g); });
    QVERIFY2(brackets(r->max_accel_mps2, a, 0.2), qPrintable(why("accel", r->max_accel_mps2, a)));
    QCOMPARE(r->sims, 1 + bisection_probes(0.1, 5.0, 0.2));
    QCOMPARE(r->sims, 1 + 2 + 5);
    QVERIFY(r->wall_ms > 0.0);
  }

  // The same carton at mu 0.08 (onset 0.78 m/s^2): the 1 m/s^2 ramp of the speed axis slides it
  // by 0.137 v^2, past 5 cm from 0.60 m/s, so both axes bisect: [0.1, 2.0] to 0.1 and
  // [0.1, 5.0] to 0.2 (towards 1 m/s it fails from 0.85 m/s^2), five halvings each.
  void bisectsBothAxes() {
    const FrictionModel friction = test::constant_friction({1.0, 0.08, 0.4});
    Analyzer analyzer(reference_search_options(), friction);
    auto r = reference_search(analyzer, test::pallet({test::carton(0, 0, 0.15)}));
    QVERIFY2(r.ok(), r.ok() ? "" : r.diagnostics.front().message.c_str());
    const double mu_g = 0.08 * g;
    const double v = closed_form_threshold(0.0, 2.0, [&](double x) { return slide(1.0, x, mu_g); });
    const double a =
        closed_form_threshold(mu_g, 5.0, [&](double x) { return slide(x, 1 / x, mu_g); });
    QVERIFY2(brackets(r->max_speed_mps, v, 0.1), qPrintable(why("speed", r->max_speed_mps, v)));
    QVERIFY2(brackets(r->max_accel_mps2, a, 0.2), qPrintable(why("accel", r->max_accel_mps2, a)));
    QCOMPARE(r->sims, bisection_probes(0.1, 2.0, 0.1) + bisection_probes(0.1, 5.0, 0.2));
    QCOMPARE(r->sims, 7 + 7);
  }

  // Its numerics are the reference system's: the full model at 2 ms, no early stop.
  void runsTheReferenceNumerics() {
    const AnalyzerOptions o = reference_search_options();
    QCOMPARE(o.fidelity, Fidelity::full);
    QCOMPARE(o.scene.timestep_s, 0.002);
    QVERIFY(!o.full_model_timestep_s);
    QVERIFY(!o.full_model_solref_s);
    QVERIFY(!o.sim.early_stop && !o.sim.skip_comoving);
  }
};

QTEST_APPLESS_MAIN(ReferenceSearchTest)
#include "reference_search_test.moc"
