// SPDX-License-Identifier: MIT
// Small fixed-size vectors of the JSON contract. Physics code uses Eigen; the contract keeps plain
// arrays so that a value type is trivially comparable and serialisable.
#pragma once

#include <array>

namespace pb {

using Vec2 = std::array<double, 2>;  ///< (x, y) in metres, pallet frame
using Vec3 = std::array<double, 3>;  ///< (x, y, z) in metres, pallet frame unless stated

}  // namespace pb
