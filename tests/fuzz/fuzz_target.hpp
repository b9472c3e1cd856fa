// SPDX-License-Identifier: MIT
// The entry point every fuzz target defines (libFuzzer's). Built with -fsanitize=fuzzer (the fuzz
// preset) libFuzzer drives it; in every other build corpus_main.cpp runs it once on each file of
// the target's committed corpus and regression inputs, so CI replays them on every submission.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace pb::fuzz {

inline std::string_view as_text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

}  // namespace pb::fuzz
