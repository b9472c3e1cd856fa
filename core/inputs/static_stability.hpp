// SPDX-License-Identifier: MIT
// Can the load stand? Each item's load (its own weight and the share of everything above that
// bears on it) traced from the top of the load down to the deck, and where that load meets the
// region the item rests on. A rigid item stands while the resultant of its load acts inside the
// convex hull of its contact patches; validate() asks for a margin inside that edge.
//
// Where an item rests on several supports (a brick layer bridging two cartons), the share each
// carries is statically indeterminate; it is taken from a linear contact pressure over the patches
// (a rigid item on an elastic bed, the classic eccentric-footing model), which keeps the
// resultant's moment exact. A support the pressure would pull on is lifted and the rest re-solved.
// On a single support the load passes down whole: a column is judged by its centre of mass. An
// item whose load is outside its region passes it down at the region's edge (it tips there).
#pragma once

#include <optional>
#include <vector>

#include "core/base/vec3.hpp"
#include "core/contract/pallet_config.hpp"

namespace pb {

/// One item's standing: what it rests on and where its load acts.
struct ItemStanding {
  bool on_deck = false;               ///< rests on the pallet deck
  std::vector<std::size_t> supports;  ///< the items it rests on (empty on the deck or floating)
  double load_kg = 0.0;               ///< its weight plus the share of the load above it
  Vec2 load_point{};                  ///< where that load's resultant acts, pallet frame (m)
  /// Distance from load_point to the edge of the convex hull of its contact patches: positive
  /// inside, negative outside. Meaningless when !supported().
  double margin_m = 0.0;

  bool supported() const { return on_deck || !supports.empty(); }
  /// Its load acts at least `margin` inside its region (to round-off: 9.999999 mm is 10 mm), or it
  /// rests on nothing (floating is another rule's).
  bool stands(double margin) const { return !supported() || margin_m >= margin - 1e-9; }
};

/// Every item's standing, in item order. Contacts: an item whose bottom is within `tolerance_m` of
/// the deck top rests on the deck (its footprint clipped to the deck); otherwise on every item
/// whose top is within `tolerance_m` of its bottom and whose footprint shares more than 1 mm^2.
/// Items whose numbers are not finite must not be passed (validate() checks them first).
std::vector<ItemStanding> standing(const PalletConfig& config, double tolerance_m = 0.001);

/// Every item that rests on something has its load at least `margin_m` inside its support region.
bool stands(const PalletConfig& config, double margin_m, double tolerance_m = 0.001);

/// The items whose weight reaches `item` through what rests on it (transitively), ascending.
std::vector<std::size_t> carried_items(const PalletConfig& config, std::size_t item,
                                       double tolerance_m = 0.001);

/// The smallest horizontal shift (to the millimetre, pointing from the load point towards the
/// inside of the support region) of `item` together with everything it carries that puts its load
/// point at least `margin_m` inside the region it then rests on; nullopt when no shift of up to
/// the item's own length does (its supports are too small for it).
std::optional<Vec2> standing_correction(const PalletConfig& config,
                                        const std::vector<ItemStanding>& standings,
                                        std::size_t item, double margin_m,
                                        double tolerance_m = 0.001);

}  // namespace pb
