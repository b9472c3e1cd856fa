// SPDX-License-Identifier: MIT
#include "core/contract/fingerprint.hpp"

#include "core/base/sha256.hpp"

namespace pb {

std::string config_fingerprint(const PalletConfig& config) {
  Json json = pallet_to_json(config, /*computed=*/false);
  for (const char* key : {"pallet_id", "notes", "schema_version"}) json.erase(key);
  return fingerprint_json(json);
}

std::string fingerprint_json(const Json& json) {
  return sha256_hex(to_canonical_text(json));
}

}  // namespace pb
