// SPDX-License-Identifier: MIT
#include "core/inputs/random_pallet.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/base/rng.hpp"
#include "core/base/text.hpp"
#include "core/contract/pallet_metrics.hpp"
#include "core/contract/pallet_type.hpp"

namespace pb {

namespace {

constexpr int kMaxLayers = 50;
constexpr int kMaxItemsPerLayer = 100;

struct EnvChoice {
  Environment env;
  double weight;
  double temp_lo_c;
  double temp_hi_c;
};
constexpr EnvChoice kEnvs[] = {{Environment::frozen, 0.45, -25.0, -18.0},
                               {Environment::refrigerated, 0.35, 0.0, 5.0},
                               {Environment::thawed, 0.10, 15.0, 22.0},
                               {Environment::transitioning, 0.10, -2.0, 8.0}};

struct PatternChoice {
  LayerPattern pattern;
  double weight;
  int min_items_per_layer;  ///< below this the pattern is not the pattern
};
constexpr PatternChoice kPatterns[] = {{LayerPattern::brick, 0.55, 4},
                                       {LayerPattern::column, 0.20, 1},
                                       {LayerPattern::pinwheel, 0.20, 4},
                                       {LayerPattern::irregular, 0.05, 3}};
constexpr int kMaxColumnItemsPerLayer = 2;  // a column pallet is a tower, not a slab

enum class Homogeneity { single_sku, sku_per_layer, mixed };
constexpr Homogeneity kHomogeneities[] = {Homogeneity::single_sku, Homogeneity::sku_per_layer,
                                          Homogeneity::mixed};
constexpr double kHomogeneityWeights[] = {0.70, 0.20, 0.10};

constexpr WrapType kWraps[] = {WrapType::none, WrapType::shrink, WrapType::stretch,
                               WrapType::banded};

constexpr PalletType kBases[] = {PalletType::eur, PalletType::gma, PalletType::chep};
constexpr double kBaseWeights[] = {0.55, 0.35, 0.10};

constexpr double kLeanLoDeg = 2.0, kLeanHiDeg = 8.0;
constexpr double kOverhangLoM = 0.025, kOverhangHiM = 0.10;
constexpr double kTransitionLoS = 30.0, kTransitionHiS = 300.0;
constexpr double kSettledLoS = 1800.0, kSettledHiS = 7200.0;

// A height cap for layouts that are about to be trimmed to the real one.
constexpr double kUncappedHeightM = 1e6;

template <class T, std::size_t N>
std::array<double, N> weights_of(const T (&choices)[N]) {
  std::array<double, N> w{};
  for (std::size_t i = 0; i < N; ++i) w[i] = choices[i].weight;
  return w;
}

// The environment's default products (transitioning loads are frozen ones warming up); the whole
// catalog when it has none.
std::vector<const SkuTemplate*> sku_pool(Environment env, const Catalog& catalog) {
  auto pool = catalog.for_env(env == Environment::transitioning ? Environment::frozen : env);
  if (pool.empty()) {
    for (const SkuTemplate& sku : catalog.all()) pool.push_back(&sku);
  }
  return pool;
}

std::vector<std::string> pick_skus(Rng& rng, const std::vector<const SkuTemplate*>& pool,
                                   Homogeneity mode, int layers, int items_per_layer) {
  std::vector<std::string> skus;
  if (pool.empty()) return skus;
  const int last = static_cast<int>(pool.size()) - 1;
  auto draw = [&] { return pool[static_cast<std::size_t>(rng.uniform_int(0, last))]->sku; };
  const std::size_t n = static_cast<std::size_t>(layers * items_per_layer);
  switch (mode) {
    case Homogeneity::single_sku:
      skus.assign(n, draw());
      break;
    case Homogeneity::sku_per_layer:
      for (int l = 0; l < layers; ++l) {
        skus.insert(skus.end(), static_cast<std::size_t>(items_per_layer), draw());
      }
      break;
    case Homogeneity::mixed:
      for (std::size_t i = 0; i < n; ++i) skus.push_back(draw());
      break;
  }
  return skus;
}

// The barcodes of `inputs` cut to `layers` layers of the first `items_per_layer` of each.
ScannerInputs cut(const ScannerInputs& inputs, int layers, int items_per_layer) {
  ScannerInputs out = inputs;
  out.layers = layers;
  out.items_per_layer = items_per_layer;
  out.skus.clear();
  for (int l = 0; l < layers; ++l) {
    for (int k = 0; k < items_per_layer; ++k) {
      out.skus.push_back(inputs.skus[static_cast<std::size_t>(l * inputs.items_per_layer + k)]);
    }
  }
  return out;
}

double gross_mass_kg(const ScannerInputs& inputs, const Catalog& catalog) {
  double mass = pallet_type_spec(inputs.base_pallet_type).mass_kg;
  for (const std::string& sku : inputs.skus) mass += catalog.find(sku)->weight_kg;
  return mass;
}

// The least the stack can stand above the floor: every column carries at least each layer's
// shortest carton. Above the cap, a layer goes without laying anything out (forty layers asked of
// a 1.85 m cap would otherwise be laid out past the validator's 10 m coordinates first).
double least_stack_height_m(const ScannerInputs& inputs, const Catalog& catalog) {
  double height = pallet_type_spec(inputs.base_pallet_type).dims_m[2];
  for (int l = 0; l < inputs.layers; ++l) {
    double shortest = std::numeric_limits<double>::infinity();
    for (int k = 0; k < inputs.items_per_layer; ++k) {
      const auto& sku = inputs.skus[static_cast<std::size_t>(l * inputs.items_per_layer + k)];
      shortest = std::min(shortest, catalog.find(sku)->dims_m[2]);
    }
    height += shortest;
  }
  return height;
}

// "homogeneous", "one SKU per layer" or "mixed", as the barcodes read.
std::string homogeneity_of(const ScannerInputs& inputs) {
  const auto& skus = inputs.skus;
  if (std::all_of(skus.begin(), skus.end(), [&](const auto& s) { return s == skus.front(); })) {
    return "homogeneous";
  }
  for (std::size_t i = 0; i < skus.size(); ++i) {
    const std::size_t first = i - i % static_cast<std::size_t>(inputs.items_per_layer);
    if (skus[i] != skus[first]) return "mixed";
  }
  return "one SKU per layer";
}

// Why the top layers went: each rule that took at least one.
struct Trimmed {
  bool mass = false, height = false, stand = false;
};

std::string notes_for(const RandomPalletOptions& options, const ScannerInputs& drawn,
                      const ScannerInputs& built, const Trimmed& trimmed,
                      const Diagnostics& layout_warnings) {
  std::string notes = "random seed " + std::to_string(options.seed) + ": " +
                      std::string(to_string(built.pattern)) + " " +
                      std::to_string(built.items_per_layer) + "x" + std::to_string(built.layers) +
                      " on " + std::string(to_string(built.base_pallet_type)) + ", " +
                      homogeneity_of(built) + ", " + std::string(to_string(built.env));
  if (drawn.lean_angle_deg != 0.0 || drawn.top_overhang_m != 0.0) {
    notes += "; anomaly: lean " + fixed(drawn.lean_angle_deg, 1) + " deg, top overhang " +
             fixed(drawn.top_overhang_m * 100.0, 1) + " cm";
  }
  if (built.items_per_layer < drawn.items_per_layer) {
    notes += "; " + std::to_string(drawn.items_per_layer) + " cartons a layer reduced to " +
             std::to_string(built.items_per_layer) + " to fit the deck";
  }
  for (const Diagnostic& d : layout_warnings) {
    if (d.pointer == "/lean_angle_deg" || d.pointer == "/pattern") notes += "; " + d.message;
  }
  if (built.layers < drawn.layers) {
    std::vector<std::string> why;
    if (trimmed.mass) why.emplace_back("the mass cap");
    if (trimmed.height) why.emplace_back("the height cap");
    if (trimmed.stand) why.emplace_back("so that every item stands");
    notes += "; trimmed from " + std::to_string(drawn.layers) + " layers for ";
    for (std::size_t i = 0; i < why.size(); ++i) {
      if (i > 0) notes += i + 1 == why.size() ? " and " : ", ";
      notes += why[i];
    }
  }
  return notes;
}

bool only_fit_error(const Diagnostics& diags) {
  return std::all_of(diags.begin(), diags.end(), [](const Diagnostic& d) {
    return d.severity == Severity::warning || d.pointer == "/items_per_layer";
  });
}

}  // namespace

Diagnostics validate_random_options(const RandomPalletOptions& options) {
  Diagnostics diags;
  if (!(options.anomaly_rate >= 0.0 && options.anomaly_rate <= 1.0)) {
    diags.push_back({"/anomaly_rate", "anomaly_rate " + fixed(options.anomaly_rate, 3) +
                                          " is not a probability; use 0..1 (0.08 is typical)"});
  }
  auto check_range = [&](const char* lo_key, int lo, const char* hi_key, int hi, int cap,
                         const char* what) {
    if (lo < 1 || lo > cap) {
      diags.push_back({std::string("/") + lo_key, std::string(lo_key) + " " + std::to_string(lo) +
                                                      " is out of range; use 1.." +
                                                      std::to_string(cap) + " " + what});
    }
    if (hi < lo || hi > cap) {
      diags.push_back({std::string("/") + hi_key, std::string(hi_key) + " " + std::to_string(hi) +
                                                      " must lie in " + std::string(lo_key) + ".." +
                                                      std::to_string(cap) + " " + what + " (" +
                                                      lo_key + " is " + std::to_string(lo) + ")"});
    }
  };
  check_range("min_layers", options.min_layers, "max_layers", options.max_layers, kMaxLayers,
              "layers");
  check_range("min_items_per_layer", options.min_items_per_layer, "max_items_per_layer",
              options.max_items_per_layer, kMaxItemsPerLayer, "items per layer");
  return diags;
}

ScannerInputs random_scanner_inputs(const RandomPalletOptions& options, const Catalog& catalog) {
  Rng rng(options.seed);
  const EnvChoice& env = kEnvs[rng.weighted_index(weights_of(kEnvs))];
  // A pattern that needs more items a layer than asked for is not drawn (the column always can
  // be); the draw is the same one as ever when every pattern can.
  std::array<double, std::size(kPatterns)> pattern_weights = weights_of(kPatterns);
  for (std::size_t i = 0; i < pattern_weights.size(); ++i) {
    if (kPatterns[i].min_items_per_layer > options.max_items_per_layer) pattern_weights[i] = 0.0;
  }
  const PatternChoice& pattern = kPatterns[rng.weighted_index(pattern_weights)];
  const Homogeneity homogeneity = kHomogeneities[rng.weighted_index(kHomogeneityWeights)];
  const PalletType base = kBases[rng.weighted_index(kBaseWeights)];

  int ti_lo = std::max(pattern.min_items_per_layer, options.min_items_per_layer);
  int ti_hi = std::max(ti_lo, options.max_items_per_layer);
  if (pattern.pattern == LayerPattern::column) {
    ti_hi = std::min(ti_hi, kMaxColumnItemsPerLayer);
    ti_lo = std::min(ti_lo, ti_hi);
  }

  ScannerInputs inputs;
  inputs.pallet_id = "R-" + std::to_string(options.seed);
  inputs.base_pallet_type = base;
  inputs.pattern = pattern.pattern;
  inputs.items_per_layer = rng.uniform_int(ti_lo, ti_hi);
  inputs.layers = rng.uniform_int(options.min_layers, options.max_layers);
  if (rng.bernoulli(options.anomaly_rate)) {
    inputs.lean_angle_deg = rng.uniform(kLeanLoDeg, kLeanHiDeg);
    inputs.top_overhang_m = rng.uniform(kOverhangLoM, kOverhangHiM);
  }
  inputs.skus = pick_skus(rng, sku_pool(env.env, catalog), homogeneity, inputs.layers,
                          inputs.items_per_layer);
  inputs.env = env.env;
  inputs.body_temp_c = rng.uniform(env.temp_lo_c, env.temp_hi_c);
  inputs.seconds_since_temp_change = env.env == Environment::transitioning
                                         ? rng.uniform(kTransitionLoS, kTransitionHiS)
                                         : rng.uniform(kSettledLoS, kSettledHiS);
  inputs.wrap = options.wrap ? *options.wrap : kWraps[std::size_t(rng.uniform_int(0, 3))];
  return inputs;
}

Result<PalletConfig> random_pallet(const RandomPalletOptions& options, const Catalog& catalog,
                                   const ValidationLimits& limits) {
  if (Diagnostics diags = validate_random_options(options); has_errors(diags)) {
    return Result<PalletConfig>::failure(std::move(diags));
  }
  const ScannerInputs drawn = random_scanner_inputs(options, catalog);
  if (drawn.skus.empty()) {
    return Result<PalletConfig>::failure("", "the catalog has no SKUs to draw from; load one");
  }
  const PalletTypeSpec& spec = pallet_type_spec(drawn.base_pallet_type);
  const double mass_cap = std::min(limits.max_gross_mass_kg, spec.rated_load_kg + spec.mass_kg);
  ValidationLimits uncapped = limits;
  uncapped.max_stack_height_m = kUncappedHeightM;
  uncapped.check_standing = false;  // the layout as drawn; whether it stands is asked below

  int layers = drawn.layers;
  int items_per_layer = drawn.items_per_layer;
  // First what fits the deck, on two layers (a brick's or pinwheel's alternate layer differs):
  // the caps then trim layers of what is really laid (83 drawn a layer, 9 fit: five layers of 9
  // are under the mass cap where five of 83 are not).
  while (items_per_layer > 1) {
    const auto fits =
        build_from_scanner(cut(drawn, std::min(layers, 2), items_per_layer), catalog, uncapped);
    if (fits || !only_fit_error(fits.diagnostics)) break;
    --items_per_layer;
  }
  Trimmed trimmed;
  for (;;) {
    ScannerInputs attempt = cut(drawn, layers, items_per_layer);
    if (layers > 1 && gross_mass_kg(attempt, catalog) > mass_cap) {
      trimmed.mass = true;
      --layers;
      continue;
    }
    if (layers > 1 && least_stack_height_m(attempt, catalog) > limits.max_stack_height_m) {
      trimmed.height = true;
      --layers;
      continue;
    }
    auto laid_out = build_from_scanner(attempt, catalog, uncapped);
    if (!laid_out) {
      if (items_per_layer > 1 && only_fit_error(laid_out.diagnostics)) {
        --items_per_layer;
        continue;
      }
      return laid_out;
    }
    if (layers > 1 && stack_height_m(*laid_out) > limits.max_stack_height_m) {
      trimmed.height = true;
      --layers;
      continue;
    }
    auto result = build_from_scanner(attempt, catalog, limits);
    // A layout that cannot stand even without its anomalies or its pattern's turns (cartons of
    // different heights in a layer), and would build but for that: its top layers go, as for the
    // caps (a single layer always stands).
    if (!result && layers > 1 && limits.check_standing) {
      ValidationLimits no_standing = limits;
      no_standing.check_standing = false;
      if (build_from_scanner(attempt, catalog, no_standing)) {
        --layers;
        trimmed.stand = true;
        continue;
      }
    }
    if (result) {
      result->notes = notes_for(options, drawn, attempt, trimmed, result.diagnostics);
    }
    return result;
  }
}

}  // namespace pb
