// SPDX-License-Identifier: MIT
#include "ui/widgets/sku_color.hpp"

#include <cstdint>

namespace pb::ui {

QColor skuColor(const std::string& sku) {
  std::uint32_t hash = 2166136261u;  // FNV-1a: stable across runs and platforms
  for (unsigned char c : sku) hash = (hash ^ c) * 16777619u;
  // Hues from 40 to 320 degrees: never the highlight's red.
  const int hue = 40 + static_cast<int>(hash % 281u);
  const int saturation = 140 + static_cast<int>((hash >> 12) % 60u);
  return QColor::fromHsv(hue, saturation, 215);
}

}  // namespace pb::ui
