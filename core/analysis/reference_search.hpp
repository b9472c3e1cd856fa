// SPDX-License-Identifier: MIT
// The reference system's envelope search (PalletBallet, REFERENCE_FACTS.md "Envelope search"), as
// a mode of our own code, so that `palletballet-cli bench` times both on the same machine in one
// run: the full multi-body model at 2 ms, two plain bisections, no closed-form seed, no early
// stop. It answers only what the reference answered (a start-up speed and acceleration); it is a
// yardstick for speed, not a product answer.
#pragma once

#include "core/analysis/analyzer.hpp"

namespace pb {

/// What the reference's two searches found.
struct ReferenceSearch {
  double max_speed_mps = 0.0;   ///< speed axis: ramps at 1 m/s^2, bisected on [0.1, 2.0] by 0.1
  double max_accel_mps2 = 0.0;  ///< accel axis: ramps to 1 m/s, bisected on [0.1, 5.0] by 0.2
  int sims = 0;
  double wall_ms = 0.0;  ///< compile and settle included
};

/// The reference's model numerics: full model, 2 ms (its timestep), no early stop, no skipping.
AnalyzerOptions reference_search_options();

/// Runs both searches on `config` with `analyzer` (use reference_search_options(); a fresh
/// Analyzer times a cold run). Each axis probes its top first (safe: done), then its floor (fails:
/// 0), then bisects to the precision; every probe holds 0.25 s after its ramp. An unstable probe
/// fails the search with its reason.
Result<ReferenceSearch> reference_search(Analyzer& analyzer, const PalletConfig& config);

}  // namespace pb
