// SPDX-License-Identifier: MIT
// Fingerprints: a SHA-256 of the canonical JSON of what determines a simulation, so equal physics
// gives an equal key (compiled-model and result caches, SafetyResult::config_hash).
#pragma once

#include <string>

#include "core/contract/json_io.hpp"
#include "core/contract/pallet_config.hpp"

namespace pb {

/// The fingerprint of the physically relevant fields of a pallet: every field written by
/// pallet_to_json(config, false) except "pallet_id", "notes" and "schema_version". Two pallets
/// that differ only in name or notes share it; any other difference, however small, changes it.
/// 64 lowercase hexadecimal characters.
std::string config_fingerprint(const PalletConfig& config);

/// The fingerprint of any JSON value (e.g. a composite key of a pallet and solver settings):
/// sha256_hex(to_canonical_text(json)), so key order never matters.
std::string fingerprint_json(const Json& json);

}  // namespace pb
