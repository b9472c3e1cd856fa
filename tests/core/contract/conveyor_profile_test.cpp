// SPDX-License-Identifier: MIT
#include "core/contract/conveyor_profile.hpp"

#include <QtTest>
#include <cmath>
#include <functional>
#include <numbers>

using namespace pb;

namespace {

ConveyorProfile profile(ProfileShape shape, double speed, double accel, double decel_start = 3.0) {
  ConveyorProfile p;
  p.shape = shape;
  p.target_speed_mps = speed;
  p.accel_mps2 = accel;
  p.decel_start_s = decel_start;
  return p;
}

QList<double> q(const std::vector<double>& values) {
  return QList<double>(values.begin(), values.end());
}

QStringList pointers(const Diagnostics& diagnostics) {
  QStringList out;
  for (const auto& d : diagnostics) out << QString::fromStdString(d.pointer);
  return out;
}

}  // namespace

class ConveyorProfileTest : public QObject {
  Q_OBJECT

 private slots:
  void defaultsAreTheReference() {
    const ConveyorProfile p;
    QCOMPARE(p.target_speed_mps, 0.5);
    QCOMPARE(p.accel_mps2, 0.5);
    QCOMPARE(p.duration_s, 5.0);
    QCOMPARE(p.shape, ProfileShape::accel_hold);
    QCOMPARE(p.decel_start_s, 3.0);
    QCOMPARE(p.decel_mps2, 2.0);
    QCOMPARE(p.curve_radius_m, 3.0);
    QCOMPARE(p.curve_angle_deg, 90.0);
    QCOMPARE(p.curve_start_s, 0.1);
    QCOMPARE(p.eumos_g, 0.5);
    QCOMPARE(p.eumos_hold_s, 0.3);
    QVERIFY(validate_profile(p).empty());
  }

  void accelHoldRampsThenHolds() {
    const ConveyorProfile p = profile(ProfileShape::accel_hold, 1.0, 0.5);  // ramp ends at 2 s
    QCOMPARE(p.velocity_at(-1.0), 0.0);
    QCOMPARE(p.velocity_at(0.0), 0.0);
    QCOMPARE(p.velocity_at(0.5), 0.25);
    QCOMPARE(p.velocity_at(1.999), 0.9995);
    QCOMPARE(p.velocity_at(2.0), 1.0);
    QCOMPARE(p.velocity_at(3.5), 1.0);  // no deceleration in this shape
    QCOMPARE(p.velocity_at(30.0), 1.0);
  }

  void constantIsAStep() {
    const ConveyorProfile p = profile(ProfileShape::constant, 0.8, 0.5);
    QCOMPARE(p.velocity_at(-0.1), 0.0);
    QCOMPARE(p.velocity_at(0.0), 0.0);
    QCOMPARE(p.velocity_at(1e-6), 0.8);
    QCOMPARE(p.velocity_at(10.0), 0.8);
  }

  void rampDecelRampsHoldsAndStops() {
    const ConveyorProfile p = profile(ProfileShape::ramp_decel, 1.0, 0.5, 3.0);
    QCOMPARE(p.velocity_at(0.0), 0.0);
    QCOMPARE(p.velocity_at(1.0), 0.5);
    QCOMPARE(p.velocity_at(2.0), 1.0);
    QCOMPARE(p.velocity_at(2.9), 1.0);
    QCOMPARE(p.velocity_at(3.0), 1.0);  // deceleration starts here
    QCOMPARE(p.velocity_at(4.0), 0.5);
    QCOMPARE(p.velocity_at(5.0), 0.0);
    for (double t = 5.0; t < 30.0; t += 0.25) QCOMPARE(p.velocity_at(t), 0.0);  // never negative
  }

