// SPDX-License-Identifier: MIT
// PalletConfig: the centre of the contract. A validated, JSON-serialisable pallet: base, items,
// wrap, thermal state. Derived quantities live in pallet_metrics.hpp; reading and writing in
// json_io.hpp; the physical rules in validation.hpp.
#pragma once

#include <string>
#include <vector>

#include "core/base/enums.hpp"
#include "core/base/vec3.hpp"
#include "core/contract/item.hpp"

namespace pb {

/// Version of every JSON document the core writes. Readers accept documents without one (the
/// reference system's payloads) and reject newer versions.
inline constexpr int kSchemaVersion = 1;

struct PalletConfig {
  std::string pallet_id = "pallet";
  PalletType base_pallet_type = PalletType::eur;
  Vec3 base_dims_m{1.2, 0.8, 0.15};  ///< absent from a document: the type's (pallet_type.hpp)
  double base_mass_kg = 25.0;        ///< (0, 100]; absent: the type's tare
  std::vector<Item> items;
  WrapType wrap = WrapType::stretch;
  Environment env = Environment::refrigerated;
  double body_temp_c = 2.0;                   ///< [-40, 40]
  double seconds_since_temp_change = 3600.0;  ///< >= 0
  std::string notes;
  // Our additions (optional keys with defaults).
  BeltSurface belt_surface = BeltSurface::rubber_belt;

  bool operator==(const PalletConfig&) const = default;
};

}  // namespace pb
