// SPDX-License-Identifier: MIT
// A belt-velocity command over time, along the belt (X) and across it (Y, for curves).
#pragma once

#include <vector>

#include "core/base/diagnostic.hpp"
#include "core/base/enums.hpp"

namespace pb {

/// Shapes. The first three are the reference's; the rest are ours.
///  - accel_hold: from rest, ramp to target at `accel_mps2`, then hold.
///  - constant:   target speed from t = 0 (a worst-case step).
///  - ramp_decel: ramp up as accel_hold, hold, and from `decel_start_s` ramp down to 0 at
///                `accel_mps2`.
///  - estop:      the load already rides at target speed; from `decel_start_s` the belt stops at
///                `decel_mps2` (a controlled or emergency stop).
///  - curve:      the load rides at target speed; from `curve_start_s`, for the time the arc of
///                `curve_angle_deg` at `curve_radius_m` takes at that speed, the belt accelerates
///                sideways at v^2 / r (the centripetal acceleration, in a frame that does not turn
///                with the belt), towards +Y in a left turn (`curve_turn`), -Y in a right one.
///  - eumos:      from rest, the belt's acceleration rises linearly to `eumos_g` * g within 50 ms
///                and is held for `eumos_hold_s` (>= 0.3 s, EUMOS 40509's test pulse); then the
///                speed holds.
struct ConveyorProfile {
  double target_speed_mps = 0.5;  ///< [0, 5]
  double accel_mps2 = 0.5;        ///< (0, 10]
  double duration_s = 5.0;        ///< (0, 30]; absent from a document: default_duration_s
  ProfileShape shape = ProfileShape::accel_hold;
  double decel_start_s = 3.0;  ///< >= 0; ramp_decel and estop
  // Our additions.
  double decel_mps2 = 2.0;                 ///< (0, 20]; estop
  double curve_radius_m = 3.0;             ///< (0, 1000]; curve
  double curve_angle_deg = 90.0;           ///< (0, 360]; curve
  double curve_start_s = 0.1;              ///< >= 0; curve
  CurveTurn curve_turn = CurveTurn::left;  ///< curve
  double eumos_g = 0.5;                    ///< (0, 2]; eumos
  double eumos_hold_s = 0.3;               ///< [0.3, 10]; eumos

  /// Commanded belt velocity along X at time t (for t <= 0: the initial speed).
  double velocity_at(double t) const;
  /// Commanded belt velocity along Y (non-zero only for curve).
  double lateral_velocity_at(double t) const;
  /// How fast the belt, and a load riding it, turns about Z during the step that starts at t:
  /// v / r during a curve's arc (positive in a left turn), 0 otherwise. Its frame turns with it
  /// (physics/turning_frame.hpp).
  double yaw_rate_at(double t) const;
  /// The speed the load already has at t = 0 (estop and curve start at speed, riding along).
  double initial_speed_mps() const;
  /// Times in (0, duration_s) where the commanded acceleration changes, sorted: between two of
  /// them (and after the last) the belt's acceleration is constant.
  std::vector<double> breakpoints() const;
  /// When the commanded acceleration last changes, within the run or after it (0 if never): a run
  /// that ends before it ends with the belt still changing its motion.
  double motion_end_s() const;
  /// Lateral acceleration of a curve (v^2 / r), 0 for other shapes.
  double lateral_accel_mps2() const;

  bool operator==(const ConveyorProfile&) const = default;
};

/// The longest run a profile may ask for, s.
inline constexpr double kMaxProfileDurationS = 30.0;

/// How long a profile that names no duration runs: the reference's 5 s, or, for a motion that
/// changes later, until its last change plus a second for the load to settle into it (at most
/// kMaxProfileDurationS). The JSON reader and the CLI's flags both default to it.
double default_duration_s(const ConveyorProfile& profile);

/// Range checks, with pointers below `pointer_prefix` (e.g. "/profile").
Diagnostics validate_profile(const ConveyorProfile& profile,
                             const std::string& pointer_prefix = "");

}  // namespace pb
