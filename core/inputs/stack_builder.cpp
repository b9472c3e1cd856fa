// SPDX-License-Identifier: MIT
#include "core/inputs/stack_builder.hpp"
#include "core/base/text.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <map>
#include <utility>

#include "core/contract/pallet_type.hpp"
#include "core/inputs/validation.hpp"

namespace pb {

namespace {

constexpr int kMaxStackHeight = 50;
// Added before flooring a count of items per deck length, so that 1.2 / 0.4 = 2.9999999999999996
// counts 3 items (the reference's floor division counted 2 and dropped a column).
constexpr double kCountEpsilon = 1e-9;
// The carton a grid is sized for when no stack names a known SKU.
constexpr double kDefaultCellLength = 0.4;
constexpr double kDefaultCellWidth = 0.3;

std::string metres(double value) {
  return fixed(value, 2) + " m";
}

// The known SKUs with the largest length and the largest width among the stacks (first wins).
struct SizingSkus {
  const SkuTemplate* longest = nullptr;
  const SkuTemplate* widest = nullptr;

  double length() const { return longest ? longest->dims_m[0] : kDefaultCellLength; }
  double width() const { return widest ? widest->dims_m[1] : kDefaultCellWidth; }
};

SizingSkus sizing_skus(std::span<const StackSpec> stacks, const Catalog& catalog) {
  SizingSkus out;
  for (const StackSpec& stack : stacks) {
    const SkuTemplate* sku = catalog.find(stack.sku);
    if (!sku) continue;
    if (!out.longest || sku->dims_m[0] > out.longest->dims_m[0]) out.longest = sku;
    if (!out.widest || sku->dims_m[1] > out.widest->dims_m[1]) out.widest = sku;
  }
  return out;
}

int fitting_count(double deck, double item) {
  return std::max(1, static_cast<int>(std::floor(deck / item + kCountEpsilon)));
}

Vec3 base_dims(const StackBuildOptions& options) {
  return options.base_dims_m.value_or(pallet_type_spec(options.base_pallet_type).dims_m);
}

// "the 3-column grid sized for SKU-FM-001 (0.40 m long) on a 1.20 m deck" or, for a grid the
// caller set, "the 3-column grid set in /grid".
std::string grid_phrase(int count, const char* unit, const SkuTemplate* sizing_sku, double size,
                        const char* size_word, double deck, bool explicit_grid) {
  std::string out = "the " + std::to_string(count) + "-" + unit + " grid ";
  if (explicit_grid) return out + "set in /grid";
  out += sizing_sku ? "sized for " + sizing_sku->sku + " (" + metres(size) + " " + size_word + ")"
                    : "sized for a " + metres(size) + " " + size_word + " carton";
  return out + " on a " + metres(deck) + " deck";
}

// Checks an explicit grid: positive counts, and cells no smaller than the items they hold.
void check_grid(const GridShape& grid, const SizingSkus& sizing, const Vec3& dims,
                Diagnostics& diags) {
  if (grid.rows < 1) {
    diags.push_back(
        {"/grid/rows", "the grid has " + std::to_string(grid.rows) + " rows; give at least 1 row"});
  }
  if (grid.cols < 1) {
    diags.push_back({"/grid/cols", "the grid has " + std::to_string(grid.cols) +
                                       " columns; give at least 1 column"});
  }
  if (grid.cols > 1 && sizing.longest && dims[0] / grid.cols + kCountEpsilon < sizing.length()) {
    diags.push_back(
        {"/grid", "the " + std::to_string(grid.cols) + "-column grid makes cells " +
                      metres(dims[0] / grid.cols) + " long but " + sizing.longest->sku + " is " +
                      metres(sizing.length()) +
                      " long, so neighbouring stacks would interpenetrate; use at " + "most " +
                      std::to_string(fitting_count(dims[0], sizing.length())) + " columns"});
  }
  if (grid.rows > 1 && sizing.widest && dims[1] / grid.rows + kCountEpsilon < sizing.width()) {
    diags.push_back({"/grid", "the " + std::to_string(grid.rows) + "-row grid makes cells " +
                                  metres(dims[1] / grid.rows) + " wide but " + sizing.widest->sku +
                                  " is " + metres(sizing.width()) +
                                  " wide, so neighbouring stacks would interpenetrate; use at " +
                                  "most " + std::to_string(fitting_count(dims[1], sizing.width())) +
                                  " rows"});
  }
}

// Errors of one stack (unknown SKU, cell outside the grid, height out of range).
void check_stack(const StackSpec& stack, std::size_t index, const GridShape& grid,
                 const SizingSkus& sizing, const Vec3& dims, bool explicit_grid,
                 const Catalog& catalog, Diagnostics& diags) {
  const std::string where = "/stacks/" + std::to_string(index);
  if (!catalog.find(stack.sku)) {
    diags.push_back(
        {where + "/sku",
         "unknown SKU '" + stack.sku + "'; use a SKU from the catalog (palletballet-cli catalog)"});
  }
  if (grid.rows >= 1 && (stack.row < 0 || stack.row >= grid.rows)) {
    diags.push_back(
        {where + "/row", "row " + std::to_string(stack.row) + " is outside " +
                             grid_phrase(grid.rows, "row", sizing.widest, sizing.width(), "wide",
                                         dims[1], explicit_grid) +
                             "; use row 0.." + std::to_string(grid.rows - 1)});
  }
  if (grid.cols >= 1 && (stack.col < 0 || stack.col >= grid.cols)) {
    diags.push_back(
        {where + "/col", "col " + std::to_string(stack.col) + " is outside " +
                             grid_phrase(grid.cols, "column", sizing.longest, sizing.length(),
                                         "long", dims[0], explicit_grid) +
                             "; use col 0.." + std::to_string(grid.cols - 1)});
  }
  if (stack.height < 1 || stack.height > kMaxStackHeight) {
    diags.push_back({where + "/height", "height " + std::to_string(stack.height) +
                                            " is not a number of cartons; use 1.." +
                                            std::to_string(kMaxStackHeight)});
  }
}

// Validation findings point at items; the caller wrote stacks, so "/items/<k>/..." becomes
// "/stacks/<stack of k>" and the message says which carton of the stack it is.
Diagnostic to_stack_pointer(Diagnostic d, const std::vector<std::pair<std::size_t, int>>& owner) {
  constexpr std::string_view kItems = "/items/";
  if (d.pointer.rfind(kItems, 0) != 0) return d;
  const std::size_t end = d.pointer.find('/', kItems.size());
  const std::string token = d.pointer.substr(kItems.size(), end - kItems.size());
  std::size_t k = 0;
  const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), k);
  if (ec != std::errc() || ptr != token.data() + token.size() || k >= owner.size()) return d;
  d.pointer = "/stacks/" + std::to_string(owner[k].first);
  d.message = "carton " + std::to_string(owner[k].second) + " (from the bottom, 0 first) of " +
              "this stack: " + d.message;
  return d;
}

}  // namespace

