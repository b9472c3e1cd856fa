// SPDX-License-Identifier: MIT
// Nominal data of the pallet base types: footprint, height, tare, deck material, rated load.
#pragma once

#include <string_view>

#include "core/base/enums.hpp"
#include "core/base/vec3.hpp"

namespace pb {

struct PalletTypeSpec {
  PalletType type;
  Vec3 dims_m;               ///< length (along +X, belt travel), width, deck height
  double mass_kg;            ///< tare
  std::string_view surface;  ///< deck/runner material as named in the friction tables
  double rated_load_kg;      ///< safe dynamic (conveyor-handled) load, excluding the tare
};

/// EUR (EPAL 1, 1200 x 800 mm, wood), GMA (48 x 40 in, wood), CHEP (1200 x 800 mm plastic pool
/// pallet). Dimensions follow the reference system (EUR base 0.15 m high, 25 kg); rated loads are
/// the dynamic ratings those pallets are sold with, which the reference's 1,200 kg cap sits under.
const PalletTypeSpec& pallet_type_spec(PalletType type);

}  // namespace pb
