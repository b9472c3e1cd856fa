// SPDX-License-Identifier: MIT
// The clustered rung of the fidelity ladder: which items of an unwrapped load cannot move relative
// to what carries them over the whole search range, so that the scene can merge them rigidly into
// their carrier (a jointless child body: MuJoCo composes the exact mass, centre of mass and
// inertia) and simulate only the items that can move.
#pragma once

#include <string>
#include <vector>

#include "core/contract/pallet_config.hpp"
#include "core/inputs/friction.hpp"

namespace pb {

/// An item's carrier in a clustering: kFreeItem = its own free joint, kOnPallet = merged into the
/// pallet body, k >= 0 = merged into item k.
inline constexpr int kFreeItem = -2;
inline constexpr int kOnPallet = -1;

struct Clustering {
  std::vector<int> carrier;  ///< per item
  double reach_mps2 = 0.0;   ///< the most the load can be accelerated (what the onsets beat)

  /// The item (k >= 0) or the pallet (kOnPallet) whose rigid body item `i` belongs to.
  int root(int i) const;
  int free_count() const;
};

/// The demand an item is held against, `max_demand_mps2`, is the most that can reach the load:
/// the search's ceiling, or what its pallet passes on before it slips on its belt
/// (load_reach_mps2, fidelity.hpp). Until session 17 the belt's cap was not used: the columns of
/// frozen-pallet-jerk-start sheared 2 cm against each other while the pallet slipped, in the full
/// model and the reference configuration alike, which was MuJoCo's sliding contacts making the
/// pallet hop (step.hpp); with Coulomb's sliding they ride along, and the capped clustering
/// answers as the full model does (core/README.md). Bottom-up, an item is merged into what carries
/// it when
///   - everything it rests on belongs to one rigid body (the pallet's, or one free item's), and
///   - each of its onsets, along and across, is at least `margin` x that demand: its slip on its
///     support (mu g) and the tip of the sub-stack from it up over its bottom edge (g (b/2) / h).
/// `margin` covers what the quasi-static onset leaves out: a step load's transient, and a carrier
/// that rocks under it. Items on no support, and every item of a wrapped load (its welds hold it:
/// that is the reduced rung), stay free.
Clustering cluster_items(const PalletConfig& config, const ContactFriction& friction,
                         double max_demand_mps2, double margin);

}  // namespace pb
