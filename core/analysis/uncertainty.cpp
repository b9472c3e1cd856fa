// SPDX-License-Identifier: MIT
#include "core/analysis/uncertainty.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include "core/base/rng.hpp"
#include "core/physics/probe_batch.hpp"

namespace pb {

std::pair<double, double> wilson_interval(int failures, int n, double z) {
  if (n <= 0) return {0.0, 1.0};
  const double p = double(failures) / n;
  const double z2 = z * z;
  const double denom = 1.0 + z2 / n;
  const double centre = (p + z2 / (2.0 * n)) / denom;
  const double half = z / denom * std::sqrt(p * (1.0 - p) / n + z2 / (4.0 * n * n));
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

namespace {

double normal(Rng& rng) {                   // Box-Muller, one value per call (platform-independent)
  const double u1 = 1.0 - rng.uniform01();  // (0, 1]
  const double u2 = rng.uniform01();
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
}

}  // namespace

Result<UncertaintyResult> failure_probability(const Scene& scene, const RestState& rest,
                                              const std::vector<ConveyorProfile>& profiles,
                                              const UncertaintyOptions& o, const SimOptions& sim) {
  using Out = Result<UncertaintyResult>;
  const auto start = std::chrono::steady_clock::now();
  if (o.samples < 1 || o.samples > 100000) {
    return Out::failure("/samples", "give 1 to 100000 samples");
  }
  if (o.threads < 0) return Out::failure("/threads", "give 0 (every CPU) or a thread count");
  if (!(o.spread.friction_sigma >= 0.0 && o.spread.friction_sigma <= 1.0)) {
    return Out::failure("/spread/friction_sigma", "give a sigma in [0, 1]");
  }
  if (!(o.spread.mass_sigma >= 0.0 && o.spread.mass_sigma <= 0.3)) {
    return Out::failure("/spread/mass_sigma", "give a relative sigma in [0, 0.3]");
  }
  if (profiles.empty()) return Out::failure("/profiles", "give at least one profile");

  const mjModel& m = *scene.model;
  const int P = int(profiles.size()), M = o.samples;
  // The draws, sample by sample (the same for every profile of a sample).
  Rng rng(o.seed);
  const auto& items = scene.layout.item_bodies;
  std::vector<double> pair_factor(std::size_t(M) * std::size_t(m.npair));
  std::vector<double> mass_factor(std::size_t(M) * items.size());
  for (int s = 0; s < M; ++s) {
    for (int p = 0; p < m.npair; ++p) {
      pair_factor[std::size_t(s * m.npair + p)] = std::exp(o.spread.friction_sigma * normal(rng));
    }
    for (std::size_t i = 0; i < items.size(); ++i) {
      mass_factor[std::size_t(s) * items.size() + i] =
          std::clamp(1.0 + o.spread.mass_sigma * normal(rng), 0.5, 1.5);
    }
  }
  std::vector<ConveyorProfile> all;
  all.reserve(std::size_t(M * P));
  for (int s = 0; s < M; ++s) all.insert(all.end(), profiles.begin(), profiles.end());

  auto configure = [&](Batch& batch) -> std::optional<std::string> {
    auto friction = batch.expand("pair_friction");
    if (!friction) return friction.diagnostics.front().message;
    auto mass = batch.expand("body_mass");
    if (!mass) return mass.diagnostics.front().message;
    auto inertia = batch.expand("body_inertia");
    if (!inertia) return inertia.diagnostics.front().message;
    for (int row = 0; row < M * P; ++row) {
      const int s = row / P;
      for (int p = 0; p < m.npair; ++p) {
        const double f = pair_factor[std::size_t(s * m.npair + p)];
        // Every coefficient but the last, which names the pair (step.hpp's Coulomb friction).
        for (int k = 0; k < 5; ++k)
          (*friction.value)(row, 5 * p + k) = m.pair_friction[5 * p + k] * (k < 4 ? f : 1.0);
      }
      for (std::size_t i = 0; i < items.size(); ++i) {
        const int b = items[i];
        const double f = mass_factor[std::size_t(s) * items.size() + i];
        (*mass.value)(row, b) = m.body_mass[b] * f;
        for (int k = 0; k < 3; ++k)
          (*inertia.value)(row, 3 * b + k) = m.body_inertia[3 * b + k] * f;
      }
    }
    // MuJoCo 2.2 takes a free body's inertia from dof_M0 (mj_setConst): without this a heavier
    // item would weigh more but accelerate as before.
    if (auto error = batch.set_const()) return error->message;
    return std::nullopt;
  };
  SimOptions so = sim;
  so.record_trace = false;
  so.fail_fast = true;
  auto results = run_probes_batched(scene, rest, all, so, o.threads, configure);
  if (!results) return Out::failure(std::move(results.diagnostics));

  UncertaintyResult r;
  r.samples = M;
  r.sims = M * P;
  for (int s = 0; s < M; ++s) {
    bool unstable = false;
    std::optional<FailureEvent> first;
    for (int p = 0; p < P; ++p) {
      const SimResult& x = (*results.value)[std::size_t(s * P + p)];
      if (x.outcome == Outcome::unstable) unstable = true;
      if (x.outcome == Outcome::failed && x.failure && !first) first = x.failure;
    }
    if (first) {
      ++r.failures;
      ++r.modes[first->mode];
    } else if (unstable) {
      ++r.unstable;
    }
  }
  const int judged = M - r.unstable;
  r.p_fail = judged > 0 ? double(r.failures) / judged : 0.0;
  std::tie(r.ci_low, r.ci_high) = wilson_interval(r.failures, judged);
  r.wall_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return Out{std::move(r), {}};
}

Result<UncertaintyResult> limits_confidence(const Scene& scene, const Envelope& env,
                                            const LineDescription& line, const SearchConfig& search,
                                            const UncertaintyOptions& options,
                                            const SimOptions& sim) {
  const SafetyResult& r = env.result;
  if (r.verdict == Verdict::reject) {
    UncertaintyResult none;
    none.p_fail = 1.0;
    none.ci_low = none.ci_high = 1.0;
    return Result<UncertaintyResult>{none, {}};
  }
  std::vector<ConveyorProfile> profiles;
  if (r.max_accel_mps2 > 0.0) profiles.push_back(accel_probe_profile(r.max_accel_mps2, search));
  if (r.max_decel_mps2 > 0.0) {
    profiles.push_back(decel_probe_profile(r.max_decel_mps2, search.speed_max_mps, search));
  }
  if (r.max_lateral_g > 0.0) {
    for (CurveTurn turn : curve_turns(scene.config)) {
      profiles.push_back(lateral_probe_profile(r.max_lateral_g, line, search, turn));
    }
  }
  if (r.max_speed_mps > 0.0) profiles.push_back(stop_probe_profile(r.max_speed_mps, line, search));
  return failure_probability(scene, env.rest, profiles, options, sim);
}

}  // namespace pb
