// SPDX-License-Identifier: MIT
// Quantities derived from a PalletConfig: mass, centre of mass, height, overhang, support.
// Footprints account for item yaw (the reference system ignored it).
#pragma once

#include <array>
#include <vector>

#include "core/base/vec3.hpp"
#include "core/contract/item.hpp"
#include "core/contract/pallet_config.hpp"

namespace pb {

/// Base mass plus every item's weight.
double total_mass_kg(const PalletConfig& config);

/// Mass-weighted centre of mass of base (at half the base height, centred) and items (their
/// geometric centres), in the pallet frame.
Vec3 composite_com_m(const PalletConfig& config);

/// Top of the highest item, or the deck height when there are no items.
double stack_height_m(const PalletConfig& config);

/// The largest distance any item's (yawed) footprint reaches beyond the pallet's edge along X or
/// Y; 0 when every item is within the footprint (never negative, as in the reference).
double overhang_m(const PalletConfig& config);

/// How far this item's (yawed) footprint reaches beyond the edge of a base of `base_dims_m`
/// along X or Y; 0 when it is within the footprint.
double item_overhang_m(const Item& item, const Vec3& base_dims_m);

/// Corners of the item's yawed footprint in the pallet XY plane, counter-clockwise.
std::array<Vec2, 4> item_footprint(const Item& item);

/// The item's footprint as a polygon (item_footprint's corners).
std::vector<Vec2> footprint_polygon(const Item& item);
/// The deck's rectangle, centred on the origin, counter-clockwise.
std::vector<Vec2> deck_polygon(const Vec3& base_dims_m);

/// Signed area of a polygon (shoelace): positive when counter-clockwise (m^2).
double polygon_area(const std::vector<Vec2>& polygon);

/// The intersection of two convex polygons given counter-clockwise (Sutherland-Hodgman), counter-
/// clockwise; empty when they share less than a polygon.
std::vector<Vec2> convex_intersection(const std::vector<Vec2>& a, const std::vector<Vec2>& b);

/// Area of the intersection of two convex polygons given counter-clockwise (m^2).
double convex_overlap_area(const std::vector<Vec2>& a, const std::vector<Vec2>& b);

/// Overlap area of two items' footprints (m^2).
double footprint_overlap_area(const Item& a, const Item& b);

/// For each item, the other items whose footprints' bounding boxes come within `margin_m` of its
/// own, in ascending order: every pair that can overlap, touch or carry one another in plan, found
/// by sort and sweep along X (O(n log n + pairs), not every pair). An item whose footprint is not
/// finite has no neighbours and is no one's. The pair checks of validation, support and standing
/// run over these lists.
std::vector<std::vector<std::size_t>> footprint_neighbours(const PalletConfig& config,
                                                           double margin_m = 0.0);

/// Per item, the fraction of its footprint area resting on something: the pallet deck (items
/// whose bottom is within `tolerance_m` of the deck top, clipped to the deck's rectangle) or items
/// whose top is within `tolerance_m` of its bottom. Overlapping supports are not double-counted
/// beyond 1 (the fraction is clamped to [0, 1]; supports under one item do not overlap in a valid
/// layout).
std::vector<double> support_fractions(const PalletConfig& config, double tolerance_m = 0.001);

/// The load is its own mirror image across the plane x = 0 (along the belt): every item has a
/// twin at (-x, y, z) of the same size, mass and SKU (an item on the plane is its own twin), every
/// yaw a multiple of 90 degrees; positions within `tolerance_m`.
bool mirror_symmetric_along(const PalletConfig& config, double tolerance_m = 0.001);
/// The same across the plane y = 0 (across the belt): a curve turning either way is one
/// experiment, mirrored.
bool mirror_symmetric_across(const PalletConfig& config, double tolerance_m = 0.001);

/// A length that meets a tolerance exactly in the input's decimals may compute a hair over it
/// (0.151 - 0.15 is 0.0010000000000000009 in doubles): every tolerance allows this much more.
inline constexpr double kLengthRoundOff_m = 1e-9;
/// Surfaces within this distance touch: validation's tolerance (1 mm) and the round-off (an item
/// placed 1 mm above the deck passed validation and got no contact with it, so it fell through
/// and the load was called one that cannot stand).
inline constexpr double kSupportTolerance_m = 0.001 + kLengthRoundOff_m;
/// Per item, the items it rests on directly: their top within kSupportTolerance_m of its bottom,
/// their footprints sharing more than 1 cm^2 (less is an edge: a neighbour, not a support).
std::vector<std::vector<std::size_t>> resting_on(const PalletConfig& config);

}  // namespace pb
