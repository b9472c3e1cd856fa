// SPDX-License-Identifier: MIT
// The curated scenarios: scenarios/<slug>.json, compiled into palletcore.
#pragma once

#include <string>
#include <vector>

#include "core/base/diagnostic.hpp"
#include "core/contract/conveyor_profile.hpp"
#include "core/contract/json_io.hpp"
#include "core/contract/pallet_config.hpp"

namespace pb {

struct Scenario {
  int order = 0;  ///< display order of the curated set
  std::string slug;
  std::string name;
  std::string tag;
  std::string description;
  std::string expected_failure;
  Json recipe;  ///< how the pallet was built: {"stacks": [...], ...} or {"random": {...}}
  PalletConfig pallet;
  ConveyorProfile suggested_profile;
};

Json scenario_to_json(const Scenario& scenario);
Result<Scenario> scenario_from_json(const Json& json);

/// Slugs of the curated scenarios, in display order.
std::vector<std::string> scenario_slugs();
/// A curated scenario by slug; an unknown slug is an error that lists the known ones.
Result<Scenario> load_scenario(const std::string& slug);
/// Every curated scenario in display order (each validated by the tests).
std::vector<Scenario> all_scenarios();

/// The pallet its recipe builds today (build_from_stacks or random_pallet): the stored pallet must
/// equal it, which the tests check.
Result<PalletConfig> build_from_recipe(const Scenario& scenario);

}  // namespace pb
