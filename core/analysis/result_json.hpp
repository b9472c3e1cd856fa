// SPDX-License-Identifier: MIT
// The JSON of the core's answers, one writer for every client (the CLI, the service): diagnostics,
// a validation report, a simulation's outcome, a search's probes, a failure map. The contract's
// own types (pallet, profile, SafetyResult, replay) are written by json_io.hpp and replay.hpp.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "core/analysis/envelope.hpp"
#include "core/analysis/failure_map.hpp"
#include "core/base/diagnostic.hpp"
#include "core/contract/conveyor_profile.hpp"
#include "core/contract/json_io.hpp"
#include "core/contract/pallet_config.hpp"
#include "core/inputs/validation.hpp"
#include "core/physics/detectors.hpp"
#include "core/physics/simulate.hpp"

namespace pb {

/// [{"pointer", "message"}, ...] in their order.
Json diagnostics_to_json(const Diagnostics& diagnostics);

/// Validation of one pallet with the recomputed summary a supervisor checks first: "valid",
/// "errors", "warnings", "pallet_id", "items", "total_mass_kg", "composite_com_m",
/// "stack_height_m", "overhang_m", "min_support_fraction". The last compares items pairwise: for
/// a pallet over `max_items` (which validation refused before any other check) it is null.
Json validation_report_to_json(const PalletConfig& config, const Diagnostics& diagnostics,
                               std::size_t max_items = ValidationLimits{}.max_items);

/// replay.hpp's failure_to_json with a "description".
Json failure_event_to_json(const std::optional<FailureEvent>& failure);

/// One simulation of `profile`: "outcome", "failure", "reason" (unstable only), "aftermath_cut"
/// (only when a failure's aftermath ended early, and why), "peak_ratio" and "load_peak_ratio"
/// (how near it came to failing: the largest detector reading over its threshold, of every
/// detector and of the load's own, without the pallet's slip on its belt), "steps",
/// "steps_skipped", "skipped_s", "sim_time_s", "stopped_early", "wall_ms", "profile".
Json sim_result_to_json(const SimResult& sim, const ConveyorProfile& profile);

/// Every probe of a search: {"axis", "value", "outcome", "mode", "failure_time_s" (null unless
/// failed), "sim_time_s", "steps", "wall_ms"}.
Json probes_to_json(const std::vector<Probe>& probes);

/// The line an answer was computed for and the range its limits were searched in (the console's
/// dials and the failure map span the same one): {"estop_decel_mps2", "curve_radius_m",
/// "curve_angle_deg", "range": {"speed_mps": [min, max], "accel_mps2", "decel_mps2",
/// "lateral_g"}}. A limit at the top of its range means nothing failed up to it.
Json line_to_json(const LineDescription& line, const SearchConfig& search);

/// A failure map: "speeds_mps", "accels_mps2", "cells" (a row per acceleration, a cell per speed:
/// {"outcome", "mode", "failure_time_s", "decided_by", "non_monotone", "reason"?}), "line_cells",
/// the derived "envelope", "unstable_cells", "non_monotone_cells", "sims", "threads", "wall_ms".
Json failure_map_to_json(const FailureMap& map);

}  // namespace pb
