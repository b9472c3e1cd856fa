// SPDX-License-Identifier: MIT
#include "core/base/pose.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace pb {

namespace {

// Below this angle between two orientations (rad), slerp's weights sin((1 - s) theta) / sin theta
// and sin(s theta) / sin theta equal 1 - s and s to within theta^2 / 6 (< 1e-12): blend linearly.
constexpr double kNearlyEqualAngle = 1e-6;

Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

double norm4(const Quat& q) {
  return std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
}

Quat normalised(const Quat& q) {
  const double n = norm4(q);
  return {q[0] / n, q[1] / n, q[2] / n, q[3] / n};
}

// Weighted sum wa * a + wb * b of two quaternions, normalised.
Quat blend(const Quat& a, double wa, const Quat& b, double wb) {
  return normalised(
      {wa * a[0] + wb * b[0], wa * a[1] + wb * b[1], wa * a[2] + wb * b[2], wa * a[3] + wb * b[3]});
}

Quat slerp(const Quat& a, Quat b, double s) {
  if (a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3] < 0.0) {
    for (double& c : b) c = -c;  // q and -q are the same rotation: take the shorter arc
  }
  // The angle between a and b on the unit sphere; atan2 keeps it accurate when they nearly agree,
  // where acos(a . b) loses half the digits.
  const Quat diff{a[0] - b[0], a[1] - b[1], a[2] - b[2], a[3] - b[3]};
  const Quat sum{a[0] + b[0], a[1] + b[1], a[2] + b[2], a[3] + b[3]};
  const double theta = 2.0 * std::atan2(norm4(diff), norm4(sum));
  if (theta < kNearlyEqualAngle) return blend(a, 1.0 - s, b, s);
  const double sin_theta = std::sin(theta);
  return blend(a, std::sin((1.0 - s) * theta) / sin_theta, b, std::sin(s * theta) / sin_theta);
}

}  // namespace

Vec3 rotate(const Quat& q, const Vec3& v) {
  // v' = v + 2w (u x v) + 2 u x (u x v), u the vector part of q.
  const Vec3 u{q[1], q[2], q[3]};
  const Vec3 uv = cross(u, v);
  const Vec3 uuv = cross(u, uv);
  return {v[0] + 2.0 * (q[0] * uv[0] + uuv[0]), v[1] + 2.0 * (q[0] * uv[1] + uuv[1]),
          v[2] + 2.0 * (q[0] * uv[2] + uuv[2])};
}

Vec3 rotate_inverse(const Quat& q, const Vec3& v) {
  return rotate({q[0], -q[1], -q[2], -q[3]}, v);
}

Vec3 to_frame(const Pose& frame, const Vec3& p) {
  return rotate_inverse(frame.quat,
                        {p[0] - frame.pos[0], p[1] - frame.pos[1], p[2] - frame.pos[2]});
}

double tilt_deg(const Quat& q) {
  // The body's +Z in world coordinates has z component R_zz = 1 - 2 (x^2 + y^2) for a unit q.
  const double cos_tilt = std::clamp(1.0 - 2.0 * (q[1] * q[1] + q[2] * q[2]), -1.0, 1.0);
  return std::acos(cos_tilt) * 180.0 / std::numbers::pi;
}

Pose interpolate(const Pose& a, const Pose& b, double s) {
  if (s <= 0.0) return a;
  if (s >= 1.0) return b;
  Pose out;
  for (std::size_t k = 0; k < 3; ++k) out.pos[k] = a.pos[k] + s * (b.pos[k] - a.pos[k]);
  out.quat = slerp(a.quat, b.quat, s);
  return out;
}

}  // namespace pb
