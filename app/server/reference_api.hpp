// SPDX-License-Identifier: MIT
// The reference system's response shapes (its FastAPI models), written from our types, so that a
// client written for it works unchanged against this service. Ours add fields; none are renamed.
#pragma once

#include <string>
#include <vector>

#include "app/server/analysis_pool.hpp"
#include "core/analysis/analyzer.hpp"
#include "core/contract/json_io.hpp"
#include "core/inputs/catalog.hpp"
#include "core/inputs/friction.hpp"
#include "core/inputs/scenario.hpp"

namespace pb::server {

/// ScenarioSummary: slug, name, tag, description, expected_failure, item_count, total_mass_kg,
/// stack_height_m.
Json scenario_summary_json(const Scenario& scenario);

/// SkuInfo: sku, name, weight_kg, dims_m, fragility, category, default_env.
Json sku_info_json(const SkuTemplate& sku);

/// FrictionPoint: temp_c, mu_static, mu_dynamic (effective: the frost-melt penalty applied).
Json friction_point_json(double temp_c, const FrictionValue& value);

/// SafetyAnalyzeResponse: result (our SafetyResult, reference fields first), sims_run,
/// cache_hits, sweep_points [{axis, value, safe, failure_mode}].
Json analyze_response_json(const Analysis& analysis);

/// SolveResponse: pallet_id, failure {mode, time_s, max_tip_angle_deg} (null when the run was
/// unstable: then "unstable" and "reason"), trace {times_s, conveyor_vel_mps, pallet_vel_x_mps,
/// pallet_pos_x_m, tip_angle_deg} sampled at the replay's frames, runtime_ms, n_steps_simulated,
/// replay (ReplayData: world poses of body centres, wxyz quaternions, belt displacement; null
/// unless `include_replay`); ours: outcome, fidelity.
Json solve_response_json(const PalletConfig& pallet, const Solve& solve, bool include_replay,
                         const std::string& fidelity);

}  // namespace pb::server
