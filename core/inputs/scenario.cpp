// SPDX-License-Identifier: MIT
#include "core/inputs/scenario.hpp"

#include <algorithm>

#include "core/base/resources.hpp"
#include "core/inputs/catalog.hpp"
#include "core/inputs/random_pallet.hpp"
#include "core/inputs/stack_builder.hpp"

namespace pb {

namespace {

constexpr std::string_view kScenarioDir = "scenarios/";

// Reads a string member; missing or not a string is an error at /<key>.
bool read_string(const Json& json, const char* key, std::string& out, Diagnostics& diags) {
  auto it = json.find(key);
  if (it == json.end() || !it->is_string()) {
    diags.push_back({std::string("/") + key,
                     std::string("'") + key + "' must be a string; add it to the scenario"});
    return false;
  }
  out = it->get<std::string>();
  return true;
}

template <class E>
bool read_enum(const Json& json, const char* key, E& out, Diagnostics& diags,
               const std::string& prefix) {
  auto it = json.find(key);
  if (it == json.end()) return true;  // keep the default
  if (it->is_string()) {
    if (auto v = enum_from_string<E>(it->get<std::string>())) {
      out = *v;
      return true;
    }
  }
  diags.push_back(
      {prefix + "/" + key, std::string("'") + key + "' must be one of " + enum_choices<E>()});
  return false;
}

bool read_number(const Json& json, const char* key, double& out, Diagnostics& diags,
                 const std::string& prefix) {
  auto it = json.find(key);
  if (it == json.end()) return true;
  if (!it->is_number()) {
    diags.push_back({prefix + "/" + key, std::string("'") + key + "' must be a number"});
    return false;
  }
  out = it->get<double>();
  return true;
}

bool read_int(const Json& json, const char* key, int& out, Diagnostics& diags,
              const std::string& prefix) {
  auto it = json.find(key);
  if (it == json.end()) return true;
  if (!it->is_number_integer()) {
    diags.push_back({prefix + "/" + key, std::string("'") + key + "' must be a whole number"});
    return false;
  }
  out = it->get<int>();
  return true;
}

Result<PalletConfig> build_stacks_recipe(const Json& recipe, const std::string& slug) {
  Diagnostics diags;
  std::vector<StackSpec> stacks;
  const Json& list = recipe["stacks"];
  if (!list.is_array()) return Result<PalletConfig>::failure("/recipe/stacks", "must be an array");
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string where = "/recipe/stacks/" + std::to_string(i);
    StackSpec s;
    if (!list[i].is_object() || !list[i].contains("sku") || !list[i]["sku"].is_string()) {
      diags.push_back({where, "each stack needs at least a string 'sku'"});
      continue;
    }
    s.sku = list[i]["sku"].get<std::string>();
    read_int(list[i], "row", s.row, diags, where);
    read_int(list[i], "col", s.col, diags, where);
    read_int(list[i], "height", s.height, diags, where);
    stacks.push_back(std::move(s));
  }
  StackBuildOptions options;
  options.pallet_id = slug;
  read_enum(recipe, "base_pallet_type", options.base_pallet_type, diags, "/recipe");
  read_enum(recipe, "wrap", options.wrap, diags, "/recipe");
  read_enum(recipe, "env", options.env, diags, "/recipe");
  read_number(recipe, "body_temp_c", options.body_temp_c, diags, "/recipe");
  read_number(recipe, "seconds_since_temp_change", options.seconds_since_temp_change, diags,
              "/recipe");
  if (has_errors(diags)) return Result<PalletConfig>::failure(std::move(diags));
  auto built = build_from_stacks(stacks, options, Catalog::builtin());
  for (auto& d : built.diagnostics) d.pointer = "/recipe" + d.pointer;
  return built;
}

Result<PalletConfig> build_random_recipe(const Json& recipe) {
  Diagnostics diags;
  const Json& r = recipe["random"];
  if (!r.is_object()) return Result<PalletConfig>::failure("/recipe/random", "must be an object");
  RandomPalletOptions options;
  if (!r.contains("seed") || !r["seed"].is_number_unsigned()) {
    return Result<PalletConfig>::failure("/recipe/random/seed",
                                         "the random recipe needs a non-negative integer seed");
  }
  options.seed = r["seed"].get<std::uint64_t>();
  read_number(r, "anomaly_rate", options.anomaly_rate, diags, "/recipe/random");
  read_int(r, "min_layers", options.min_layers, diags, "/recipe/random");
  read_int(r, "max_layers", options.max_layers, diags, "/recipe/random");
  read_int(r, "min_items_per_layer", options.min_items_per_layer, diags, "/recipe/random");
  read_int(r, "max_items_per_layer", options.max_items_per_layer, diags, "/recipe/random");
  for (auto d : validate_random_options(options)) {
    d.pointer = "/recipe/random" + d.pointer;
    diags.push_back(std::move(d));
  }
  if (has_errors(diags)) return Result<PalletConfig>::failure(std::move(diags));
  return random_pallet(options, Catalog::builtin());
}

}  // namespace

