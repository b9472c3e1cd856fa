// SPDX-License-Identifier: MIT
// Test helper: a friction model with constant coefficients per contact (one control point, so every
// temperature gives the same value; mu_d = mu_s unless told otherwise) and the reference's
// frost-melt penalty, so the physics tests know mu exactly.
#pragma once

#include <string>

#include "core/inputs/friction.hpp"

namespace pb::test {

/// The penalty block of the test tables: zone [-2, 8] C, 0.65 at its centre, 600 s recovery.
inline constexpr FrostMeltPenalty kTestPenalty{-2.0, 8.0, 0.65, 600.0};

struct ConstantMu {
  double belt_pallet = 1.0;  ///< wood_pallet/rubber_belt
  double item_pallet = 0.3;  ///< carton/wood_pallet
  double item_item = 0.4;    ///< carton/carton
  double kinetic = 1.0;      ///< mu_d / mu_s of every pair
};

/// The JSON text of a table with the constant coefficients of `mu` and kTestPenalty.
inline std::string constant_friction_json(const ConstantMu& mu) {
  auto pair = [&](const char* key, double value) {
    return std::string("\"") + key + "\": {\"description\": \"constant\", \"control_points\": " +
           "[{\"temp_c\": 0.0, \"mu_s\": " + std::to_string(value) +
           ", \"mu_d\": " + std::to_string(value * mu.kinetic) + "}]}";
  };
  return "{\"surface_pairs\": {" + pair("wood_pallet/rubber_belt", mu.belt_pallet) + ", " +
         pair("carton/wood_pallet", mu.item_pallet) + ", " + pair("carton/carton", mu.item_item) +
         "}, \"transition_penalty\": {\"danger_zone_temp_c\": [" +
         std::to_string(kTestPenalty.zone_lo_c) + ", " + std::to_string(kTestPenalty.zone_hi_c) +
         "], \"min_multiplier\": " + std::to_string(kTestPenalty.min_multiplier) +
         ", \"recovery_seconds\": " + std::to_string(kTestPenalty.recovery_s) + "}}";
}

/// The model of constant_friction_json(mu) (coefficients are written with six decimals, exact for
/// the values the tests use). Should the text not parse, the model is empty and every scene built
/// with it fails, naming the missing pair.
inline FrictionModel constant_friction(const ConstantMu& mu) {
  auto model = FrictionModel::from_json_text(constant_friction_json(mu));
  if (!model) return {};
  return std::move(*model.value);
}

}  // namespace pb::test
