// SPDX-License-Identifier: MIT
#include "core/inputs/layer_layout.hpp"
#include "core/base/text.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>

#include "core/contract/pallet_metrics.hpp"
#include "core/contract/pallet_type.hpp"
#include "core/inputs/static_stability.hpp"

namespace pb {

namespace {

constexpr int kMaxLayers = 50;
constexpr int kMaxItemsPerLayer = 100;
constexpr double kMaxLeanDeg = 45.0;
// Lengths that agree within this are equal (grid fits, compactness ties).
constexpr double kEpsilon = 1e-9;
// Layouts keep this far inside the overhang limit so that round-off never crosses it.
constexpr double kOverhangMargin = 1e-6;
// Footprints sharing no more than this area (m^2, 1 mm^2) touch along an edge; they do not stand
// on each other (validate() draws the same line when it looks for floating items).
constexpr double kContactArea = 1e-6;
// Layer shifts are rounded to 0.1 mm so that a one-ulp difference in a platform's tan() cannot
// change the layout's bytes.
constexpr double kShiftResolution = 1e-4;

std::string fixed(double value, int decimals, const char* unit) {
  return pb::fixed(value, decimals) + " " + unit;
}

// One carton of a layer before its height is known: position relative to the deck centre.
struct Placement {
  const SkuTemplate* sku = nullptr;
  double x = 0.0;
  double y = 0.0;
  double yaw_deg = 0.0;
};

using Layer = std::vector<Placement>;

// The deck and how far a layout may reach beyond each of its edges.
struct Deck {
  double length = 0.0;
  double width = 0.0;
  double top = 0.0;
  double budget = 0.0;  ///< overhang allowed per edge (the limit less a round-off margin)
};

// Extent of a SKU's footprint along X and Y at yaw 0 or 90 degrees.
Vec2 extent(const SkuTemplate& sku, double yaw_deg) {
  return yaw_deg == 0.0 ? Vec2{sku.dims_m[0], sku.dims_m[1]} : Vec2{sku.dims_m[1], sku.dims_m[0]};
}

// Ti cells, cols along X and rows along Y, each as large as the layer's largest footprint.
struct Grid {
  int cols = 1;
  int rows = 1;
  Vec2 cell{};
  double yaw_deg = 0.0;

