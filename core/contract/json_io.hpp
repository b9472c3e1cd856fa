// SPDX-License-Identifier: MIT
// The JSON contract: reading and writing Item, PalletConfig, ConveyorProfile and SafetyResult.
// Field names and units are the reference system's; our additions are optional keys with
// defaults; every document written carries "schema_version". Reading never throws: it returns the
// value or diagnostics with a JSON pointer and a sentence that says what to change.
#pragma once

#include <string_view>

#include "core/base/diagnostic.hpp"
#include "core/contract/conveyor_profile.hpp"
#include "core/contract/json_reader.hpp"
#include "core/contract/pallet_config.hpp"
#include "core/contract/safety_result.hpp"

namespace pb {

/// Writes an item; with `computed`, also its "center_of_mass" (as the reference does).
Json item_to_json(const Item& item, bool computed = true);

/// Writes a pallet: "schema_version", every field, and with `computed` the reference's computed
/// fields ("total_mass_kg", "composite_com_m", "stack_height_m", "overhang_m", per item
/// "center_of_mass"), which readers accept, check and ignore.
Json pallet_to_json(const PalletConfig& config, bool computed = true);
Json profile_to_json(const ConveyorProfile& profile);
Json safety_result_to_json(const SafetyResult& result);

/// Reads a pallet. Required keys: "items", "env", "body_temp_c" (as in the reference); every other
/// key has the default of PalletConfig. Structural problems (wrong JSON type, unknown enum value,
/// missing required key, newer schema_version) are errors; unknown keys and computed fields that
/// disagree with the recomputed value are warnings. Range and physical rules are not checked here:
/// call validate() (validation.hpp) on the value.
/// `pointer_prefix` is prepended to every pointer (for a pallet inside a larger document).
Result<PalletConfig> pallet_from_json(const Json& json, const std::string& pointer_prefix = "");
Result<ConveyorProfile> profile_from_json(const Json& json, const std::string& pointer_prefix = "");
Result<SafetyResult> safety_result_from_json(const Json& json,
                                             const std::string& pointer_prefix = "");

/// The largest JSON text read, 64 MiB: a pallet of the most items validation allows (400) is about
/// 0.3 MB and a long replay a few MB. A larger text is refused before it is parsed; readers of
/// files and streams read at most one byte more than this.
inline constexpr std::size_t kMaxDocumentBytes = std::size_t{64} << 20;

/// Parses JSON text; a syntax error is one diagnostic at pointer "" naming the byte offset, a text
/// over kMaxDocumentBytes one that names the limit.
Result<Json> parse_json(std::string_view text);

/// Compact canonical text of a JSON value: keys sorted (nlohmann's default), numbers written to
/// round-trip exactly. The same value always gives the same bytes.
std::string to_canonical_text(const Json& json);

}  // namespace pb
