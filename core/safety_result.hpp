// SPDX-License-Identifier: MIT
// The answer for one pallet: the conveyor motion it survives and what fails first.
#pragma once

#include <string>

#include "core/enums.hpp"

namespace pb {

/// Reference fields first (same names and units), then ours (optional in JSON, with defaults).
struct SafetyResult {
  std::string pallet_id;
  double max_speed_mps = 0.0;   ///< the speed the line's stops and curves allow
  double max_accel_mps2 = 0.0;  ///< start-up, measured
  double max_decel_mps2 = 0.0;  ///< controlled or emergency stop, measured
  double max_lateral_g = 0.0;   ///< curves, measured
  FailureMode dominant_failure_mode = FailureMode::no_failure;
  double margin_pct = 0.0;  ///< [0, 100]: the tightest limit's place in its search range
  double confidence = 0.0;  ///< [0, 1]
  double sim_runtime_ms = 0.0;
  std::string config_hash;
  // Ours.
  int sims_run = 0;
  FailureMode accel_mode = FailureMode::no_failure;  ///< what fails just above each limit
  FailureMode decel_mode = FailureMode::no_failure;
  FailureMode lateral_mode = FailureMode::no_failure;
  FailureMode speed_mode = FailureMode::no_failure;
  std::string speed_governed_by;       ///< "estop", "curve", "ceiling" or "reject"
  std::string verdict = "ok";          ///< "ok", or "reject": unsafe at any motion
  std::string reason;                  ///< one sentence a supervisor reads
  double line_estop_decel_mps2 = 0.0;  ///< the line description the speed was derived from
  double line_curve_radius_m = 0.0;
  std::string fidelity = "full";  ///< the model level that produced the result

  bool operator==(const SafetyResult&) const = default;
};

}  // namespace pb
