// SPDX-License-Identifier: MIT
// Pose math: rotations, frames, tilt and interpolation against rotations known in closed form.
#include "core/base/pose.hpp"

#include <QtTest>

#include <cmath>
#include <numbers>

using namespace pb;

namespace {

constexpr double kTol = 1e-12;

// Rotation by `deg` about a unit axis.
Quat axis_angle(const Vec3& axis, double deg) {
  const double half = deg * std::numbers::pi / 360.0;
  return {std::cos(half), axis[0] * std::sin(half), axis[1] * std::sin(half),
          axis[2] * std::sin(half)};
}

constexpr Vec3 kX{1, 0, 0};
constexpr Vec3 kY{0, 1, 0};
constexpr Vec3 kZ{0, 0, 1};

bool near(const Vec3& a, const Vec3& b) {
  for (std::size_t k = 0; k < 3; ++k) {
    if (std::abs(a[k] - b[k]) > kTol) return false;
  }
  return true;
}

bool near(const Quat& a, const Quat& b) {
  for (std::size_t k = 0; k < 4; ++k) {
    if (std::abs(a[k] - b[k]) > kTol) return false;
  }
  return true;
}

double norm(const Quat& q) {
  return std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
}

Quat negated(const Quat& q) {
  return {-q[0], -q[1], -q[2], -q[3]};
}

}  // namespace

class PoseTest : public QObject {
  Q_OBJECT

 private slots:
  void rotateKnownRotations() {
    QVERIFY(near(rotate(axis_angle(kZ, 90), {1, 0, 0}), {0, 1, 0}));
    QVERIFY(near(rotate(axis_angle(kX, 90), {0, 1, 0}), {0, 0, 1}));
    QVERIFY(near(rotate(axis_angle(kY, 90), {0, 0, 1}), {1, 0, 0}));
    QVERIFY(near(rotate(axis_angle(kZ, 180), {1, 2, 3}), {-1, -2, 3}));
    QVERIFY(near(rotate(Quat{1, 0, 0, 0}, {1, 2, 3}), {1, 2, 3}));
    // q and -q are the same rotation.
    QVERIFY(near(rotate(negated(axis_angle(kZ, 90)), {1, 0, 0}), {0, 1, 0}));
  }

  void rotateInverseUndoesRotate() {
    const Quat q = axis_angle({0.6, 0.0, 0.8}, 37.0);
    const Vec3 v{0.3, -1.2, 2.5};
    QVERIFY(near(rotate_inverse(q, rotate(q, v)), v));
    QVERIFY(near(rotate_inverse(axis_angle(kZ, 90), {0, 1, 0}), {1, 0, 0}));
  }

  void toFrame() {
    Pose frame;
    frame.pos = {1, 2, 0};
    frame.quat = axis_angle(kZ, 90);
    // One metre along the frame's own +X (world +Y) from its origin.
    QVERIFY(near(to_frame(frame, {1, 3, 0}), {1, 0, 0}));
    QVERIFY(near(to_frame(frame, {1, 2, 0.5}), {0, 0, 0.5}));
    QVERIFY(near(to_frame(Pose{}, {4, 5, 6}), {4, 5, 6}));
  }

  void tilt() {
    QCOMPARE(tilt_deg(Quat{1, 0, 0, 0}), 0.0);
    QVERIFY(std::abs(tilt_deg(axis_angle(kX, 10)) - 10.0) < 1e-9);
    QVERIFY(std::abs(tilt_deg(axis_angle(kY, -25)) - 25.0) < 1e-9);
    QVERIFY(std::abs(tilt_deg(axis_angle(kX, 180)) - 180.0) < 1e-9);
    QVERIFY(std::abs(tilt_deg(negated(axis_angle(kX, 10))) - 10.0) < 1e-9);
    // A yaw does not tilt.
    QVERIFY(std::abs(tilt_deg(axis_angle(kZ, 75))) < 1e-6);
    // 10 deg about a horizontal axis at 45 deg between X and Y.
    QVERIFY(std::abs(tilt_deg(axis_angle({std::sqrt(0.5), std::sqrt(0.5), 0}, 10)) - 10.0) < 1e-9);
  }

