// SPDX-License-Identifier: MIT
// Fuzz target: an SKU catalog in CSV. Reads it and, when it is accepted, looks up and lists its
// SKUs and builds an item of each, as the stack builder does.
#include "core/inputs/catalog.hpp"
#include "tests/fuzz/fuzz_target.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  auto catalog = pb::Catalog::from_csv(pb::fuzz::as_text(data, size));
  if (!catalog) return 0;
  for (const auto& sku : catalog.value->all()) {
    (void)catalog.value->find(sku.sku);
    (void)pb::make_item(sku, {0.1, 0.2, 0.144}, 90.0);
  }
  for (auto env : {pb::Environment::frozen, pb::Environment::refrigerated, pb::Environment::thawed,
                   pb::Environment::transitioning})
    (void)catalog.value->for_env(env);
  return 0;
}
