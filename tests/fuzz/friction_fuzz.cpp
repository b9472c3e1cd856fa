// SPDX-License-Identifier: MIT
// Fuzz target: a friction table in the reference's format. Reads it and, when it is accepted, asks
// it what the console and the physics ask: every pair's friction at, between and beyond its control
// points, with and without the frost-melt penalty, and its curve.
#include "core/inputs/friction.hpp"
#include "tests/fuzz/fuzz_target.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  auto model = pb::FrictionModel::from_json_text(pb::fuzz::as_text(data, size));
  if (!model) return 0;
  for (const auto& key : model.value->pair_keys()) {
    for (double t : {-1e9, -40.0, -18.0, 0.0, 0.5, 25.0, 1e9}) {
      (void)model.value->steady(key, t);
      for (double since : {0.0, 60.0, 1e9}) (void)model.value->effective(key, t, since);
    }
    (void)model.value->curve(key, -30.0, 10.0, 5.0, 120.0);
  }
  return 0;
}
