// SPDX-License-Identifier: MIT
// The stack builder model: stacks of one SKU in the cells of a grid on the deck, N items high.
// What a floor supervisor builds by hand, and how the curated scenarios are described.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/base/diagnostic.hpp"
#include "core/contract/pallet_config.hpp"
#include "core/inputs/catalog.hpp"

namespace pb {

/// `height` items of `sku` in cell (row, col). Several stacks may name the same cell: they stand
/// on each other in the order given, so a cell can hold mixed SKUs.
struct StackSpec {
  std::string sku;
  int row = 0;
  int col = 0;
  int height = 1;

  bool operator==(const StackSpec&) const = default;
};

/// Grid on the deck: cols along X (belt travel), rows along Y.
struct GridShape {
  int rows = 1;
  int cols = 1;

  bool operator==(const GridShape&) const = default;
};

/// The grid sized so the largest item of any stack fits one cell:
/// cols = floor(L / max_length), rows = floor(W / max_width), each at least 1, with the division
/// done so that 1.2 / 0.4 gives 3 (the reference's floor division gave 2 and silently dropped a
/// column). With no stacks (or only unknown SKUs), the grid for a 0.4 x 0.3 m carton.
GridShape grid_for(std::span<const StackSpec> stacks, const Vec3& base_dims_m,
                   const Catalog& catalog);

/// Everything of the pallet that is not the stacks.
struct StackBuildOptions {
  std::string pallet_id = "pallet";
  PalletType base_pallet_type = PalletType::eur;
  std::optional<Vec3> base_dims_m;     ///< default: the type's nominal dimensions
  std::optional<double> base_mass_kg;  ///< default: the type's tare
  WrapType wrap = WrapType::stretch;
  Environment env = Environment::refrigerated;
  double body_temp_c = 2.0;
  double seconds_since_temp_change = 3600.0;
  BeltSurface belt_surface = BeltSurface::rubber_belt;
  std::optional<GridShape> grid;  ///< default: grid_for()
};

/// Cell centre x = -L/2 + (col + 0.5) * L / cols, y = -W/2 + (row + 0.5) * W / rows; items stand
/// from the deck upward. Every stack is placed as asked, or the call fails saying why (unknown
/// SKU, cell outside the grid, height < 1): nothing is dropped silently. Items are listed stack by
/// stack, bottom to top. Pointers: "/stacks/<i>/<field>", and "/grid/<field>" or "/grid" for an
/// explicit grid. A rule of validate() (default limits) that the built pallet breaks, such as the
/// height cap, is reported at "/stacks/<i>" of the carton concerned (or at validate()'s own pointer
/// when no single carton is, e.g. "/items" for the gross mass).
Result<PalletConfig> build_from_stacks(std::span<const StackSpec> stacks,
                                       const StackBuildOptions& options, const Catalog& catalog);

}  // namespace pb
