// SPDX-License-Identifier: MIT
// SHA-256 (FIPS 180-4), for fingerprints of configurations. Self-contained: the core links no
// crypto library.
#pragma once

#include <string>
#include <string_view>

namespace pb {

/// The SHA-256 digest of `data` as 64 lowercase hexadecimal characters.
std::string sha256_hex(std::string_view data);

}  // namespace pb
