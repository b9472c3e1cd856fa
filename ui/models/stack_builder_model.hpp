// SPDX-License-Identifier: MIT
// The stack builder's view of a pallet (headless, no widgets): the items grouped into stacks
// (columns of items sharing one footprint centre), the grid the builder offers on the deck, and
// validation findings rewritten to name the stack they concern.
#pragma once

#include <QString>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/base/diagnostic.hpp"
#include "core/contract/pallet_config.hpp"
#include "core/inputs/stack_builder.hpp"

namespace pb::ui {

/// Items whose footprint centres are within this distance (m) belong to the same stack.
inline constexpr double kStackCentreTolerance = 0.005;

/// One stack: items of the pallet sharing a footprint centre, bottom to top.
struct StackView {
  std::vector<int> items;  ///< indices into PalletConfig::items, bottom to top
  pb::Vec2 centre{};       ///< footprint centre (x, y) of the bottom item
  std::string sku;         ///< SKU of the bottom item ("" for none)
  bool mixed = false;      ///< the stack holds more than one SKU
  double top_z = 0.0;      ///< top of the stack's highest item

  int height() const { return static_cast<int>(items.size()); }
};

/// The pallet's stacks, ordered by their lowest item index (stable under move and resize).
/// Every item belongs to exactly one stack.
std::vector<StackView> stacks_of(const pb::PalletConfig& config);

/// Index of the stack that item `item` belongs to, or -1.
int stack_of_item(const std::vector<StackView>& stacks, int item);

/// The grid the builder offers: pb::grid_for() sized by the largest catalog SKU among the
/// pallet's items and `extra_sku` (the SKU about to be placed; may be empty) on the pallet's deck.
pb::GridShape builder_grid(const pb::PalletConfig& config, std::string_view extra_sku = {});

/// Centre (x, y) of cell (row, col) of `grid` on the deck, as pb::build_from_stacks places it.
pb::Vec2 cell_centre(const pb::PalletConfig& config, const pb::GridShape& grid, int row, int col);

struct Cell {
  int row = 0;
  int col = 0;
  bool operator==(const Cell&) const = default;
};
/// The cell holding point (x, y) of the deck, or nullopt outside the deck.
std::optional<Cell> cell_at(const pb::PalletConfig& config, const pb::GridShape& grid,
                            pb::Vec2 point);

/// The stack whose top footprint (yawed) contains point (x, y), the topmost first; -1 if none.
int stack_at(const pb::PalletConfig& config, const std::vector<StackView>& stacks, pb::Vec2 point);

/// "Stack 3 (SKU-FM-001, 4 high)" — 1-based, as the panel lists it.
QString stack_label(const std::vector<StackView>& stacks, int stack);

/// A validation finding in the builder's words: a finding about "/items/<k>/..." names the stack
/// and the carton ("Stack 3 (SKU-FM-001, 4 high), carton 2 from the bottom: <message>"); other
/// findings keep their pointer ("/wrap: <message>"). Warnings are prefixed "Warning: ".
QString describe_finding(const pb::Diagnostic& finding, const std::vector<StackView>& stacks);

/// The stack a finding concerns, or -1.
int stack_of_finding(const pb::Diagnostic& finding, const std::vector<StackView>& stacks);

/// Live summary in one line: "612.0 kg · CoM (0.00, 0.00, 0.71) m · height 1.35 m · overhang
/// 0.00 m · least support 100 %".
QString summary_line(const pb::PalletConfig& config);

}  // namespace pb::ui
