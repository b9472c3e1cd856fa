// SPDX-License-Identifier: MIT
#include "app/server/reference_api.hpp"

#include <algorithm>

#include "core/base/pose.hpp"
#include "core/contract/pallet_metrics.hpp"

namespace pb::server {

Json scenario_summary_json(const Scenario& s) {
  return {{"slug", s.slug},
          {"name", s.name},
          {"tag", s.tag},
          {"description", s.description},
          {"expected_failure", s.expected_failure},
          {"item_count", s.pallet.items.size()},
          {"total_mass_kg", total_mass_kg(s.pallet)},
          {"stack_height_m", stack_height_m(s.pallet)}};
}

Json sku_info_json(const SkuTemplate& t) {
  return {{"sku", t.sku},
          {"name", t.name},
          {"weight_kg", t.weight_kg},
          {"dims_m", t.dims_m},
          {"fragility", to_string(t.fragility)},
          {"category", t.category},
          {"default_env", to_string(t.default_env)}};
}

Json friction_point_json(double temp_c, const FrictionValue& value) {
  return {{"temp_c", temp_c}, {"mu_static", value.mu_s}, {"mu_dynamic", value.mu_d}};
}

Json analyze_response_json(const Analysis& analysis) {
  const Envelope& env = analysis.cached->envelope;
  SafetyResult result = env.result;
  if (analysis.cache_hit) {
    result.sims_run = 0;
    result.sim_runtime_ms = analysis.wall_ms;
  }
  Json sweep = Json::array();
  for (const auto& p : env.probes) {
    sweep.push_back({{"axis", to_string(p.axis)},
                     {"value", p.value},
                     {"safe", p.outcome == Outcome::safe},
                     {"failure_mode", to_string(p.mode)}});
  }
  return {{"result", safety_result_to_json(result)},
          {"sims_run", result.sims_run},
          {"cache_hits", analysis.cache_hit ? 1 : 0},
          {"sweep_points", std::move(sweep)}};
}

namespace {

Json vec3(const Vec3& v) {
  return Json::array({v[0], v[1], v[2]});
}
Json quat(const Quat& q) {
  return Json::array({q[0], q[1], q[2], q[3]});
}

// The trace frame at or just before `t` (the trace's times increase).
std::size_t frame_at_or_before(const Trace& trace, double t) {
  std::size_t lo = 0, hi = trace.size();
  while (hi - lo > 1) {
    const std::size_t mid = (lo + hi) / 2;
    (trace.time(mid) <= t ? lo : hi) = mid;
  }
  return lo;
}

// The pallet's velocity along the belt at trace frame k: a central difference of its position
// over the neighbouring frames (one-sided at the ends).
double pallet_vel_x(const Trace& trace, std::size_t k) {
  if (trace.size() < 2) return 0.0;
  const std::size_t a = k == 0 ? 0 : k - 1;
  const std::size_t b = std::min(trace.size() - 1, k + 1);
  const double dt = trace.time(b) - trace.time(a);
  return dt > 0.0 ? (trace.pallet(b).pos[0] - trace.pallet(a).pos[0]) / dt : 0.0;
}

}  // namespace

Json solve_response_json(const PalletConfig& pallet, const Solve& solve, bool include_replay,
                         const std::string& fidelity) {
  const SimResult& sim = solve.sim;
  const Replay& replay = solve.replay;
  const Trace& trace = sim.trace;
  double max_tip = 0.0;
  for (std::size_t k = 0; k < trace.size(); ++k) {
    max_tip = std::max(max_tip, tilt_deg(trace.pallet(k).quat));
  }
  Json times = Json::array(), conveyor = Json::array(), vel = Json::array(), pos = Json::array(),
       tip = Json::array();
  for (const auto& f : replay.frames) {
    const std::size_t k = trace.empty() ? 0 : frame_at_or_before(trace, f.t);
    times.push_back(f.t);
    conveyor.push_back(trace.empty() ? 0.0 : trace.belt(k).vx);
    vel.push_back(pallet_vel_x(trace, k));
    pos.push_back(f.pallet.pos[0]);
    tip.push_back(tilt_deg(f.pallet.quat));
  }
  Json out;
  out["pallet_id"] = pallet.pallet_id;
  if (sim.outcome == Outcome::unstable) {
    out["failure"] = nullptr;
    out["unstable"] = true;
    out["reason"] = sim.reason;
  } else {
    out["failure"] = {
        {"mode", to_string(sim.failure ? sim.failure->mode : FailureMode::no_failure)},
        {"time_s", sim.failure ? Json(sim.failure->time_s) : Json(nullptr)},
        {"max_tip_angle_deg", max_tip}};
  }
  out["trace"] = {{"times_s", std::move(times)},
                  {"conveyor_vel_mps", std::move(conveyor)},
                  {"pallet_vel_x_mps", std::move(vel)},
                  {"pallet_pos_x_m", std::move(pos)},
                  {"tip_angle_deg", std::move(tip)}};
  out["runtime_ms"] = sim.wall_ms;
  out["n_steps_simulated"] = sim.steps - sim.steps_skipped;
  out["outcome"] = to_string(sim.outcome);
  out["fidelity"] = fidelity;
  if (!include_replay) {
    out["replay"] = nullptr;
    return out;
  }
  Json r;
  Json items = Json::array();
  for (const auto& item : pallet.items) {
    const SkuTemplate* t = Catalog::builtin().find(item.sku);
    items.push_back({{"sku", item.sku},
                     {"name", t ? t->name : item.sku},
                     {"dims_m", item.dims_m},
                     {"fragility", to_string(item.fragility)},
                     {"category", t ? t->category : std::string("unknown")}});
  }
  Json rt = Json::array(), belt = Json::array(), ppos = Json::array(), pq = Json::array(),
       ipos = Json::array(), iq = Json::array();
  for (const auto& f : replay.frames) {
    rt.push_back(f.t);
    belt.push_back(f.belt_x);
    ppos.push_back(vec3(f.pallet.pos));
    pq.push_back(quat(f.pallet.quat));
    Json fp = Json::array(), fq = Json::array();
    for (const auto& p : f.items) {
      fp.push_back(vec3(p.pos));
      fq.push_back(quat(p.quat));
    }
    ipos.push_back(std::move(fp));
    iq.push_back(std::move(fq));
  }
  r["times_s"] = std::move(rt);
  r["belt_disp_m"] = std::move(belt);
  r["base_dims_m"] = pallet.base_dims_m;
  r["pallet_pos_m"] = std::move(ppos);
  r["pallet_quat_wxyz"] = std::move(pq);
  r["items"] = std::move(items);
  r["item_pos_m"] = std::move(ipos);
  r["item_quat_wxyz"] = std::move(iq);
  out["replay"] = std::move(r);
  return out;
}

}  // namespace pb::server
