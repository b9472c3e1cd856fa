// SPDX-License-Identifier: MIT
// Results in words a supervisor reads at a glance: a grade for a SafetyResult, and one sentence on
// why a run failed with the mechanics behind it ("top item slid: the start-up's 0.41 g needs
// μ 0.41, carton on carton has 0.32 at −22 °C").
#pragma once

#include <string>
#include <string_view>

#include "core/contract/conveyor_profile.hpp"
#include "core/contract/pallet_config.hpp"
#include "core/contract/safety_result.hpp"
#include "core/inputs/friction.hpp"
#include "core/physics/detectors.hpp"

namespace pb {

/// The speed a fixed table gives every pallet today (the reference's 1.0 m/s) and the start-up
/// such a line runs at; a grade says how a pallet compares with them.
inline constexpr double kTableSpeedMps = 1.0;
inline constexpr double kTableAccelMps2 = 1.0;

struct Grade {
  /// 'A' faster than the table (>= 1.5x its speed and start-up), 'B' runs at the table's speed
  /// and start-up, 'C' slower than the table on some axis, 'R' reject: no motion is safe (or, for
  /// a load that cannot stand, a build defect: "Build defect: re-stack").
  char letter = 'R';
  std::string label;  ///< "Faster than the table", "Table speed", "Slow zone", "Reject and re-wrap"
  std::string advice;  ///< what to do with the pallet, one short sentence
};
Grade grade(const SafetyResult& result);

/// The acceleration a profile demands of the load at its hardest moment (m/s^2): the start-up
/// for accel_hold / ramp_decel, the stop for estop, v^2/r for a curve, the pulse for eumos; a
/// `constant` profile is a step (infinite in principle): reported as 0 (unknown).
double peak_demand_mps2(const ConveyorProfile& profile);

/// One sentence on why `event` happened under `profile` (the pallet's friction from `model` at its
/// body temperature and time since the change). Never empty; falls back to describe(event) when
/// the mechanics cannot be named (an unknown friction pair).
std::string explain_failure(const PalletConfig& config, const ConveyorProfile& profile,
                            const FailureEvent& event,
                            const FrictionModel& model = FrictionModel::builtin());

/// "−22 °C" (a true minus sign, as a person writes it).
std::string format_temperature(double temp_c);

}  // namespace pb
