// SPDX-License-Identifier: MIT
#include "core/base/text.hpp"

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

std::string short_number(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.9g", value);
  return buffer;
}

}  // namespace pb
