// SPDX-License-Identifier: MIT
// A pseudo-random generator whose output is the same on every platform and compiler (the
// standard library's distributions are not): xoshiro256** seeded through splitmix64, with our own
// uniform, integer and weighted draws.
#pragma once

#include <cstdint>
#include <span>

namespace pb {

class Rng {
 public:
  explicit Rng(std::uint64_t seed);

  std::uint64_t next_u64();
  /// Uniform in [0, 1) with 53 random bits.
  double uniform01();
  /// Uniform in [lo, hi).
  double uniform(double lo, double hi);
  /// Uniform integer in [lo, hi] (inclusive), unbiased (rejection sampling); lo when hi <= lo.
  int uniform_int(int lo, int hi);
  /// True with probability p.
  bool bernoulli(double p);
  /// Index i with probability weights[i] / sum(weights); weights >= 0, sum > 0.
  std::size_t weighted_index(std::span<const double> weights);

 private:
  std::uint64_t s_[4];
};

}  // namespace pb