  void estopStopsFromSpeed() {
    ConveyorProfile p = profile(ProfileShape::estop, 2.0, 0.5, 1.0);
    p.decel_mps2 = 4.0;
    QCOMPARE(p.initial_speed_mps(), 2.0);
    QCOMPARE(p.velocity_at(-1.0), 2.0);  // already riding at speed
    QCOMPARE(p.velocity_at(0.0), 2.0);
    QCOMPARE(p.velocity_at(1.0), 2.0);
    QCOMPARE(p.velocity_at(1.25), 1.0);
    QCOMPARE(p.velocity_at(1.5), 0.0);
    QCOMPARE(p.velocity_at(4.0), 0.0);  // never negative
    QCOMPARE(q(p.breakpoints()), (QList<double>{1.0, 1.5}));
    QCOMPARE(p.lateral_velocity_at(1.0), 0.0);
  }

  void curveAcceleratesSideways() {
    ConveyorProfile p = profile(ProfileShape::curve, 1.5, 0.5);
    p.curve_radius_m = 3.0;
    p.curve_angle_deg = 90.0;
    p.curve_start_s = 0.1;
    const double arc_s = std::numbers::pi;  // 3 m * pi/2 at 1.5 m/s
    QCOMPARE(p.initial_speed_mps(), 1.5);
    QCOMPARE(p.lateral_accel_mps2(), 0.75);  // v^2 / r
    QCOMPARE(p.velocity_at(0.0), 1.5);
    QCOMPARE(p.velocity_at(2.0), 1.5);
    QCOMPARE(p.lateral_velocity_at(0.0), 0.0);
    QCOMPARE(p.lateral_velocity_at(0.1), 0.0);
    QCOMPARE(p.lateral_velocity_at(1.1), 0.75);
    QCOMPARE(p.lateral_velocity_at(0.1 + arc_s), 0.75 * arc_s);
    QCOMPARE(p.lateral_velocity_at(10.0), 0.75 * arc_s);  // the arc is over
    QCOMPARE(q(p.breakpoints()), (QList<double>{0.1, 0.1 + arc_s}));
    // A right turn: the same motion towards -Y (a left one, the default, goes towards +Y).
    p.curve_turn = CurveTurn::right;
    QCOMPARE(p.lateral_velocity_at(1.1), -0.75);
    QCOMPARE(p.lateral_accel_mps2(), 0.75);
  }

  void eumosPulse() {
    ConveyorProfile p = profile(ProfileShape::eumos, 0.5, 0.5);
    p.eumos_g = 0.5;
    p.eumos_hold_s = 0.3;
    const double a = 0.5 * 9.81;
    QCOMPARE(p.initial_speed_mps(), 0.0);
    QCOMPARE(p.velocity_at(0.0), 0.0);
    QCOMPARE(p.velocity_at(0.025), 0.5 * (a / 0.05) * 0.025 * 0.025);  // jerk-limited rise
    QCOMPARE(p.velocity_at(0.05), 0.5 * a * 0.05);
    QCOMPARE(p.velocity_at(0.2), 0.5 * a * 0.05 + a * 0.15);
    QCOMPARE(p.velocity_at(0.35), 0.5 * a * 0.05 + a * 0.3);
    QCOMPARE(p.velocity_at(2.0), 0.5 * a * 0.05 + a * 0.3);  // then the speed holds
    QCOMPARE(q(p.breakpoints()), (QList<double>{0.05, 0.35}));
  }

  void breakpointsOfTheReferenceShapes() {
    ConveyorProfile p = profile(ProfileShape::accel_hold, 1.0, 0.5);
    QCOMPARE(q(p.breakpoints()), QList<double>{2.0});
    p.duration_s = 2.0;  // only times inside (0, duration)
    QVERIFY(p.breakpoints().empty());
    QVERIFY(profile(ProfileShape::constant, 1.0, 0.5).breakpoints().empty());
    p = profile(ProfileShape::ramp_decel, 1.0, 0.5, 3.0);
    p.duration_s = 10.0;
    QCOMPARE(q(p.breakpoints()), (QList<double>{2.0, 3.0, 5.0}));
    // Decel from 1 s, before the 2 s ramp ends: the belt peaks at 1.5 s (0.75 m/s), stops at 3 s.
    p.decel_start_s = 1.0;
    QCOMPARE(q(p.breakpoints()), (QList<double>{1.5, 3.0}));
    QCOMPARE(p.velocity_at(1.5), 0.75);
    QCOMPARE(p.lateral_accel_mps2(), 0.0);
    QCOMPARE(p.initial_speed_mps(), 0.0);
  }

