// SPDX-License-Identifier: MIT
// Small pallets for the physics tests: a test carton anywhere, on a default EUR pallet.
#pragma once

#include <utility>
#include <vector>

#include "core/contract/pallet_config.hpp"

namespace pb::test {

/// A carton of SKU "test" whose bottom face is centred at (x, y, z).
inline Item carton(double x, double y, double z, Vec3 dims = {0.4, 0.3, 0.2}, double kg = 10.0,
                   double yaw = 0.0) {
  Item item;
  item.sku = "test";
  item.weight_kg = kg;
  item.dims_m = dims;
  item.position = {x, y, z};
  item.orientation_deg = yaw;
  return item;
}

/// A default EUR pallet (1.2 x 0.8 x 0.15 m, 25 kg: the deck is at z = 0.15) with these items.
inline PalletConfig pallet(std::vector<Item> items, WrapType wrap = WrapType::none) {
  PalletConfig config;
  config.items = std::move(items);
  config.wrap = wrap;
  return config;
}

}  // namespace pb::test
