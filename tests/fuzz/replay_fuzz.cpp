// SPDX-License-Identifier: MIT
// Fuzz target: a replay file (File > Open Replay, `palletballet --replay`). Reads it and, when it
// is accepted, plays it as the player does (frames at, between and beyond its times) and writes it
// back: the written form must read back to the same text.
#include <cstdlib>

#include "core/analysis/replay.hpp"
#include "core/contract/json_io.hpp"
#include "tests/fuzz/fuzz_target.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  auto json = pb::parse_json(pb::fuzz::as_text(data, size));
  if (!json) return 0;
  auto replay = pb::replay_from_json(*json);
  if (!replay) return 0;
  const pb::Replay& r = *replay.value;
  if (!r.frames.empty()) {
    const double t0 = r.frames.front().t, t1 = r.frames.back().t;
    for (double f : {-1.0, 0.0, 0.25, 0.5, 0.999, 1.0, 2.0})
      (void)pb::frame_at(r, t0 + f * (t1 - t0));
  }
  const pb::Json written = pb::replay_to_json(r);
  auto reread = pb::replay_from_json(written);
  if (!reread || pb::replay_to_json(*reread.value) != written) std::abort();
  return 0;
}