GridShape grid_for(std::span<const StackSpec> stacks, const Vec3& base_dims_m,
                   const Catalog& catalog) {
  const SizingSkus sizing = sizing_skus(stacks, catalog);
  return {fitting_count(base_dims_m[1], sizing.width()),
          fitting_count(base_dims_m[0], sizing.length())};
}

Result<PalletConfig> build_from_stacks(std::span<const StackSpec> stacks,
                                       const StackBuildOptions& options, const Catalog& catalog) {
  const Vec3 dims = base_dims(options);
  const SizingSkus sizing = sizing_skus(stacks, catalog);
  const bool explicit_grid = options.grid.has_value();
  const GridShape grid = options.grid.value_or(grid_for(stacks, dims, catalog));
  Diagnostics diags;
  if (explicit_grid) check_grid(grid, sizing, dims, diags);
  for (std::size_t i = 0; i < stacks.size(); ++i) {
    check_stack(stacks[i], i, grid, sizing, dims, explicit_grid, catalog, diags);
  }
  if (has_errors(diags)) return Result<PalletConfig>::failure(std::move(diags));

  PalletConfig config;
  config.pallet_id = options.pallet_id;
  config.base_pallet_type = options.base_pallet_type;
  config.base_dims_m = dims;
  config.base_mass_kg =
      options.base_mass_kg.value_or(pallet_type_spec(options.base_pallet_type).mass_kg);
  config.wrap = options.wrap;
  config.env = options.env;
  config.body_temp_c = options.body_temp_c;
  config.seconds_since_temp_change = options.seconds_since_temp_change;
  config.belt_surface = options.belt_surface;

  const double cell_l = dims[0] / grid.cols;
  const double cell_w = dims[1] / grid.rows;
  std::map<std::pair<int, int>, double> cell_top;  // (row, col) -> top of what stands there
  std::vector<std::pair<std::size_t, int>> owner;  // item -> (stack, level in the stack)
  for (std::size_t i = 0; i < stacks.size(); ++i) {
    const StackSpec& stack = stacks[i];
    const SkuTemplate& sku = *catalog.find(stack.sku);
    const double x = -dims[0] / 2.0 + (stack.col + 0.5) * cell_l;
    const double y = -dims[1] / 2.0 + (stack.row + 0.5) * cell_w;
    const auto top = cell_top.try_emplace({stack.row, stack.col}, dims[2]).first;
    for (int level = 0; level < stack.height; ++level) {
      config.items.push_back(make_item(sku, {x, y, top->second}));
      top->second += sku.dims_m[2];
      owner.emplace_back(i, level);
    }
  }

  Diagnostics findings = validate(config, ValidationLimits{}, &catalog);
  for (Diagnostic& d : findings) diags.push_back(to_stack_pointer(std::move(d), owner));
  if (has_errors(diags)) return Result<PalletConfig>::failure(std::move(diags));
  return Result<PalletConfig>{std::move(config), std::move(diags)};
}

}  // namespace pb
