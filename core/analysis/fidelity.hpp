// SPDX-License-Identifier: MIT
// The fidelity ladder: which model answers a question. Each level is a real model, not a shortcut
// in the result: closed-form quasi-static bounds (per-interface slip, per-sub-stack tip), a
// reduced multi-body model (items the wrap holds rigidly merged into the pallet body), or the full
// multi-body model. `automatic` picks the cheapest level whose agreement with the full model is
// established for pallets of that kind; the level actually used is reported in
// SafetyResult::fidelity.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "core/base/enums.hpp"
#include "core/contract/pallet_config.hpp"
#include "core/inputs/friction.hpp"
#include "core/physics/detectors.hpp"

namespace pb {

/// The clustered rung's margin: an item is merged into what carries it when each of its onsets is
/// at least this many times the most the load can be accelerated (clustering.hpp).
inline constexpr double kClusterMargin = 1.25;

/// The level that answers for one pallet, and why.
struct FidelityChoice {
  Fidelity level = Fidelity::full;
  std::string why;
  /// The clustered level's merge (SceneOptions::rigid_carrier); empty for the other levels.
  std::vector<int> rigid_carrier;
};

/// The automatic choice: the reduced model when a wrap holds every item rigidly at the scale of
/// the detectors, i.e. when the largest wrap deflection an item can see, m a / K with a the most
/// the load can be accelerated (the lower of `max_accel_mps2` and the pallet's slip onset mu g),
/// stays below a quarter of the load-shift threshold (the reduced model agrees with the full one
/// within one search step on the wrapped curated scenarios: core/README.md, fidelity_test);
/// otherwise the full model (an unwrapped load, or a wrap too soft for its items). The
/// closed-form level is never chosen automatically: on loads that can rock its onsets are up to 2.3
/// search steps from the reference's limits, and its agreement on wrapped loads rests on 14
/// pallets so far (core/README.md, `study speed-accuracy`).
/// `requested` other than automatic is returned as is (a reduced request on an unwrapped pallet
/// is the full model: nothing can be merged). The clustered level (unwrapped loads: items whose
/// onsets are all beyond kClusterMargin x the search's highest demand merged into what carries
/// them) is given only when asked: capped at the belt's slip onset instead, it put
/// frozen-pallet-jerk-start 7 steps above the reference (unsafe), and at the ceiling it merged no
/// item of the 24 unwrapped pallets measured (core/README.md).
FidelityChoice choose_fidelity(const PalletConfig& config, const ContactFriction& friction,
                               double max_accel_mps2, const DetectorThresholds& thresholds,
                               Fidelity requested = Fidelity::automatic);

}  // namespace pb