  double length() const { return cols * cell[0]; }
  double width() const { return rows * cell[1]; }
};

// The most compact grid of `count` cells for these SKUs at one of `yaws`: on the deck if any
// fits, else within the overhang budget; ties go to fewer columns, then to the earlier yaw.
std::optional<Grid> choose_grid(const std::vector<const SkuTemplate*>& skus, int count,
                                std::span<const double> yaws, const Deck& deck) {
  for (const double allowance : {0.0, deck.budget}) {
    std::optional<Grid> best;
    double best_compactness = 0.0;
    for (const double yaw : yaws) {
      Vec2 cell{0.0, 0.0};
      for (const SkuTemplate* sku : skus) {
        const Vec2 e = extent(*sku, yaw);
        cell = {std::max(cell[0], e[0]), std::max(cell[1], e[1])};
      }
      for (int cols = 1; cols <= count; ++cols) {
        const Grid grid{cols, (count + cols - 1) / cols, cell, yaw};
        if (grid.length() > deck.length + 2.0 * allowance + kEpsilon ||
            grid.width() > deck.width + 2.0 * allowance + kEpsilon) {
          continue;
        }
        const double compactness = std::max(grid.length() / deck.length, grid.width() / deck.width);
        const bool tie = std::abs(compactness - best_compactness) <= kEpsilon;
        if (!best || (!tie && compactness < best_compactness) || (tie && cols < best->cols)) {
          best = grid;
          best_compactness = compactness;
        }
      }
    }
    if (best) return best;
  }
  return std::nullopt;
}

// Fills the grid row-major, centred on the deck, shifted by `shift_x`.
Layer fill_grid(const std::vector<const SkuTemplate*>& skus, const Grid& grid, double shift_x) {
  Layer layer;
  for (std::size_t k = 0; k < skus.size(); ++k) {
    const int row = static_cast<int>(k) / grid.cols;
    const int col = static_cast<int>(k) % grid.cols;
    layer.push_back({skus[k], (col + 0.5 - grid.cols / 2.0) * grid.cell[0] + shift_x,
                     (row + 0.5 - grid.rows / 2.0) * grid.cell[1], grid.yaw_deg});
  }
  return layer;
}

// Brick: a quarter of a cell of offset between layers (less where the overhang budget runs out),
// split symmetrically: even layers -s/2, odd layers +s/2. Every carton straddles the joint below it
// and the end cartons keep three quarters of their length on the layer below; half a cell
// balanced each end carton on an edge (its centre of mass over the last carton's end face).
double brick_shift(const Grid& grid, const Deck& deck, int layer_index) {
  const double room = deck.length - grid.length() + 2.0 * deck.budget;
  const double s = std::max(0.0, std::min(grid.cell[0] / 4.0, room));
  return layer_index % 2 == 0 ? -s / 2.0 : s / 2.0;
}

// Shelf packing in barcode order at yaw 0: items left to right along X, a new shelf along Y when
// the deck length is used up; the packing is centred on the deck.
std::optional<Layer> shelf_pack(const std::vector<const SkuTemplate*>& skus, const Deck& deck) {
  for (const double allowance : {0.0, deck.budget}) {
    const double capacity = deck.length + 2.0 * allowance;
    Layer layer;
    double cursor = 0.0, shelf_y = 0.0, shelf_width = 0.0, packed_length = 0.0;
    bool fits = true;
    for (const SkuTemplate* sku : skus) {
      const double l = sku->dims_m[0], w = sku->dims_m[1];
      if (l > capacity + kEpsilon) fits = false;
      if (cursor > 0.0 && cursor + l > capacity + kEpsilon) {
        shelf_y += shelf_width;
        cursor = 0.0;
        shelf_width = 0.0;
      }
      layer.push_back({sku, cursor + l / 2.0, shelf_y + w / 2.0, 0.0});
      cursor += l;
      shelf_width = std::max(shelf_width, w);
      packed_length = std::max(packed_length, cursor);
    }
    const double packed_width = shelf_y + shelf_width;
    if (!fits || packed_width > deck.width + 2.0 * allowance + kEpsilon) continue;
    for (Placement& p : layer) {
      p.x -= packed_length / 2.0;
      p.y -= packed_width / 2.0;
    }
    return layer;
  }
  return std::nullopt;
}

// The layer's cartons in the plane, or nullopt when they do not fit the deck.
std::optional<Layer> lay_out_layer(LayerPattern pattern, int layer_index,
                                   const std::vector<const SkuTemplate*>& skus, const Deck& deck) {
  static constexpr double kBoth[] = {0.0, 90.0};
  static constexpr double kStraight[] = {0.0};
  static constexpr double kTurned[] = {90.0};
  const int count = static_cast<int>(skus.size());
  switch (pattern) {
    case LayerPattern::irregular:
      return shelf_pack(skus, deck);
    case LayerPattern::pinwheel: {
      const auto grid = choose_grid(skus, count, layer_index % 2 == 0 ? kStraight : kTurned, deck);
      if (!grid) return std::nullopt;
      return fill_grid(skus, *grid, 0.0);
    }
    case LayerPattern::brick: {
      const auto grid = choose_grid(skus, count, kBoth, deck);
      if (!grid) return std::nullopt;
      return fill_grid(skus, *grid, brick_shift(*grid, deck, layer_index));
    }
    case LayerPattern::column:
      break;
  }
  const auto grid = choose_grid(skus, count, kBoth, deck);
  if (!grid) return std::nullopt;
  return fill_grid(skus, *grid, 0.0);
}

// Where an item comes to rest: on the highest top among the items under its footprint, or on
// the deck.
double resting_z(const Item& item, const std::vector<Item>& below, double deck_top) {
  double z = deck_top;
  for (const Item& other : below) {
    if (footprint_overlap_area(item, other) > kContactArea) z = std::max(z, other.top_z());
  }
  return z;
}

// Range of X shifts that keep every carton of the layer within the overhang budget.
Vec2 shift_range(const Layer& layer, const Deck& deck) {
  double lo = -1e300, hi = 1e300;
  for (const Placement& p : layer) {
    for (const Vec2& corner : item_footprint(make_item(*p.sku, {p.x, p.y, 0.0}, p.yaw_deg))) {
      lo = std::max(lo, -(deck.length / 2.0 + deck.budget) - corner[0]);
      hi = std::min(hi, deck.length / 2.0 + deck.budget - corner[0]);
    }
  }
  return {std::min(lo, 0.0), std::max(hi, 0.0)};
}

// The lean offset of a layer whose bottom is `height` above the deck (plus the top-layer push),
// both at `scale` of their scanned size, rounded to kShiftResolution and clamped to the overhang
// budget.
double layer_shift(const ScannerInputs& inputs, double scale, bool top_layer, double height,
                   const Layer& layer, const Deck& deck) {
  double shift = scale * std::tan(inputs.lean_angle_deg * std::numbers::pi / 180.0) * height;
  if (top_layer) shift += scale * inputs.top_overhang_m;
  shift = std::round(shift / kShiftResolution) * kShiftResolution;
  const Vec2 range = shift_range(layer, deck);
  return std::clamp(shift, range[0], range[1]);
}

Diagnostics check_inputs(const ScannerInputs& inputs, const Catalog& catalog) {
  Diagnostics diags;
  if (inputs.layers < 1 || inputs.layers > kMaxLayers) {
    diags.push_back({"/layers", std::to_string(inputs.layers) + " layers is not a pallet; use 1.." +
                                    std::to_string(kMaxLayers)});
  }
  if (inputs.items_per_layer < 1 || inputs.items_per_layer > kMaxItemsPerLayer) {
    diags.push_back({"/items_per_layer", std::to_string(inputs.items_per_layer) +
                                             " items per layer is not a layer; use 1.." +
                                             std::to_string(kMaxItemsPerLayer)});
  }
  if (inputs.skus.empty()) {
    diags.push_back({"/skus", "no barcodes were scanned; give at least one SKU"});
  }
  if (!std::isfinite(inputs.lean_angle_deg) || std::abs(inputs.lean_angle_deg) >= kMaxLeanDeg) {
    diags.push_back({"/lean_angle_deg", "a lean of " + fixed(inputs.lean_angle_deg, 1, "deg") +
                                            " is not a standing load; use a finite angle under " +
                                            fixed(kMaxLeanDeg, 0, "deg")});
  }
  if (!std::isfinite(inputs.top_overhang_m)) {
    diags.push_back(
        {"/top_overhang_m", "the top-layer overhang must be a finite length in metres"});
  }
  const std::size_t used = std::min(
      inputs.skus.size(), static_cast<std::size_t>(std::max(0, inputs.layers)) *
                              static_cast<std::size_t>(std::max(0, inputs.items_per_layer)));
  for (std::size_t i = 0; i < used; ++i) {
    if (!catalog.find(inputs.skus[i])) {
      diags.push_back({"/skus/" + std::to_string(i),
                       "unknown SKU '" + inputs.skus[i] +
                           "'; use a SKU from the catalog (palletballet-cli catalog)"});
    }
  }
  return diags;
}

// The SKUs of layer `index`: barcodes layer-major, repeated cyclically.
std::vector<const SkuTemplate*> layer_skus(const ScannerInputs& inputs, int index,
                                           const Catalog& catalog) {
  std::vector<const SkuTemplate*> skus;
  for (int k = 0; k < inputs.items_per_layer; ++k) {
    const std::size_t i = static_cast<std::size_t>(index * inputs.items_per_layer + k);
    skus.push_back(catalog.find(inputs.skus[i % inputs.skus.size()]));
  }
  return skus;
}

// Whether the first `count` cartons of every layer fit the deck.
bool first_cartons_fit(LayerPattern pattern,
                       const std::vector<std::vector<const SkuTemplate*>>& layers, int count,
                       const Deck& deck) {
  for (std::size_t l = 0; l < layers.size(); ++l) {
    const std::vector<const SkuTemplate*> first(layers[l].begin(), layers[l].begin() + count);
    if (!lay_out_layer(pattern, static_cast<int>(l), first, deck)) return false;
  }
  return true;
}

// "/items_per_layer": layer `index` does not fit, and how many cartons per layer would fit every
// layer (alternate layers of a pinwheel turn, so they may hold fewer).
Diagnostic does_not_fit(const ScannerInputs& inputs, std::size_t index,
                        const std::vector<std::vector<const SkuTemplate*>>& layers,
                        const Deck& deck, double limit_m) {
  int fitting = inputs.items_per_layer - 1;
  while (fitting > 0 && !first_cartons_fit(inputs.pattern, layers, fitting, deck)) --fitting;
  const auto& skus = layers[index];
  const SkuTemplate* largest =
      *std::max_element(skus.begin(), skus.end(), [](const SkuTemplate* a, const SkuTemplate* b) {
        return a->dims_m[0] * a->dims_m[1] < b->dims_m[0] * b->dims_m[1];
      });
  std::string message =
      "layer " + std::to_string(index) + " does not fit " + std::to_string(skus.size()) +
      " cartons (largest " + largest->sku + ", " + fixed(largest->dims_m[0], 2, "x") + " " +
      fixed(largest->dims_m[1], 2, "m") + ") in a " + std::string(to_string(inputs.pattern)) +
      " pattern on the " + fixed(deck.length, 3, "x") + " " + fixed(deck.width, 3, "m") + " " +
      std::string(to_string(inputs.base_pallet_type)) + " deck, even with " +
      fixed(limit_m * 100.0, 1, "cm") + " of overhang; ";
  message += fitting > 0 ? "at most " + std::to_string(fitting) +
                               " fit on every layer, so set items_per_layer to " +
                               std::to_string(fitting) + " or fewer"
                         : "not even one fits, so use a smaller SKU";
  return {"/items_per_layer", message};
}

}  // namespace

Result<PalletConfig> build_from_scanner(const ScannerInputs& inputs, const Catalog& catalog,
                                        const ValidationLimits& limits) {
  Diagnostics diags = check_inputs(inputs, catalog);
  if (has_errors(diags)) return Result<PalletConfig>::failure(std::move(diags));

  const PalletTypeSpec& spec = pallet_type_spec(inputs.base_pallet_type);
  const double limit =
      std::isfinite(limits.max_overhang_m) ? std::max(0.0, limits.max_overhang_m) : 0.0;
  const Deck deck{spec.dims_m[0], spec.dims_m[1], spec.dims_m[2],
                  std::max(0.0, limit - kOverhangMargin)};

  std::vector<std::vector<const SkuTemplate*>> skus;
  for (int l = 0; l < inputs.layers; ++l) skus.push_back(layer_skus(inputs, l, catalog));
  // Each layer as its pattern lays it and, for the alternate layers of a brick or a pinwheel, as
  // the layers below them are laid (not shifted, not turned): what the pattern falls back to when,
  // shifted or turned, some cartons could not stand.
  std::vector<Layer> layers, plain;
  for (std::size_t l = 0; l < skus.size(); ++l) {
    auto layer = lay_out_layer(inputs.pattern, static_cast<int>(l), skus[l], deck);
    if (!layer) return Result<PalletConfig>::failure({does_not_fit(inputs, l, skus, deck, limit)});
    layers.push_back(std::move(*layer));
    auto unturned = lay_out_layer(inputs.pattern, 0, skus[l], deck);
    plain.push_back(unturned ? std::move(*unturned) : layers.back());
  }
  const bool alternates =
      inputs.pattern == LayerPattern::brick || inputs.pattern == LayerPattern::pinwheel;

  // The anomalies at `scale` of their scanned size (each layer shifted by its lean offset, the top
  // layer pushed, clamped to the overhang budget), the alternate layers laid plain or not.
  auto stack = [&](double scale, bool laid_plain) {
    PalletConfig config;
    config.pallet_id = inputs.pallet_id;
    config.base_pallet_type = inputs.base_pallet_type;
    config.base_dims_m = spec.dims_m;
    config.base_mass_kg = spec.mass_kg;
    config.wrap = inputs.wrap;
    config.env = inputs.env;
    config.body_temp_c = inputs.body_temp_c;
    config.seconds_since_temp_change = inputs.seconds_since_temp_change;
    config.belt_surface = inputs.belt_surface;
    for (std::size_t l = 0; l < layers.size(); ++l) {
      const Layer& layer = laid_plain ? plain[l] : layers[l];
      const double floor = stack_height_m(config);
      const double shift =
          layer_shift(inputs, scale, l + 1 == layers.size(), floor - deck.top, layer, deck);
      for (const Placement& p : layer) {
        Item item = make_item(*p.sku, {p.x + shift, p.y, 0.0}, p.yaw_deg);
        item.position[2] = resting_z(item, config.items, deck.top);
        config.items.push_back(std::move(item));
      }
    }
    return config;
  };

  // What cannot stand is not built (as the overhang is clamped): the pattern as scanned, else
  // with its anomalies reduced (to the largest share, to 1/1024, under which every item stands),
  // else with the alternate layers laid plain (and the anomalies reduced as needed). A layout that
  // cannot stand even so (cartons of different heights in a layer) is reported by validate().
  const double margin = limits.stability_margin_m;
  const double tolerance = limits.support_tolerance_m;
  auto stands_as = [&](double scale, bool laid_plain) {
    return stands(stack(scale, laid_plain), margin, tolerance);
  };
  const bool anomalous = inputs.lean_angle_deg != 0.0 || inputs.top_overhang_m != 0.0;
  double scale = 1.0;
  bool laid_plain = false;
  if (limits.check_standing && !stands_as(1.0, false)) {
    for (const bool p : {false, true}) {
      if (p && !alternates) break;
      if (stands_as(1.0, p)) {
        laid_plain = p;
        break;
      }
      if (!anomalous || !stands_as(0.0, p)) continue;
      double lo = 0.0, hi = 1.0;
      for (int k = 0; k < 10; ++k) {
        const double mid = 0.5 * (lo + hi);
        (stands_as(mid, p) ? lo : hi) = mid;
      }
      scale = lo;
      laid_plain = p;
      break;
    }
  }
  const PalletConfig config = stack(scale, laid_plain);
  if (scale < 1.0) {
    diags.push_back({"/lean_angle_deg",
                     "the lean (" + fixed(inputs.lean_angle_deg, 1, "deg") +
                         ") and top-layer overhang (" +
                         fixed(100.0 * inputs.top_overhang_m, 1, "cm") + ") were reduced to " +
                         fixed(100.0 * scale, 0, "%") + " so that every item stands",
                     Severity::warning});
  }
  if (laid_plain) {
    diags.push_back({"/pattern",
                     std::string(inputs.pattern == LayerPattern::brick
                                     ? "the alternate layers are not shifted"
                                     : "the alternate layers are not turned") +
                         ": so laid, some cartons of the " +
                         std::string(to_string(inputs.pattern)) +
                         " pattern would not stand on the layer below",
                     Severity::warning});
  }

  Diagnostics found = validate(config, limits, &catalog);
  diags.insert(diags.end(), found.begin(), found.end());
  if (has_errors(diags)) return Result<PalletConfig>::failure(std::move(diags));
  return Result<PalletConfig>{std::move(config), std::move(diags)};
}

}  // namespace pb
