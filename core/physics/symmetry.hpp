// SPDX-License-Identifier: MIT
// Symmetry reduction of an unwrapped load: stacks that are copies of each other, side by side
// across the plane a probe acts in, move alike, so one copy of each is simulated.
//
// A probe along the belt (start-up, stop, e-stop) pushes every item along X: two identical stacks
// at the same X and different Y are driven alike, carry alike and pitch alike, so in the X-Z plane
// one stands for both. A curve pushes along Y: the same would hold for identical stacks at the
// same Y, but a curve also turns the load (turning_frame.hpp), pushing stacks at different X
// differently, so the Analyzer reduces probes along the belt only (ProbePlane::across is kept for
// the geometry and its tests).
// The reduced load keeps one stack of each such group, where it stands, on a pallet of 1/m of the
// tare (m copies a group): every body then carries 1/m of the whole load's weight, friction and
// momentum in the plane, so the pallet slips, pitches and carries its stacks as the whole load
// does. What it leaves out is motion out of the plane (a yaw or roll, which identical groups
// spread evenly across the plane do not excite) and contact between the copies (they move
// alike). Measured against the full model and the reference configuration in core/README.md
// ("Symmetry reduction").
#pragma once

#include <optional>
#include <vector>

#include "core/contract/pallet_config.hpp"

namespace pb {

/// The plane a probe acts in: along the belt (X-Z: start-up, stop, e-stop) or across it (Y-Z:
/// curves).
enum class ProbePlane { along, across };

struct LoadReduction {
  PalletConfig config;           ///< one stack of each group; tare / copies
  int copies = 1;                ///< stacks each kept stack stands for
  std::vector<int> source_item;  ///< per item of `config`, its index in the original load
};

/// The reduction of `config` for probes in `plane`, or nullopt when there is none: a wrapped load
/// (its wrap ties every item to the pallet: the reduced level applies), an item not turned by a
/// multiple of 90 degrees, a group of copies whose size differs from another's, groups whose mean
/// positions across the plane differ (a yaw would couple them), or no group with two copies.
/// A stack is a set of items resting on one another (touching within 1 mm, footprints
/// overlapping); copies have the same items (SKU, mass, size, turn, fragility) at the same offsets.
std::optional<LoadReduction> reduce_symmetric_stacks(const PalletConfig& config, ProbePlane plane);

}  // namespace pb
