// SPDX-License-Identifier: MIT
// One carton (or crate, sack, tub pack) on a pallet.
#pragma once

#include <string>

#include "core/base/enums.hpp"
#include "core/base/vec3.hpp"

namespace pb {

/// An item placed on a pallet. Frame: origin at the centre of the bottom face of the pallet base,
/// +X belt travel, +Y lateral, +Z up. `position` is the centre of the item's *bottom* face;
/// `orientation_deg` is a yaw about +Z in [-180, 180]; `dims_m` is (length along the item's own
/// x, width, height).
struct Item {
  std::string sku;
  double weight_kg = 10.0;  ///< (0, 500]
  Vec3 dims_m{0.4, 0.3, 0.2};
  Fragility fragility = Fragility::rigid;
  Vec3 position{0.0, 0.0, 0.15};
  double orientation_deg = 0.0;

  /// Geometric centre (uniform density): position + (0, 0, height / 2).
  Vec3 center_of_mass() const { return {position[0], position[1], position[2] + dims_m[2] / 2.0}; }
  /// Height of the top face above the pallet frame origin.
  double top_z() const { return position[2] + dims_m[2]; }

  bool operator==(const Item&) const = default;
};

}  // namespace pb
