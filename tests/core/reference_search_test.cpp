// SPDX-License-Identifier: MIT
#include "core/reference_search.hpp"

#include <QtTest>
#include <cmath>

#include "test_friction.hpp"
#include "test_pallets.hpp"

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
    double lo = mu_g, hi = 20.0;
    while (hi - lo > 1e-9) {
      const double mid = 0.5 * (lo + hi);
      (slide(mid, 1.0 / mid, mu_g) > DetectorThresholds{}.item_slide_m ? hi : lo) = mid;
    }
    QVERIFY2(r->max_accel_mps2 <= hi + 0.02 && r->max_accel_mps2 >= hi - 0.2 - 0.02,
             qPrintable(QString("found %1, closed form %2").arg(r->max_accel_mps2).arg(hi)));
    QCOMPARE(r->sims, 1 + 2 + 5);
    QVERIFY(r->wall_ms > 0.0);
  }

  // Its numerics are the reference system's: the full model at 2 ms, no early stop.
  void runsTheReferenceNumerics() {
    const AnalyzerOptions o = reference_search_options();
    QCOMPARE(o.fidelity, Fidelity::full);
    QCOMPARE(o.scene.timestep_s, 0.002);
    QVERIFY(!o.full_model_timestep_s);
    QVERIFY(!o.sim.early_stop && !o.sim.skip_comoving);
  }
};

QTEST_APPLESS_MAIN(ReferenceSearchTest)
#include "reference_search_test.moc"
