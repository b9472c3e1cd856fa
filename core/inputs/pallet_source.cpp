// SPDX-License-Identifier: MIT
#include "core/inputs/pallet_source.hpp"

#include <filesystem>
#include <fstream>
#include <iostream>

#include "core/inputs/scenario.hpp"

namespace pb {

namespace {

// The pallet and suggested profile of a curated scenario, for a FILE argument that is no file.
Result<PalletSource> curated_pallet(const std::string& arg) {
  auto scenario = load_scenario(arg);
  if (!scenario) {
    std::string known;
    for (const auto& slug : scenario_slugs()) known += (known.empty() ? "" : ", ") + slug;
    return Result<PalletSource>::failure(
        "", "cannot open '" + arg + "': there is no such file and no curated scenario of that " +
                "name; check the path, or name one of " + known);
  }
  return Result<PalletSource>{
      PalletSource{std::move(scenario->pallet), "", scenario->suggested_profile, scenario->name},
      {}};
}

}  // namespace

const Json& pallet_member(const Json& document, std::string& prefix) {
  const bool member = document.is_object() && document.contains("pallet");
  prefix = member ? "/pallet" : "";
  return member ? document["pallet"] : document;
}

Result<PalletSource> pallet_source_from_json(const Json& json) {
  PalletSource source;
  const Json& pallet_json = pallet_member(json, source.pointer_prefix);
  Diagnostics diags;
  if (!source.pointer_prefix.empty()) {
    if (json.contains("suggested_profile")) {
      auto profile = profile_from_json(json["suggested_profile"], "/suggested_profile");
      diags = std::move(profile.diagnostics);
      source.suggested_profile = std::move(profile.value);
    }
    if (json.contains("name") && json["name"].is_string()) {
      source.scenario_name = json["name"].get<std::string>();
    }
  }
  auto pallet = pallet_from_json(pallet_json, source.pointer_prefix);
  diags.insert(diags.end(), pallet.diagnostics.begin(), pallet.diagnostics.end());
  if (!pallet || has_errors(diags)) return Result<PalletSource>::failure(std::move(diags));
  source.pallet = std::move(*pallet.value);
  return Result<PalletSource>{std::move(source), std::move(diags)};
}

std::optional<std::string> read_document_text(const std::string& path) {
  std::ifstream file;
  std::istream* in = &std::cin;
  if (path != "-") {
    file.open(path, std::ios::binary);
    if (!file) return std::nullopt;
    in = &file;
  }
  std::string text;
  char chunk[1 << 16];
  while (text.size() <= kMaxDocumentBytes) {
    in->read(chunk, sizeof chunk);
    text.append(chunk, std::size_t(in->gcount()));
    if (!*in) break;
  }
  if (in->bad()) return std::nullopt;
  return text;
}

Result<PalletSource> read_pallet_source(const std::string& arg) {
  if (arg != "-" && !std::filesystem::exists(arg)) return curated_pallet(arg);
  std::error_code ec;
  if (arg != "-" && std::filesystem::is_directory(arg, ec)) {
    return Result<PalletSource>::failure(
        "", "'" + arg + "' is a directory; give a pallet or scenario file in it (.json)");
  }
  auto text = read_document_text(arg);
  if (!text) {
    const std::string what = "cannot open '" + arg + "'; check the path and its permissions";
    return Result<PalletSource>::failure("", what);
  }
  auto json = parse_json(*text);
  if (!json) return Result<PalletSource>::failure(std::move(json.diagnostics));
  return pallet_source_from_json(*json);
}

}  // namespace pb
