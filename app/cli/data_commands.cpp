// SPDX-License-Identifier: MIT
// Verbs over the contract and the data: scenarios, catalog, validate, random, friction.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <sstream>

#include "app/cli/commands.hpp"
#include "core/analysis/analyzer.hpp"
#include "core/analysis/result_json.hpp"
#include "core/base/text.hpp"
#include "core/contract/pallet_metrics.hpp"
#include "core/inputs/catalog.hpp"
#include "core/inputs/friction.hpp"
#include "core/inputs/random_pallet.hpp"
#include "core/inputs/scenario.hpp"
#include "core/inputs/validation.hpp"

namespace pb::cli {

std::optional<std::string> read_input(const std::string& path) {
  auto text = read_document_text(path);
  if (!text) std::cerr << "palletballet-cli: cannot open '" << path << "'; check the path\n";
  return text;
}

void print_json(const Json& json) {
  std::cout << json.dump(2, ' ', false, Json::error_handler_t::replace) << "\n";
}

void print_diagnostics(const Diagnostics& diagnostics) {
  for (const auto& d : condensed(diagnostics)) std::cerr << to_string(d) << "\n";
}

namespace {

// ---- scenarios ----

int run_scenarios(const Args& args) {
  if (auto path = args.text("rebuild")) {
    auto text = read_input(*path);
    if (!text) return kExitBadInput;
    auto json = parse_json(*text);
    if (!json) {
      print_diagnostics(json.diagnostics);
      return kExitBadInput;
    }
    // The pallet is what the recipe builds; a scenario being written may not have one yet.
    if (json->is_object() && !json->contains("pallet")) (*json)["pallet"] = pallet_to_json({});
    auto scenario = scenario_from_json(*json);
    if (!scenario) {
      print_diagnostics(scenario.diagnostics);
      return kExitBadInput;
    }
    auto built = build_from_recipe(*scenario);
    if (!built) {
      print_diagnostics(built.diagnostics);
      return kExitBadInput;
    }
    scenario->pallet = std::move(*built.value);
    print_json(scenario_to_json(*scenario));
    return kExitOk;
  }
  if (!args.positionals().empty()) {
    auto scenario = load_scenario(args.positionals()[0]);
    if (!scenario) {
      print_diagnostics(scenario.diagnostics);
      return kExitBadInput;
    }
    print_json(scenario_to_json(*scenario));
    return kExitOk;
  }
  const bool check = args.flag("check");
  bool all_valid = true;
  Json list = Json::array();
  for (const auto& s : all_scenarios()) {
    Json entry = {{"order", s.order},
                  {"slug", s.slug},
                  {"name", s.name},
                  {"tag", s.tag},
                  {"expected_failure", s.expected_failure}};
    if (check) {
      const Diagnostics diags = validate(s.pallet);
      auto rebuilt = build_from_recipe(s);
      const bool matches = rebuilt.ok() && *rebuilt.value == s.pallet;
      entry["validation"] = validation_report_to_json(s.pallet, diags);
      entry["recipe_matches"] = matches;
      const bool ok = !has_errors(diags) && matches;
      all_valid = all_valid && ok;
      std::cerr << (ok ? "ok      " : "INVALID ") << s.slug << ": " << s.pallet.items.size()
                << " items, " << total_mass_kg(s.pallet) << " kg, " << stack_height_m(s.pallet)
                << " m high, " << warnings_of(diags).size() << " warning(s)"
                << (matches ? "" : ", pallet differs from what its recipe builds") << "\n";
      for (const auto& d : errors_of(diags)) std::cerr << "        " << to_string(d) << "\n";
    }
    list.push_back(std::move(entry));
  }
  print_json(list);
  return all_valid ? kExitOk : kExitBadInput;
}

// ---- catalog ----

int run_catalog(const Args& args) {
  std::optional<Environment> env;
  if (auto e = args.text("env")) {
    env = enum_from_string<Environment>(*e);
    if (!env) throw UsageError{"catalog: --env must be " + enum_choices<Environment>()};
  }
  Json list = Json::array();
  for (const auto& t : Catalog::builtin().all()) {
    if (env && t.default_env != *env) continue;
    list.push_back({{"sku", t.sku},
                    {"name", t.name},
                    {"weight_kg", t.weight_kg},
                    {"dims_m", t.dims_m},
                    {"fragility", to_string(t.fragility)},
                    {"category", t.category},
                    {"default_env", to_string(t.default_env)}});
  }
  print_json(list);
  return kExitOk;
}

// ---- validate ----

ValidationLimits limits_from(const Args& args) {
  ValidationLimits limits;
  if (auto v = args.number("max-overhang")) {  // 0: nothing may reach beyond the deck
    if (!(*v >= 0.0 && *v <= 1.0)) {
      throw UsageError{"validate: --max-overhang must be from 0 to 1 m, got " + short_number(*v)};
    }
    limits.max_overhang_m = *v;
  }
  limits.max_stack_height_m =
      option_in_range(args, "validate", "max-height", limits.max_stack_height_m, 0.0, 10.0, "m");
  limits.max_gross_mass_kg =
      option_in_range(args, "validate", "max-mass", limits.max_gross_mass_kg, 0.0, 1e5, "kg");
  limits.require_known_skus = args.flag("require-known-skus");
  return limits;
}

int run_validate(const Args& args) {
  const ValidationLimits limits = limits_from(args);
  auto input = read_pallet_source(args.positionals()[0]);
  Diagnostics diags = input.diagnostics;
  if (input) {
    for (auto d : validate(input->pallet, limits)) {
      d.pointer = input->pointer_prefix + d.pointer;
      diags.push_back(std::move(d));
    }
    // Valid here means an analysis will not refuse it either (no friction data for a pair, a
    // scene larger than the engine holds).
    if (!has_errors(diags)) {
      for (auto d : Analyzer().simulation_problems(input->pallet)) {
        d.pointer = input->pointer_prefix + d.pointer;
        diags.push_back(std::move(d));
      }
    }
  }
  print_diagnostics(diags);
  if (input) {
    print_json(validation_report_to_json(input->pallet, diags, limits.max_items));
  } else {
    print_json({{"valid", false}, {"errors", diagnostics_to_json(errors_of(diags))}});
  }
  return has_errors(diags) ? kExitBadInput : kExitOk;
}

// ---- random ----

int run_random(const Args& args) {
  RandomPalletOptions options;
  if (auto v = args.integer("seed")) {
    if (*v < 0) throw UsageError{"random: --seed must be a non-negative whole number"};
    options.seed = static_cast<std::uint64_t>(*v);
  }
  if (auto v = args.number("anomaly-rate")) options.anomaly_rate = *v;
  auto to_int = [](std::int64_t v) {
    return static_cast<int>(std::clamp<std::int64_t>(v, -1, 1000));
  };
  if (auto v = args.integer("min-layers")) options.min_layers = to_int(*v);
  if (auto v = args.integer("max-layers")) options.max_layers = to_int(*v);
  if (auto v = args.integer("min-items")) options.min_items_per_layer = to_int(*v);
  if (auto v = args.integer("max-items")) options.max_items_per_layer = to_int(*v);
  options.wrap = random_wrap_option(args, "random", options.wrap);
  Diagnostics problems = validate_random_options(options);
  if (has_errors(problems)) {
    // Name the flags, not the struct fields.
    for (auto& d : problems) {
      std::string flag = d.pointer.substr(1);
      std::replace(flag.begin(), flag.end(), '_', '-');
      if (flag == "min-items-per-layer") flag = "min-items";
      if (flag == "max-items-per-layer") flag = "max-items";
      std::cerr << "palletballet-cli random: --" << flag << ": " << d.message << "\n";
    }
    return kExitBadInput;
  }
  auto pallet = random_pallet(options, Catalog::builtin());
  if (!pallet) {
    print_diagnostics(pallet.diagnostics);
    return kExitFailure;
  }
  print_json(pallet_to_json(*pallet));
  return kExitOk;
}

// ---- friction ----

int run_friction(const Args& args) {
  const FrictionModel& model = FrictionModel::builtin();
  const double t0 = args.number("from").value_or(-30.0);
  const double t1 = args.number("to").value_or(30.0);
  const double step = args.number("step").value_or(1.0);
  const double since = args.number("since").value_or(3600.0);
  // The range a pallet's body_temp_c may take (validation) and the service's friction routes.
  for (const auto& [flag, t] : {std::pair{"from", t0}, std::pair{"to", t1}}) {
    if (!(t >= kMinTempC && t <= kMaxTempC)) {
      throw UsageError{std::string("friction: --") + flag + " is " + short_number(t) +
                       "; the friction tables cover " + short_number(kMinTempC) + " to " +
                       short_number(kMaxTempC) + " C"};
    }
  }
  if (t1 < t0) throw UsageError{"friction: --to must not be below --from"};
  if (step <= 0.0 || (t1 - t0) / step > 100000.0) {
    throw UsageError{"friction: --step must be positive and give at most 100000 samples"};
  }
  if (since < 0.0) throw UsageError{"friction: --since must be >= 0 seconds"};
  std::vector<std::string> keys = model.pair_keys();
  if (auto pair = args.text("pair")) {
    if (model.find(*pair) == nullptr) {
      std::string known;
      for (const auto& k : keys) known += (known.empty() ? "" : ", ") + k;
      throw UsageError{"friction: unknown --pair '" + *pair + "'; known pairs: " + known};
    }
    keys = {*pair};
  }
  const FrostMeltPenalty& p = model.penalty();
  Json out;
  out["seconds_since_temp_change"] = since;
  out["transition_penalty"] = {{"danger_zone_temp_c", {p.zone_lo_c, p.zone_hi_c}},
                               {"min_multiplier", p.min_multiplier},
                               {"recovery_seconds", p.recovery_s}};
  out["pairs"] = Json::array();
  for (const auto& key : keys) {
    const SurfacePair* pair = model.find(key);
    Json samples = Json::array();
    for (const auto& s : model.curve(key, t0, t1, step, since)) {
      samples.push_back({{"temp_c", s.temp_c},
                         {"mu_s", s.steady.mu_s},
                         {"mu_d", s.steady.mu_d},
                         {"penalty", s.effective.penalty},
                         {"mu_s_effective", s.effective.mu_s},
                         {"mu_d_effective", s.effective.mu_d}});
    }
    out["pairs"].push_back({{"pair", key},
                            {"description", pair->description},
                            {"source", pair->source},
                            {"samples", std::move(samples)}});
  }
  print_json(out);
  return kExitOk;
}

}  // namespace

std::vector<Command> data_commands() {
  return {
      {{"scenarios",
        "scenarios [SLUG] [--check] [--rebuild FILE|-]",
        "List the curated scenarios, print one (SLUG), check that every one validates and matches "
        "its recipe (--check, exit 2 if not), or rebuild a scenario's pallet from its recipe.",
        {{"check", "", "validate every scenario; a summary line per scenario on stderr"},
         {"rebuild", "FILE", "print the scenario in FILE with its pallet rebuilt from its recipe"}},
        0,
        1},
       run_scenarios},
      {{"catalog",
        "catalog [--env ENV]",
        "The SKU catalog as JSON.",
        {{"env", "ENV",
          "only SKUs whose default environment is ENV (" + enum_choices<Environment>() + ")"}},
        0,
        0},
       run_catalog},
      {{"validate",
        "validate FILE|-|SLUG [--require-known-skus] [--max-overhang M] "
        "[--max-height M] [--max-mass KG]",
        "Read and validate a PalletConfig (or a scenario's pallet, or a curated scenario's). Exit "
        "0 if valid; exit 2 with "
        "every error on stderr as 'pointer: message'. A JSON report goes to stdout.",
        {{"require-known-skus", "", "every item's SKU must be in the catalog"},
         {"max-overhang", "M", "overhang limit in metres (default 0.10)"},
         {"max-height", "M", "stack height cap in metres (default 1.85)"},
         {"max-mass", "KG", "gross mass cap in kg (default 1200)"}},
        1,
        1},
       run_validate},
      {{"random",
        "random --seed N [--anomaly-rate R] [--min-layers A --max-layers B] "
        "[--min-items A --max-items B] [--wrap W]",
        "A random pallet from the seeded scanner adapter (same seed, same bytes). Every pallet it "
        "makes validates and stands, wrapped or not.",
        {{"seed", "N", "seed (default 0)"},
         {"anomaly-rate", "R", "probability of a lean/overhang anomaly, 0..1 (default 0.08)"},
         {"min-layers", "A", "fewest layers (default 3)"},
         {"max-layers", "B", "most layers (default 7)"},
         {"min-items", "A",
          "fewest items per layer (default 4; a column pallet, drawn for about one seed in five, "
          "is a tower of at most 2 a layer whatever this asks)"},
         {"max-items", "B",
          "most items per layer (default 10; below 4 only the patterns that can hold so few are "
          "drawn: column, and irregular from 3)"},
         {"wrap", "W",
          "none, shrink, stretch, banded, or mixed (drawn per pallet; default stretch)"}},
        0,
        0},
       run_random},
      {{"friction",
        "friction [--pair P] [--from T0 --to T1 --step S] [--since SECONDS]",
        "Friction against temperature for every surface pair (or one), steady and with the "
        "frost-melt penalty at SECONDS since the temperature changed.",
        {{"pair", "P", "one surface pair, e.g. wood_pallet/rubber_belt"},
         {"from", "T0", "first temperature, C (default -30)"},
         {"to", "T1", "last temperature, C (default 30)"},
         {"step", "S", "temperature step, C (default 1)"},
         {"since", "SECONDS", "seconds since the temperature changed (default 3600)"}},
        0,
        0},
       run_friction},
  };
}

std::optional<WrapType> random_wrap_option(const Args& args, const std::string& command,
                                           std::optional<WrapType> fallback) {
  const auto text = args.text("wrap");
  if (!text) return fallback;
  if (*text == "mixed") return std::nullopt;
  if (auto wrap = enum_from_string<WrapType>(*text)) return wrap;
  throw UsageError{command + ": --wrap is '" + *text + "'; use " + enum_choices<WrapType>() +
                   " for every pallet, or mixed to draw one per pallet"};
}

}  // namespace pb::cli
