// SPDX-License-Identifier: MIT
// Fuzz target: a pallet or scenario document as a user or a line controller sends it. Parses it,
// reads it as a scenario (rebuilding its recipe) or a PalletConfig, validates it (the physical
// rules and the standing check included), and writes it back: none of it may crash, leak, hang or
// throw, whatever the bytes.
#include <cstdlib>

#include "core/contract/fingerprint.hpp"
#include "core/contract/json_io.hpp"
#include "core/inputs/scenario.hpp"
#include "core/inputs/validation.hpp"
#include "tests/fuzz/fuzz_target.hpp"

namespace {

void check(const pb::PalletConfig& config) {
  const pb::Diagnostics findings = pb::validate(config);
  // What validation accepts can be written, read back and fingerprinted alike.
  if (pb::has_errors(findings)) return;
  const pb::Json written = pb::pallet_to_json(config);
  const auto reread = pb::pallet_from_json(written);
  if (!reread || pb::config_fingerprint(*reread.value) != pb::config_fingerprint(config))
    std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  auto json = pb::parse_json(pb::fuzz::as_text(data, size));
  if (!json) return 0;
  if (json->is_object() && json->contains("recipe")) {
    auto scenario = pb::scenario_from_json(*json);
    if (scenario) {
      check(scenario.value->pallet);
      auto rebuilt = pb::build_from_recipe(*scenario.value);
      if (rebuilt) check(*rebuilt.value);
    }
    return 0;
  }
  const pb::Json& pallet =
      json->is_object() && json->contains("pallet") ? (*json)["pallet"] : *json;
  if (json->is_object() && json->contains("suggested_profile"))
    (void)pb::profile_from_json((*json)["suggested_profile"], "/suggested_profile");
  auto config = pb::pallet_from_json(pallet);
  if (config) check(*config.value);
  return 0;
}
