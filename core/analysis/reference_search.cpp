// SPDX-License-Identifier: MIT
#include "core/analysis/reference_search.hpp"

#include <chrono>
#include <optional>

#include "core/base/text.hpp"

namespace pb {

AnalyzerOptions reference_search_options() {
  AnalyzerOptions o;
  o.fidelity = Fidelity::full;
  o.scene.timestep_s = 0.002;
  o.scene = with_mujoco_solver(o.scene);  // the reference system keeps MuJoCo's defaults
  o.full_model_timestep_s.reset();
  o.full_model_solref_s.reset();
  o.sim.early_stop = false;
  o.sim.skip_comoving = false;
  o.sim.project_pallet_slip = false;
  return o;
}

Result<ReferenceSearch> reference_search(Analyzer& analyzer, const PalletConfig& config) {
  const auto start = std::chrono::steady_clock::now();
  auto prepared = analyzer.prepare(config);
  if (!prepared) return Result<ReferenceSearch>::failure(std::move(prepared.diagnostics));
  PreparedPallet& p = **prepared.value;
  SimOptions o = analyzer.options().sim;
  o.record_trace = false;
  o.fail_fast = true;
  ReferenceSearch out;
  std::optional<std::string> unstable;
  // A ramp at `accel` to `speed`, held 0.25 s: safe or not (nullopt when unstable).
  auto safe = [&](double speed, double accel) -> std::optional<bool> {
    ConveyorProfile profile;
    profile.shape = ProfileShape::accel_hold;
    profile.target_speed_mps = speed;
    profile.accel_mps2 = accel;
    profile.duration_s = speed / accel + 0.25;
    const SimResult r = p.simulator->run(p.rest, profile, o);
    ++out.sims;
    if (r.outcome == Outcome::unstable) {
      unstable = "the probe at " + fixed(speed, 2) + " m/s, " + fixed(accel, 2) +
                 " m/s^2 became numerically unstable: " + r.reason;
      return std::nullopt;
    }
    return r.outcome == Outcome::safe;
  };
  // Top first, then the floor, then bisection (the reference's order).
  auto bisect = [&](double lo, double hi, double precision,
                    const auto& probe) -> std::optional<double> {
    auto top = probe(hi);
    if (!top) return std::nullopt;
    if (*top) return hi;
    auto floor = probe(lo);
    if (!floor) return std::nullopt;
    if (!*floor) return 0.0;
    while (hi - lo > precision) {
      const double mid = 0.5 * (lo + hi);
      auto r = probe(mid);
      if (!r) return std::nullopt;
      (*r ? lo : hi) = mid;
    }
    return lo;
  };
  const auto speed = bisect(0.1, 2.0, 0.1, [&](double v) { return safe(v, 1.0); });
  const auto accel =
      speed ? bisect(0.1, 5.0, 0.2, [&](double a) { return safe(1.0, a); }) : std::nullopt;
  if (!speed || !accel) {
    return Result<ReferenceSearch>::failure("", unstable.value_or("the search stopped"));
  }
  out.max_speed_mps = *speed;
  out.max_accel_mps2 = *accel;
  out.wall_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return Result<ReferenceSearch>{out, {}};
}

}  // namespace pb