  void zeroTargetStaysAtRest() {
    for (auto shape : {ProfileShape::accel_hold, ProfileShape::constant, ProfileShape::ramp_decel,
                       ProfileShape::estop, ProfileShape::curve}) {
      const ConveyorProfile p = profile(shape, 0.0, 0.5, 0.0);
      QCOMPARE(p.velocity_at(1.0), 0.0);
    }
  }

  void validateBounds() {
    struct Case {
      const char* name;
      std::function<void(ConveyorProfile&)> change;
      const char* pointer;  // nullptr: valid
    };
    const double nan = std::nan("");
    const std::vector<Case> cases = {
        {"speed 0", [](auto& p) { p.target_speed_mps = 0.0; }, nullptr},
        {"speed 5", [](auto& p) { p.target_speed_mps = 5.0; }, nullptr},
        {"speed negative", [](auto& p) { p.target_speed_mps = -0.01; }, "/target_speed_mps"},
        {"speed above 5", [](auto& p) { p.target_speed_mps = 5.01; }, "/target_speed_mps"},
        {"speed NaN", [nan](auto& p) { p.target_speed_mps = nan; }, "/target_speed_mps"},
        {"accel 10", [](auto& p) { p.accel_mps2 = 10.0; }, nullptr},
        {"accel 0", [](auto& p) { p.accel_mps2 = 0.0; }, "/accel_mps2"},
        {"accel above 10", [](auto& p) { p.accel_mps2 = 10.5; }, "/accel_mps2"},
        {"accel infinite", [](auto& p) { p.accel_mps2 = INFINITY; }, "/accel_mps2"},
        {"duration 30", [](auto& p) { p.duration_s = 30.0; }, nullptr},
        {"duration 0", [](auto& p) { p.duration_s = 0.0; }, "/duration_s"},
        {"duration above 30", [](auto& p) { p.duration_s = 30.1; }, "/duration_s"},
        {"decel start 0", [](auto& p) { p.decel_start_s = 0.0; }, nullptr},
        {"decel start negative", [](auto& p) { p.decel_start_s = -1.0; }, "/decel_start_s"},
        {"decel start NaN", [nan](auto& p) { p.decel_start_s = nan; }, "/decel_start_s"},
        {"decel start 30", [](auto& p) { p.decel_start_s = 30.0; }, nullptr},
        {"decel start above 30", [](auto& p) { p.decel_start_s = 30.5; }, "/decel_start_s"},
        {"decel 20", [](auto& p) { p.decel_mps2 = 20.0; }, nullptr},
        {"decel 0", [](auto& p) { p.decel_mps2 = 0.0; }, "/decel_mps2"},
        {"decel above 20", [](auto& p) { p.decel_mps2 = 20.5; }, "/decel_mps2"},
        {"radius 1000", [](auto& p) { p.curve_radius_m = 1000.0; }, nullptr},
        {"radius 0", [](auto& p) { p.curve_radius_m = 0.0; }, "/curve_radius_m"},
        {"radius above 1000", [](auto& p) { p.curve_radius_m = 1001.0; }, "/curve_radius_m"},
        {"angle 360", [](auto& p) { p.curve_angle_deg = 360.0; }, nullptr},
        {"angle 0", [](auto& p) { p.curve_angle_deg = 0.0; }, "/curve_angle_deg"},
        {"angle above 360", [](auto& p) { p.curve_angle_deg = 361.0; }, "/curve_angle_deg"},
        {"curve start 0", [](auto& p) { p.curve_start_s = 0.0; }, nullptr},
        {"curve start negative", [](auto& p) { p.curve_start_s = -0.1; }, "/curve_start_s"},
        {"curve start above 30", [](auto& p) { p.curve_start_s = 31.0; }, "/curve_start_s"},
        {"eumos 2 g", [](auto& p) { p.eumos_g = 2.0; }, nullptr},
        {"eumos 0 g", [](auto& p) { p.eumos_g = 0.0; }, "/eumos_g"},
        {"eumos above 2 g", [](auto& p) { p.eumos_g = 2.1; }, "/eumos_g"},
        {"eumos hold 0.3", [](auto& p) { p.eumos_hold_s = 0.3; }, nullptr},
        {"eumos hold 10", [](auto& p) { p.eumos_hold_s = 10.0; }, nullptr},
        {"eumos hold short", [](auto& p) { p.eumos_hold_s = 0.29; }, "/eumos_hold_s"},
        {"eumos hold above 10", [](auto& p) { p.eumos_hold_s = 10.5; }, "/eumos_hold_s"},
    };
    for (const Case& c : cases) {
      ConveyorProfile p;
      c.change(p);
      const Diagnostics d = errors_of(validate_profile(p));  // warnings: motionEndingAfterTheRun
      const QStringList expected = c.pointer ? QStringList{c.pointer} : QStringList{};
      QVERIFY2(pointers(d) == expected, c.name);
      for (const auto& diagnostic : d) QCOMPARE(diagnostic.severity, Severity::error);
    }
  }

