// SPDX-License-Identifier: MIT
// The colour of a SKU, the same wherever a carton is drawn (the stack builder's grid, the 3D
// replay): stable across runs and platforms, never the failure highlight's red.
#pragma once

#include <QColor>
#include <string>

namespace pb::ui {

QColor skuColor(const std::string& sku);

}  // namespace pb::ui
