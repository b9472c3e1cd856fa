// SPDX-License-Identifier: MIT
#include "core/base/text.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace pb {

std::string fixed(double value, int decimals) {
  char buffer[64];
  // Beyond 1e15 a fixed-point number is a wall of digits (and 1e300's would not fit): scientific.
  if (std::abs(value) >= 1e15) {
    std::snprintf(buffer, sizeof buffer, "%.6g", value);
  } else {
    std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
  }
  return buffer;
}

std::string fixed_floor(double value, int decimals) {
  if (!std::isfinite(value) || std::abs(value) >= 1e15) return fixed(value, decimals);
  const double scale = std::pow(10.0, decimals);
  // 1e-9 relative: far below any printed digit, far above a sum's last-bit error.
  const double scaled = value * scale;
  return fixed(std::floor(scaled + 1e-9 * std::max(1.0, std::abs(scaled))) / scale, decimals);
}

std::string short_number(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.9g", value);
  return buffer;
}

}  // namespace pb
