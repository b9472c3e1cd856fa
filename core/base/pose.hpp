// SPDX-License-Identifier: MIT
// A rigid body's pose in the world: position and a unit quaternion (w, x, y, z, MuJoCo's order).
#pragma once

#include <array>

#include "core/base/vec3.hpp"

namespace pb {

using Quat = std::array<double, 4>;  ///< (w, x, y, z)

struct Pose {
  Vec3 pos{0.0, 0.0, 0.0};
  Quat quat{1.0, 0.0, 0.0, 0.0};

  bool operator==(const Pose&) const = default;
};

/// Rotates v by q.
Vec3 rotate(const Quat& q, const Vec3& v);
/// Rotates v by the inverse of q.
Vec3 rotate_inverse(const Quat& q, const Vec3& v);
/// `p` expressed in the frame of `frame`: R^T (p - frame.pos).
Vec3 to_frame(const Pose& frame, const Vec3& p);
/// Angle in degrees between the body's +Z axis and the world's +Z axis.
double tilt_deg(const Quat& q);
/// Linear interpolation of positions and spherical interpolation (shortest arc) of orientations,
/// s in [0, 1].
Pose interpolate(const Pose& a, const Pose& b, double s);

}  // namespace pb
