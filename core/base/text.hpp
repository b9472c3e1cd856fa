// SPDX-License-Identifier: MIT
// Numbers in messages: the few formats every diagnostic and summary of the core uses.
#pragma once

#include <string>

namespace pb {

/// `decimals` digits after the point: fixed(0.4, 2) == "0.40"; from 1e15 on, six significant
/// digits in scientific notation (fixed(1e300, 2) == "1e+300"), never a truncated number.
std::string fixed(double value, int decimals);

/// A limit as a person reads it: fixed(), but never rounded up past the value (a limit of 1.168
/// m/s^2 reads "1.1", not "1.2", at one decimal). A value a hair under its printed digits from
/// floating-point sums (0.1 + 0.2 + ... = 1.2999999999999998) still reads as those digits.
std::string fixed_floor(double value, int decimals);

/// Up to 9 significant digits, no trailing zeros (printf "%.9g"): for quoting a user's number.
std::string short_number(double value);

}  // namespace pb
