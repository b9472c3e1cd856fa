// SPDX-License-Identifier: MIT
// Is a PalletConfig a pallet that can exist? Syntactic (finite, in range) and physical
// (no interpenetration, nothing floating, overhang, rating, height) rules.
#pragma once

#include "core/base/diagnostic.hpp"
#include "core/contract/pallet_config.hpp"
#include "core/inputs/catalog.hpp"

namespace pb {

struct ValidationLimits {
  double penetration_tolerance_m = 0.001;  ///< overlap allowed between two items' volumes
  double support_tolerance_m = 0.001;      ///< gap allowed between an item and what carries it
  /// Reach of any item's footprint beyond the deck edge. 10 cm: beyond this a carton's own
  /// centre region hangs off the deck, and the scanner's top-layer anomalies stay under it.
  double max_overhang_m = 0.10;
  /// Gross mass cap (base + items). 1,200 kg, the reference's cap; the lower of this and the base
  /// type's rated load plus tare applies.
  double max_gross_mass_kg = 1200.0;
  double max_stack_height_m = 1.85;  ///< top of the load above the floor
  /// Warn when a standing item rests on less than this fraction of its footprint (precarious).
  double low_support_warning = 0.5;
  /// Static stability (static_stability.hpp): the centre of mass of an item and of everything it
  /// carries must act at least this far inside the edge of the region the item rests on (the
  /// convex hull of its contact patches), or the item cannot stand (an error). 10 mm: a carton's
  /// edge is no knife edge (corrugated board crushes a few millimetres under a load), and a
  /// load balanced within a few millimetres of an edge tips at the first touch; core/README.md.
  double stability_margin_m = 0.01;
  bool check_standing = true;  ///< off only to measure what the rule changes
  /// The most items a pallet may carry, checked before anything else (a 20,000-item document is
  /// refused at once, not checked pair by pair). 400: a EUR deck of the smallest catalog cartons
  /// to the height cap is about 300; the engine's own limits (scene.hpp: kMaxSimulationBytes,
  /// kMaxBufferBytes) are usually lower and are named when a scene is built.
  std::size_t max_items = 400;
  /// An item's weight over its box's volume, in kg/m^3: denser than lead (11,340) or lighter than
  /// 1 kg/m^3 (an empty carton is about 5) is a unit slip in weight_kg or dims_m, and a physics
  /// the engine would simulate with mass ratios it cannot hold.
  double min_density_kg_m3 = 1.0;
  double max_density_kg_m3 = 11340.0;
  /// The heaviest item over the base's mass: beyond 100 the engine's contact solve loses
  /// accuracy (a 2 kg base under a 500 kg item answered a curve limit of 0.26 g where 5-25 kg
  /// bases answer 0.35; a 0.01 kg base under 20 kg rejected a load that is at every ceiling),
  /// and no real pallet is that light for its load.
  double max_item_to_base_mass = 100.0;
  /// The same between an item and one it carries: a 0.5 kg plate under a 50 kg block (100 times)
  /// answers its pallet's slip limit, 4.7 m/s^2, as a 5 kg plate under 500 kg does; under 100 kg
  /// (200 times) the block slides off at 3.2, under 500 kg at 0.9 m/s^2 (the soft contacts creep).
  double max_carried_to_carrier_mass = 100.0;
  /// A base lighter than this share of its type's tare earns a warning (a typo, or the wrong
  /// base_pallet_type).
  double light_base_warning = 0.4;
  bool require_known_skus = false;  ///< every item's SKU must be in the catalog
};

/// Every rule, in document order. Errors make the pallet unusable; warnings (low support,
/// base dimensions far from the type's nominal ones, an item's weight or dims differing from its
/// catalog entry) do not. Pointers are those of pallet_to_json(): "/items/3/dims_m/2".
/// `catalog` is used for SKU checks (nullptr: Catalog::builtin()).
Diagnostics validate(const PalletConfig& config, const ValidationLimits& limits = {},
                     const Catalog* catalog = nullptr);

/// A curve turns the pallet about its centre (physics/turning_frame.hpp). A radius no larger than
/// the pallet's half-width across the belt (its load's overhang included) would put the curve's
/// centre under the pallet, which no conveyor does: an error at `pointer` naming the least radius
/// this pallet takes, or nothing. For a pallet validate() accepts.
Diagnostics validate_curve_radius(const PalletConfig& config, double radius_m,
                                  const std::string& pointer);

}  // namespace pb