  // A run that ends while the belt is still changing its motion (a ramp, a stop or a curve that
  // goes on past duration_s) is warned about at /duration_s; motion_end_s says when it ends.
  void motionEndingAfterTheRun() {
    ConveyorProfile ramp;  // accel_hold
    ramp.target_speed_mps = 2.0;
    ramp.accel_mps2 = 0.3;  // reaches 2 m/s at 6.67 s
    ramp.duration_s = 5.0;
    QCOMPARE(ramp.motion_end_s(), 2.0 / 0.3);
    QVERIFY(ramp.breakpoints().empty());
    Diagnostics d = validate_profile(ramp);
    QCOMPARE(d.size(), std::size_t(1));
    QCOMPARE(d[0].severity, Severity::warning);
    QCOMPARE(d[0].pointer, std::string("/duration_s"));
    ramp.duration_s = 7.0;
    QVERIFY(validate_profile(ramp).empty());
    ConveyorProfile curve;
    curve.shape = ProfileShape::curve;
    curve.target_speed_mps = 1.5;
    curve.curve_radius_m = 0.5;
    curve.curve_angle_deg = 300.0;  // 1.75 s of arc from 0.1 s
    curve.curve_start_s = 0.1;
    curve.duration_s = 1.5;
    QVERIFY(std::abs(curve.motion_end_s() - (0.1 + 0.5 * 300.0 * std::numbers::pi / 180.0 / 1.5)) <
            1e-12);
    QCOMPARE(warnings_of(validate_profile(curve)).size(), std::size_t(1));
    QCOMPARE(ConveyorProfile{}.motion_end_s() < ConveyorProfile{}.duration_s, true);
  }

  void validatePrefixesPointers() {
    ConveyorProfile p;
    p.accel_mps2 = 0.0;
    Diagnostics d = validate_profile(p, "/profile");
    QCOMPARE(pointers(d), QStringList{"/profile/accel_mps2"});
    // The pointer names the field; the sentence the value and what to write.
    QCOMPARE(d[0].message, std::string("0 is out of range; write a number in (0, 10] m/s^2"));

    p.target_speed_mps = 6.0;
    p.duration_s = -1.0;
    p.decel_start_s = -1.0;
    d = validate_profile(p, "/runs/2/profile");
    QCOMPARE(pointers(d),
             (QStringList{"/runs/2/profile/target_speed_mps", "/runs/2/profile/accel_mps2",
                          "/runs/2/profile/duration_s", "/runs/2/profile/decel_start_s"}));
  }
};

QTEST_APPLESS_MAIN(ConveyorProfileTest)
#include "conveyor_profile_test.moc"
