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
/// is the full model: nothing can be merged). An unwrapped load is the clustered level's, one
/// rigid body, when every item holds against kClusterMargin x `max_accel_mps2` (its slip on its
/// support, the tip of the sub-stack it carries: clustering.hpp), where `max_accel_mps2` is the
/// most its pallet can pass on to it (load_reach_mps2: a pallet slips on its belt first); on the
/// unwrapped corpus 9 of 24 loads are such, every limit within 0.6 of a search step of the
/// reference (core/README.md "The load that cannot move on its pallet"). Asked for, the
/// clustered level also merges some items and leaves the others free.
/// How much more than the belt's slip onset a slipping pallet's load may feel for a moment: the
/// breakaway's static phase and its jolt (load_reach_mps2).
inline constexpr double kBeltSlipOvershoot = 1.1;

/// The most a load can be accelerated, m/s^2: the search's `ceiling_mps2`, or what its pallet can
/// pass on before it slips on its belt if that is lower: kBeltSlipOvershoot x mu_s g, times the
/// most a curve of `curve_radius_m` demands of an item off the centre (|(r + |y|, x)| / r at the
/// item's place: turning_frame.hpp).
double load_reach_mps2(const PalletConfig& config, const ContactFriction& friction,
                       double ceiling_mps2, double curve_radius_m);

FidelityChoice choose_fidelity(const PalletConfig& config, const ContactFriction& friction,
                               double max_accel_mps2, const DetectorThresholds& thresholds,
                               Fidelity requested = Fidelity::automatic);

}  // namespace pb
