// SPDX-License-Identifier: MIT
// Scanner inputs to PalletConfig: a layer pattern, Ti items per layer, Hi layers, the SKUs read
// from barcodes, and the anomalies a camera sees (lean, top-layer overhang). Unlike the
// reference, every layout built here validates: no interpenetration, every item rests on what is
// below it, within the overhang limit and the caps.
#pragma once

#include <string>
#include <vector>

#include "core/base/diagnostic.hpp"
#include "core/contract/pallet_config.hpp"
#include "core/inputs/catalog.hpp"
#include "core/inputs/validation.hpp"

namespace pb {

struct ScannerInputs {
  std::string pallet_id = "scan";
  PalletType base_pallet_type = PalletType::eur;
  LayerPattern pattern = LayerPattern::brick;
  int layers = 4;           ///< Hi
  int items_per_layer = 6;  ///< Ti
  /// Barcodes, layer-major (layer 0 first); fewer than layers * items_per_layer repeat cyclically,
  /// extra ones are ignored (as the reference does).
  std::vector<std::string> skus;
  /// The load leans towards +X: each layer shifts by tan(lean) * its height above the deck.
  double lean_angle_deg = 0.0;
  double top_overhang_m = 0.0;  ///< the top layer is pushed this far towards +X
  WrapType wrap = WrapType::stretch;
  Environment env = Environment::refrigerated;
  double body_temp_c = 2.0;
  double seconds_since_temp_change = 3600.0;
  BeltSurface belt_surface = BeltSurface::rubber_belt;
};

/// Lays out the scanned pallet on the base type's nominal deck.
///  - column:    Ti items in a grid, the same positions on every layer of the same SKUs.
///  - brick:     as column, with alternate layers shifted by a quarter of a cell along X (less
///               where the overhang limit does not allow it).
///  - pinwheel:  alternate layers rotated 90 degrees (item yaw 90, the grid recomputed for the
///               rotated footprint).
///  - irregular: each layer shelf-packed from its own items' sizes, in barcode order.
/// The grid of a layer is the (cols x rows) arrangement of Ti cells, sized from the layer's
/// largest item, in the orientation that fits the deck best; each item's height is where it comes
/// to rest on what is below it (never the tallest item of the layer below, which left shorter
/// items floating in the reference). Lean and overhang shifts are clamped so the overhang stays
/// within `limits.max_overhang_m`. Fails, saying why, when Ti items cannot fit one layer of the
/// deck ("/items_per_layer", with how many would fit), a SKU is unknown ("/skus/<i>"), or the
/// pallet breaks a rule of validate(), e.g. the height cap (validate()'s pointers); the result
/// always passes validate(config, limits) without errors.
Result<PalletConfig> build_from_scanner(const ScannerInputs& inputs, const Catalog& catalog,
                                        const ValidationLimits& limits = {});

}  // namespace pb