Json scenario_to_json(const Scenario& s) {
  Json j;
  j["schema_version"] = kSchemaVersion;
  j["order"] = s.order;
  j["slug"] = s.slug;
  j["name"] = s.name;
  j["tag"] = s.tag;
  j["description"] = s.description;
  j["expected_failure"] = s.expected_failure;
  j["recipe"] = s.recipe;
  j["pallet"] = pallet_to_json(s.pallet);
  j["suggested_profile"] = profile_to_json(s.suggested_profile);
  return j;
}

Result<Scenario> scenario_from_json(const Json& json) {
  if (!json.is_object()) return Result<Scenario>::failure("", "a scenario must be a JSON object");
  Scenario s;
  Diagnostics diags;
  read_string(json, "slug", s.slug, diags);
  read_string(json, "name", s.name, diags);
  read_string(json, "tag", s.tag, diags);
  read_string(json, "description", s.description, diags);
  read_string(json, "expected_failure", s.expected_failure, diags);
  read_int(json, "order", s.order, diags, "");
  if (auto it = json.find("recipe"); it != json.end()) s.recipe = *it;
  if (auto it = json.find("pallet"); it == json.end()) {
    diags.push_back({"/pallet", "the scenario has no 'pallet'; add the PalletConfig"});
  } else {
    auto pallet = pallet_from_json(*it, "/pallet");
    diags.insert(diags.end(), pallet.diagnostics.begin(), pallet.diagnostics.end());
    if (pallet) s.pallet = std::move(*pallet.value);
  }
  if (auto it = json.find("suggested_profile"); it == json.end()) {
    diags.push_back({"/suggested_profile", "the scenario has no 'suggested_profile'; add one"});
  } else {
    auto profile = profile_from_json(*it, "/suggested_profile");
    diags.insert(diags.end(), profile.diagnostics.begin(), profile.diagnostics.end());
    if (profile) s.suggested_profile = *profile.value;
  }
  if (has_errors(diags)) return Result<Scenario>::failure(std::move(diags));
  return Result<Scenario>{std::move(s), std::move(diags)};
}

std::vector<Scenario> all_scenarios() {
  std::vector<Scenario> out;
  for (std::string_view name : embedded_files(kScenarioDir)) {
    auto json = parse_json(*embedded_file(name));
    if (!json) continue;
    auto scenario = scenario_from_json(*json);
    if (scenario) out.push_back(std::move(*scenario.value));
  }
  std::stable_sort(out.begin(), out.end(),
                   [](const Scenario& a, const Scenario& b) { return a.order < b.order; });
  return out;
}

std::vector<std::string> scenario_slugs() {
  std::vector<std::string> slugs;
  for (const auto& s : all_scenarios()) slugs.push_back(s.slug);
  return slugs;
}

Result<Scenario> load_scenario(const std::string& slug) {
  const std::string name = std::string(kScenarioDir) + slug + ".json";
  auto text = embedded_file(name);
  if (!text) {
    std::string known;
    for (const auto& s : scenario_slugs()) known += (known.empty() ? "" : ", ") + s;
    return Result<Scenario>::failure("", "no curated scenario '" + slug + "'; known: " + known);
  }
  auto json = parse_json(*text);
  if (!json) return Result<Scenario>::failure(std::move(json.diagnostics));
  return scenario_from_json(*json);
}

Result<PalletConfig> build_from_recipe(const Scenario& scenario) {
  const Json& recipe = scenario.recipe;
  if (recipe.is_object() && recipe.contains("stacks")) {
    return build_stacks_recipe(recipe, scenario.slug);
  }
  if (recipe.is_object() && recipe.contains("random")) return build_random_recipe(recipe);
  return Result<PalletConfig>::failure(
      "/recipe", "the recipe must hold either 'stacks' (stack builder) or 'random' (adapter)");
}

}  // namespace pb