  void tiltClampsRoundingOffUnitLength() {
    // A quaternion a hair longer than 1 would give cos < -1 without the clamp (NaN from acos).
    QCOMPARE(tilt_deg(Quat{0, 1.0 + 1e-12, 0, 0}), 180.0);
  }

  void interpolatePositionsLinearly() {
    Pose a;
    a.pos = {0, 0, 1};
    Pose b;
    b.pos = {2, -4, 1};
    const Pose mid = interpolate(a, b, 0.25);
    QVERIFY(near(mid.pos, {0.5, -1, 1}));
    QVERIFY(near(mid.quat, {1, 0, 0, 0}));
  }

  void interpolateEndpointsExactly() {
    Pose a;
    a.pos = {0.1, 0.2, 0.3};
    a.quat = axis_angle(kX, 3);
    Pose b;
    b.pos = {1, 2, 3};
    b.quat = axis_angle(kZ, 50);
    QVERIFY(interpolate(a, b, 0.0) == a);
    QVERIFY(interpolate(a, b, 1.0) == b);
  }

  void slerpHalfwayIs45DegAboutZ() {
    Pose b;
    b.quat = axis_angle(kZ, 90);
    QVERIFY(near(interpolate(Pose{}, b, 0.5).quat, axis_angle(kZ, 45)));
    // Constant angular rate along the arc, not only at the midpoint.
    QVERIFY(near(interpolate(Pose{}, b, 0.2).quat, axis_angle(kZ, 18)));
  }

  void slerpTakesShortestArc() {
    // -q is q: the halfway point is 45 deg, not 135 deg the long way round.
    Pose b;
    b.quat = negated(axis_angle(kZ, 90));
    const Quat mid = interpolate(Pose{}, b, 0.5).quat;
    QVERIFY(near(mid, axis_angle(kZ, 45)));
    // Between 170 and -170 deg of yaw the short way passes through 180.
    Pose c;
    c.quat = axis_angle(kZ, 170);
    Pose d;
    d.quat = axis_angle(kZ, -170);
    const Vec3 x_axis = rotate(interpolate(c, d, 0.5).quat, {1, 0, 0});
    QVERIFY(near(x_axis, {-1, 0, 0}));
  }

  void slerpOfNearlyEqualOrientations() {
    Pose a;
    a.quat = axis_angle(kZ, 1e-7);
    Pose b;
    b.quat = axis_angle(kZ, 3e-7);
    const Quat mid = interpolate(a, b, 0.5).quat;
    QVERIFY(std::isfinite(mid[0]));
    QVERIFY(near(mid, axis_angle(kZ, 2e-7)));
    QVERIFY(std::abs(norm(mid) - 1.0) < 1e-15);
    const Quat same = interpolate(a, a, 0.5).quat;
    QVERIFY(near(same, a.quat));
  }

  void slerpOfSmallStepsKeepsConstantRate() {
    // One 2 ms step of a 30 deg/s yaw: a third of the way is 0.02 deg past the start, not a chord.
    Pose a;
    a.quat = axis_angle(kZ, 1.0);
    Pose b;
    b.quat = axis_angle(kZ, 1.06);
    const Quat q = interpolate(a, b, 1.0 / 3.0).quat;
    const Quat expected = axis_angle(kZ, 1.02);
    for (std::size_t k = 0; k < 4; ++k) QVERIFY(std::abs(q[k] - expected[k]) < 1e-15);
  }

  void interpolationIsNormalised() {
    Pose a;
    a.quat = axis_angle({0.6, 0.0, 0.8}, 30);
    Pose b;
    b.quat = axis_angle(kY, 120);
    for (const double s : {0.1, 0.3, 0.5, 0.7, 0.9}) {
      QVERIFY(std::abs(norm(interpolate(a, b, s).quat) - 1.0) < 1e-15);
    }
  }
};

QTEST_APPLESS_MAIN(PoseTest)
#include "pose_test.moc"
