// SPDX-License-Identifier: MIT
#include "core/inputs/scenario.hpp"

#include <algorithm>

#include "core/base/resources.hpp"
#include "core/contract/json_reader.hpp"
#include "core/inputs/catalog.hpp"
#include "core/inputs/random_pallet.hpp"
#include "core/inputs/stack_builder.hpp"

namespace pb {

namespace {

constexpr std::string_view kScenarioDir = "scenarios/";

// The pallet the recipe's stacks build, with the diagnostics of reading the recipe before those of
// building it.
Result<PalletConfig> build_stacks_recipe(const Json& recipe, const std::string& slug) {
  JsonReader reader;
  const std::string where = "/recipe";
  reader.unknown_keys(
      recipe, where,
      {"stacks", "base_pallet_type", "wrap", "env", "body_temp_c", "seconds_since_temp_change"});
  std::vector<StackSpec> stacks;
  const std::string list_where = member_pointer(where, "stacks");
  const Json& list = recipe["stacks"];
  if (reader.array(list, list_where, "the stacks",
                   "[{\"sku\": ..., \"row\": ..., \"col\": ..., \"height\": ...}, ...]")) {
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string stack_where = element_pointer(list_where, i);
      if (!reader.object(list[i], stack_where, "a stack",
                         "{\"sku\": ..., \"row\": ..., \"col\": ..., \"height\": ...}")) {
        continue;
      }
      reader.unknown_keys(list[i], stack_where, {"sku", "row", "col", "height"});
      StackSpec s;
      bool ok = reader.field(list[i], stack_where, "sku", s.sku, Need::required);
      ok = reader.field(list[i], stack_where, "row", s.row) && ok;
      ok = reader.field(list[i], stack_where, "col", s.col) && ok;
      ok = reader.field(list[i], stack_where, "height", s.height) && ok;
      if (ok) stacks.push_back(std::move(s));
    }
  }
  StackBuildOptions options;
  options.pallet_id = slug;
  reader.field(recipe, where, "base_pallet_type", options.base_pallet_type);
  reader.field(recipe, where, "wrap", options.wrap);
  reader.field(recipe, where, "env", options.env);
  reader.field(recipe, where, "body_temp_c", options.body_temp_c);
  reader.field(recipe, where, "seconds_since_temp_change", options.seconds_since_temp_change);
  if (has_errors(reader.diagnostics)) return Result<PalletConfig>::failure(reader.diagnostics);
  auto built = build_from_stacks(stacks, options, Catalog::builtin());
  for (auto& d : built.diagnostics) d.pointer = where + d.pointer;
  built.diagnostics.insert(built.diagnostics.begin(), reader.diagnostics.begin(),
                           reader.diagnostics.end());
  return built;
}

// The pallet the random recipe draws, with the diagnostics of reading the recipe before those of
// drawing it.
Result<PalletConfig> build_random_recipe(const Json& recipe) {
  JsonReader reader;
  reader.unknown_keys(recipe, "/recipe", {"random"});
  const std::string where = "/recipe/random";
  const Json& r = recipe["random"];
  if (!reader.object(r, where, "the random recipe",
                     "{\"seed\": ..., \"anomaly_rate\": ..., \"min_layers\": ..., ...}")) {
    return Result<PalletConfig>::failure(reader.diagnostics);
  }
  reader.unknown_keys(r, where,
                      {"seed", "anomaly_rate", "min_layers", "max_layers", "min_items_per_layer",
                       "max_items_per_layer"});
  RandomPalletOptions options;
  reader.field(r, where, "seed", options.seed, Need::required);
  reader.field(r, where, "anomaly_rate", options.anomaly_rate);
  reader.field(r, where, "min_layers", options.min_layers);
  reader.field(r, where, "max_layers", options.max_layers);
  reader.field(r, where, "min_items_per_layer", options.min_items_per_layer);
  reader.field(r, where, "max_items_per_layer", options.max_items_per_layer);
  if (has_errors(reader.diagnostics)) return Result<PalletConfig>::failure(reader.diagnostics);
  for (auto d : validate_random_options(options)) {
    d.pointer = where + d.pointer;
    reader.diagnostics.push_back(std::move(d));
  }
  if (has_errors(reader.diagnostics)) return Result<PalletConfig>::failure(reader.diagnostics);
  auto drawn = random_pallet(options, Catalog::builtin());
  drawn.diagnostics.insert(drawn.diagnostics.begin(), reader.diagnostics.begin(),
                           reader.diagnostics.end());
  return drawn;
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
  JsonReader reader;
  Scenario s;
  if (!reader.object(json, "", "a scenario")) return reader.finish(std::move(s));
  reader.schema_version(json, "");
  reader.unknown_keys(json, "",
                      {"schema_version", "order", "slug", "name", "tag", "description",
                       "expected_failure", "recipe", "pallet", "suggested_profile"});
  reader.field(json, "", "slug", s.slug, Need::required);
  reader.field(json, "", "name", s.name, Need::required);
  reader.field(json, "", "tag", s.tag, Need::required);
  reader.field(json, "", "description", s.description, Need::required);
  reader.field(json, "", "expected_failure", s.expected_failure, Need::required);
  reader.field(json, "", "order", s.order);
  if (const Json* recipe = reader.member(json, "", "recipe", Need::optional)) s.recipe = *recipe;
  if (const Json* pallet = reader.member(json, "", "pallet", Need::required)) {
    auto read = pallet_from_json(*pallet, "/pallet");
    reader.merge(read.diagnostics);
    if (read) s.pallet = std::move(*read.value);
  }
  if (const Json* profile = reader.member(json, "", "suggested_profile", Need::required)) {
    auto read = profile_from_json(*profile, "/suggested_profile");
    reader.merge(read.diagnostics);
    if (read) s.suggested_profile = *read.value;
  }
  return reader.finish(std::move(s));
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
