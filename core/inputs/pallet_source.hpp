// SPDX-License-Identifier: MIT
// One reader of "a pallet" as a user hands it over, for the CLI and the console: a PalletConfig
// document, or a scenario file (its pallet under "pallet", with its "suggested_profile" and
// "name"); from a file, stdin ("-"), or the slug of a curated scenario when no file of that name
// exists. Errors point into the document that was read.
#pragma once

#include <optional>
#include <string>

#include "core/base/diagnostic.hpp"
#include "core/contract/conveyor_profile.hpp"
#include "core/contract/json_io.hpp"
#include "core/contract/pallet_config.hpp"

namespace pb {

struct PalletSource {
  PalletConfig pallet;
  std::string pointer_prefix;  ///< "/pallet" when it came from a scenario file, "" otherwise
  std::optional<ConveyorProfile> suggested_profile;  ///< a scenario's, when it has one
  std::string scenario_name;                         ///< a scenario's "name", when it has one
};

/// Where a document holds its pallet: under "pallet" when it has that member (a scenario file; the
/// service's requests, beside their other members; a PalletConfig has no such key), else the
/// document itself. `prefix` is set to its JSON pointer ("/pallet" or "").
const Json& pallet_member(const Json& document, std::string& prefix);

/// A parsed document: a PalletConfig, or a scenario file holding one under "pallet".
Result<PalletSource> pallet_source_from_json(const Json& json);

/// A file's text, or stdin's for "-"; nullopt when it cannot be read. At most one byte more than
/// parse_json accepts, so that a huge file is refused by its size, not read.
std::optional<std::string> read_document_text(const std::string& path);

/// A FILE argument: a PalletConfig or scenario file, "-" for stdin, or the slug of a curated
/// scenario when no file of that name exists (with its suggested profile).
Result<PalletSource> read_pallet_source(const std::string& arg);

}  // namespace pb
