// SPDX-License-Identifier: MIT
// How likely a pallet is to fail a motion when what we know about it is uncertain: friction and
// item masses vary with a stated spread, M seeded samples run through one batched call.
//
// The spread (UncertaintySpread): every contact pair's friction (belt/pallet, item/pallet,
// item/item, each pair on its own) is multiplied by a lognormal factor exp(sigma_f * z), sigma_f =
// 10 %; every item's mass by N(1, 5 %) (clamped to [0.5, 1.5]), its inertia with it (same shape).
// The pallet and the belt keep theirs. Samples start from the nominal rest state (a 5 % heavier
// item settles a few micrometres deeper: a transient far below every detector).
// Draws come from core/base/rng.hpp (xoshiro256**, Box-Muller), so a seed gives the same samples on
// every platform and at every thread count.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/analysis/envelope.hpp"
#include "core/base/diagnostic.hpp"
#include "core/contract/conveyor_profile.hpp"
#include "core/physics/scene.hpp"
#include "core/physics/simulate.hpp"

namespace pb {

struct UncertaintySpread {
  double friction_sigma = 0.10;  ///< lognormal sigma of each pair's friction factor
  double mass_sigma = 0.05;      ///< relative standard deviation of each item's mass
};

struct UncertaintyOptions {
  int samples = 32;  ///< M
  std::uint64_t seed = 0;
  int threads = 0;  ///< 0: every CPU
  UncertaintySpread spread;
};

struct UncertaintyResult {
  int samples = 0;
  int failures = 0;  ///< samples that failed at least one of the profiles
  int unstable = 0;  ///< samples without a verdict (excluded from p_fail)
  double p_fail = 0.0;
  double ci_low = 0.0, ci_high = 0.0;  ///< Wilson 95 % interval of p_fail
  std::map<FailureMode, int> modes;    ///< the first failure of each failing sample
  int sims = 0;
  double wall_ms = 0.0;
};

/// The Wilson score interval (z = 1.96) of `failures` in `n` trials; {0, 1} for n = 0.
std::pair<double, double> wilson_interval(int failures, int n, double z = 1.96);

/// Probability that the pallet fails at least one of `profiles` (an operating point; each sample
/// runs all of them), with M samples of the spread. Fails on bad options (naming the field) or if
/// the batch cannot run.
Result<UncertaintyResult> failure_probability(const Scene& scene, const RestState& rest,
                                              const std::vector<ConveyorProfile>& profiles,
                                              const UncertaintyOptions& options,
                                              const SimOptions& sim = {});

/// SafetyResult.confidence: the probability, under the spread, that the pallet survives every limit
/// the envelope reports — the start-up at max_accel, the stop at max_decel from the top of the
/// speed range, the curve at max_lateral and the line's e-stop from max_speed (each probe as the
/// bisection ran it; a sample fails if any fails). 1 - p_fail of that operating point. Limits sit
/// within one search precision of a failure, so a limit that friction or mass can move (slip,
/// slide) gives a confidence well below 1, one at the top of its range or insensitive to the
/// spread (tip of a rigid load) near 1. A rejected pallet has no limits to survive: 0.
Result<UncertaintyResult> limits_confidence(const Scene& scene, const Envelope& envelope,
                                            const LineDescription& line, const SearchConfig& search,
                                            const UncertaintyOptions& options,
                                            const SimOptions& sim = {});

}  // namespace pb
