// SPDX-License-Identifier: MIT
// A curve turns the load (turning_frame.hpp), checked against closed-form mechanics on a 1 m curve:
// a carton 0.3 m outboard of the centre line feels 1.3 times the centre line's v^2 / r, one 0.3 m
// inboard 0.7 times, one also 0.4 m ahead of the centre |(1.3, 0.4)| = 1.36 times; and a carton
// sliding outboard is turned backwards (Coriolis).
#include "core/physics/turning_frame.hpp"

#include <QtTest>

#include <cmath>
#include <numbers>
#include <string>

#include "core/physics/quasi_static.hpp"
#include "core/physics/simulate.hpp"
#include "tests/core/test_friction.hpp"
#include "tests/core/test_pallets.hpp"
#include "tests/core/test_rig.hpp"

using namespace pb;

namespace {

constexpr double kG = kGravity;
constexpr double kRadius = 1.0;
constexpr double kDeck = 0.15;
const test::ConstantMu kGrip{1.0, 0.4, 0.4, 1.0};  // carton on the deck: mu 0.4, one coefficient

using test::Rig;

Rig settled(const Item& item) {
  return test::settled_rig(test::pallet({item}), test::constant_friction(kGrip));
}

// A 1.5 s arc of the 1 m curve at the speed that gives `lateral_g` on the centre line.
ConveyorProfile curve(double lateral_g, CurveTurn turn) {
  ConveyorProfile p;
  p.shape = ProfileShape::curve;
  p.curve_turn = turn;
  p.curve_radius_m = kRadius;
  p.target_speed_mps = std::sqrt(lateral_g * kG * kRadius);
  const double arc_s = 1.5;
  p.curve_angle_deg = p.target_speed_mps * arc_s / kRadius * 180.0 / std::numbers::pi;
  p.curve_start_s = 0.05;
  p.duration_s = p.curve_start_s + arc_s + 1.0;
  return p;
}

// A search's probe: detectors on, no trace.
SimResult run(Rig& rig, const ConveyorProfile& profile) {
  SimOptions o;
  o.record_trace = false;
  return rig.sim->run(rig.rest, profile, o);
}

// Holds at 0.9 of `onset_g` (the centre line's lateral acceleration at which closed form says it
// goes) and fails at 1.1 of it.
void goesAt(const Item& item, double onset_g, CurveTurn turn) {
  Rig rig = settled(item);
  QVERIFY2(rig.error.empty(), rig.error.c_str());
  const SimResult held = run(rig, curve(0.9 * onset_g, turn));
  QVERIFY2(held.outcome == Outcome::safe,
           (held.failure ? describe(*held.failure) : held.reason).c_str());
  const SimResult gone = run(rig, curve(1.1 * onset_g, turn));
  QCOMPARE(gone.outcome, Outcome::failed);
  QVERIFY(gone.failure.has_value());
  QCOMPARE(gone.failure->mode, FailureMode::top_item_slide);
}

}  // namespace

class TurningFrameTest : public QObject {
  Q_OBJECT

 private slots:
  // A 0.2 x 0.2 x 1 m carton tips at g (b/2) / h = 0.2 g of its own lateral acceleration. A left
  // turn pushes the load towards -Y: at y = -0.3 it is outboard, at (1 + 0.3) v^2 / r, and tips at
  // 0.2 / 1.3 = 0.154 g on the centre line; at y = +0.3 inboard, at 0.2 / 0.7 = 0.286 g, above the
  // centre line's 0.2 g. Its mirror image in a right turn goes where it does.
  void aTallCartonTipsAtItsOwnRadius() {
    auto tall = [](double y) { return test::carton(0.0, y, kDeck, {0.2, 0.2, 1.0}); };
    goesAt(tall(-0.3), 0.2 / 1.3, CurveTurn::left);
    goesAt(tall(0.3), 0.2 / 1.3, CurveTurn::right);
    goesAt(tall(0.3), 0.2 / 0.7, CurveTurn::left);
  }

  // A low carton (it slips before it tips) slips where the whole horizontal demand reaches mu g =
  // 0.4 g. At (0.4, -0.3) in a left turn the demand is (0.4, -1.3) times the centre line's v^2 / r
  // (the turning pushes it forward too), |(1.3, 0.4)| = 1.36: it slips at 0.294 g. MuJoCo's
  // pyramid, left along the world axes, would hold only |f_x| + |f_y| <= mu N and let it go at
  // 0.4 / 1.7 = 0.235 g; step() turns it along the demand (DemandField). The closed form's factor
  // says the same.
  void aSlipFeelsTheWholeHorizontalDemand() {
    const Item low = test::carton(0.4, -0.3, kDeck, {0.3, 0.2, 0.2});
    QuasiStaticLimit slip;
    slip.mechanism = Mechanism::item_slip_on_deck;
    slip.offset_x_m = 0.4;
    slip.offset_y_m = -0.3;
    const double factor = std::hypot(1.3, 0.4);
    QVERIFY(std::abs(curve_demand_factor(slip, kRadius) - factor) < 1e-12);
    goesAt(low, 0.4 / factor, CurveTurn::left);
  }

  // Sliding outboard (towards -Y in a left turn) at v, the carton is turned by -2 omega z x v:
  // backwards, against the belt's travel. Without the turning it would slide straight across (it
  // starts on the centre line along X, where the centrifugal push along X is nil). Measured when
  // it has slid 0.1 m across: at 1.5 times its onset it lags at 0.2 g, so ~0.3 s in, at ~0.6 m/s,
  // on a curve turning at 2.1 rad/s.
  void aSlideOutboardIsTurnedBackwards() {
    Rig rig = settled(test::carton(0.0, -0.3, kDeck, {0.3, 0.2, 0.2}));
    QVERIFY2(rig.error.empty(), rig.error.c_str());
    const SimResult r =
        rig.sim->run(rig.rest, curve(1.5 * 0.4 / 1.3, CurveTurn::left), test::every_step());
    const Vec3 start = to_frame(rig.rest.pallet, rig.rest.items[0].pos);
    for (std::size_t k = 0; k < r.trace.size(); ++k) {
      const Vec3 now = to_frame(r.trace.pallet(k), r.trace.items(k)[0].pos);
      const double across = now[1] - start[1], along = now[0] - start[0];
      if (across > -0.1) continue;
      qInfo("0.1 m across at t = %.3f s: %.4f m along", r.trace.time(k), along);
      QVERIFY(along < -0.005);
      return;
    }
    QFAIL("the carton never slid 0.1 m across");
  }
};

QTEST_APPLESS_MAIN(TurningFrameTest)
#include "turning_frame_test.moc"
