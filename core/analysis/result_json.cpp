// SPDX-License-Identifier: MIT
#include "core/analysis/result_json.hpp"

#include <algorithm>

#include "core/analysis/replay.hpp"
#include "core/contract/pallet_metrics.hpp"

namespace pb {

Json diagnostics_to_json(const Diagnostics& diagnostics) {
  Json out = Json::array();
  for (const auto& d : diagnostics) out.push_back({{"pointer", d.pointer}, {"message", d.message}});
  return out;
}

Json validation_report_to_json(const PalletConfig& config, const Diagnostics& diagnostics,
                               std::size_t max_items) {
  const bool counted = config.items.size() <= max_items;
  const auto support = counted ? support_fractions(config) : std::vector<double>{};
  Json j;
  j["valid"] = !has_errors(diagnostics);
  j["errors"] = diagnostics_to_json(errors_of(diagnostics));
  j["warnings"] = diagnostics_to_json(warnings_of(diagnostics));
  j["pallet_id"] = config.pallet_id;
  j["items"] = config.items.size();
  j["total_mass_kg"] = total_mass_kg(config);
  j["composite_com_m"] = composite_com_m(config);
  j["stack_height_m"] = stack_height_m(config);
  j["overhang_m"] = overhang_m(config);
  j["min_support_fraction"] =
      !counted ? Json(nullptr)
               : Json(support.empty() ? 1.0 : *std::min_element(support.begin(), support.end()));
  return j;
}

Json failure_event_to_json(const std::optional<FailureEvent>& failure) {
  Json j = failure_to_json(failure);
  if (failure) j["description"] = describe(*failure);
  return j;
}

Json sim_result_to_json(const SimResult& sim, const ConveyorProfile& profile) {
  Json j;
  j["outcome"] = to_string(sim.outcome);
  j["failure"] = failure_event_to_json(sim.failure);
  if (sim.outcome == Outcome::unstable) j["reason"] = sim.reason;
  if (!sim.aftermath_cut.empty()) j["aftermath_cut"] = sim.aftermath_cut;
  j["peak_ratio"] = sim.peak_ratio;
  j["load_peak_ratio"] = sim.load_peak_ratio;
  j["steps"] = sim.steps;
  j["steps_skipped"] = sim.steps_skipped;
  j["skipped_s"] = sim.skipped_s;
  j["sim_time_s"] = sim.sim_time_s;
  j["stopped_early"] = sim.stopped_early;
  j["wall_ms"] = sim.wall_ms;
  j["profile"] = profile_to_json(profile);
  return j;
}

Json line_to_json(const LineDescription& line, const SearchConfig& search) {
  return {{"estop_decel_mps2", line.estop_decel_mps2},
          {"curve_radius_m", line.curve_radius_m},
          {"curve_angle_deg", line.curve_angle_deg},
          {"range",
           {{"speed_mps", {search.speed_min_mps, search.speed_max_mps}},
            {"accel_mps2", {search.accel_min_mps2, search.accel_max_mps2}},
            {"decel_mps2", {search.decel_min_mps2, search.decel_max_mps2}},
            {"lateral_g", {search.lateral_min_g, search.lateral_max_g}}}}};
}

Json probes_to_json(const std::vector<Probe>& probes) {
  Json out = Json::array();
  for (const auto& p : probes) {
    Json& probe = out.emplace_back(Json(
        {{"axis", to_string(p.axis)},
         {"value", p.value},
         {"outcome", to_string(p.outcome)},
         {"mode", to_string(p.mode)},
         {"failure_time_s", p.outcome == Outcome::failed ? Json(p.failure_time_s) : Json(nullptr)},
         {"sim_time_s", p.sim_time_s},
         {"steps", p.steps},
         {"peak_ratio", p.peak_ratio},
         {"load_peak_ratio", p.load_peak_ratio},
         {"confirmation", p.confirmation},
         {"wall_ms", p.wall_ms}}));
    if (p.axis == Axis::lateral) probe["turn"] = to_string(p.turn);
    if (p.mode == FailureMode::top_item_slide) {
      probe["item_tipped"] = p.slide == SlideKind::item_tipped;
      if (p.slide == SlideKind::load_as_one) probe["load_as_one"] = true;
    }
    if (p.projected) probe["projected"] = true;
  }
  return out;
}

namespace {

Json cell_json(const MapCell& c) {
  Json j = {{"outcome", to_string(c.outcome)},
            {"mode", to_string(c.mode)},
            {"failure_time_s", c.outcome == Outcome::failed ? Json(c.failure_time_s) : Json()},
            {"decided_by", to_string(c.decided_by)},
            {"non_monotone", c.non_monotone}};
  if (!c.reason.empty()) j["reason"] = c.reason;
  return j;
}

}  // namespace

Json failure_map_to_json(const FailureMap& map) {
  Json rows = Json::array();
  for (std::size_t j = 0; j < map.accels_mps2.size(); ++j) {
    Json row = Json::array();
    for (std::size_t i = 0; i < map.speeds_mps.size(); ++i) {
      row.push_back(cell_json(map.at(int(i), int(j))));
    }
    rows.push_back(std::move(row));
  }
  Json line = Json::array();
  for (const auto& c : map.line_cells) line.push_back(cell_json(c));
  return {{"speeds_mps", map.speeds_mps},
          {"accels_mps2", map.accels_mps2},
          {"cells", std::move(rows)},
          {"line_cells", std::move(line)},
          {"envelope",
           {{"max_speed_mps", map.max_speed_mps},
            {"speed_mode", to_string(map.speed_mode)},
            {"max_accel_mps2", map.max_accel_mps2},
            {"accel_mode", to_string(map.accel_mode)},
            {"reject", map.reject}}},
          {"unstable_cells", map.unstable_cells},
          {"non_monotone_cells", map.non_monotone_cells},
          {"sims", map.sims},
          {"threads", map.threads},
          {"wall_ms", map.wall_ms}};
}

}  // namespace pb
