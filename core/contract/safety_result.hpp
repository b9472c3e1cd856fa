// SPDX-License-Identifier: MIT
// The answer for one pallet: the conveyor motion it survives and what fails first.
#pragma once

#include <optional>
#include <string>

#include "core/base/enums.hpp"

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
  /// [0, 1]: the probability that the pallet survives every reported limit (start-up at
  /// max_accel, stop at max_decel, curve at max_lateral, the line's e-stop from max_speed) when
  /// each contact pair's friction varies lognormally (sigma 10 %) and each item's mass by
  /// N(1, 5 %), estimated from M seeded samples (core/analysis/uncertainty.hpp); 0 for a rejected
  /// pallet. Absent (JSON null) when not estimated (AnalyzerOptions::confidence.samples = 0, the
  /// default): a 0 there read as "certain to fail".
  std::optional<double> confidence;
  double sim_runtime_ms = 0.0;
  std::string config_hash;
  // Ours.
  int sims_run = 0;
  FailureMode accel_mode = FailureMode::no_failure;  ///< what fails just above each limit
  FailureMode decel_mode = FailureMode::no_failure;
  FailureMode lateral_mode = FailureMode::no_failure;
  FailureMode speed_mode = FailureMode::no_failure;
  /// Each axis's top_item_slide (the reference's word for any item moving 5 cm) where the item
  /// tipped over rather than slid: what the reason's "an item tips over" says, for a machine.
  bool accel_item_tipped = false;
  bool decel_item_tipped = false;
  bool lateral_item_tipped = false;
  bool speed_item_tipped = false;
  /// Each axis's top_item_slide where the whole load slid on its pallet together (its cartons
  /// grip the pallet less than the pallet grips its belt): "the load slides on its pallet".
  bool accel_load_as_one = false;
  bool decel_load_as_one = false;
  bool lateral_load_as_one = false;
  bool speed_load_as_one = false;
  /// How the dominant_failure_mode went where it is a top_item_slide (the tightest axis's
  /// *_item_tipped, *_load_as_one as one value); item_slid otherwise.
  SlideKind dominant_slide = SlideKind::item_slid;
  SpeedGovernor speed_governed_by = SpeedGovernor::unset;
  Verdict verdict = Verdict::ok;       ///< reject: unsafe at any motion, or it cannot stand
  std::string reason;                  ///< one sentence a supervisor reads
  double line_estop_decel_mps2 = 0.0;  ///< the line description the speed was derived from
  double line_curve_radius_m = 0.0;
  Fidelity fidelity = Fidelity::full;  ///< the model level that produced the result

  bool operator==(const SafetyResult&) const = default;
};

}  // namespace pb
