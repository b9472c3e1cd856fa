// SPDX-License-Identifier: MIT
#include "core/contract/pallet_type.hpp"

#include <array>

namespace pb {

const PalletTypeSpec& pallet_type_spec(PalletType type) {
  // EPAL 1: 1200 x 800 x 144 mm, 25 kg, 1500 kg dynamic load (the reference rounds the height to
  // 0.15 m; we keep its value so reference payloads mean the same pallet). GMA: 48 x 40 x 5.5 in,
  // about 17 kg (hardwood stringer), 1270 kg (2800 lb) dynamic. CHEP plastic 1200 x 800: about
  // 20 kg, 1250 kg dynamic.
  static const std::array<PalletTypeSpec, 3> specs{{
      {PalletType::eur, {1.2, 0.8, 0.15}, 25.0, "wood_pallet", 1500.0},
      {PalletType::gma, {1.219, 1.016, 0.14}, 17.0, "wood_pallet", 1270.0},
      {PalletType::chep, {1.2, 0.8, 0.15}, 20.0, "plastic_pallet", 1250.0},
  }};
  for (const auto& spec : specs) {
    if (spec.type == type) return spec;
  }
  return specs[0];
}

}  // namespace pb
