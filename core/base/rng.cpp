// SPDX-License-Identifier: MIT
#include "core/base/rng.hpp"

namespace pb {

namespace {

// splitmix64 (Steele, Lea and Flood; Vigna's public-domain reference): advances `state` and
// returns the next output. Used only to spread a 64-bit seed over xoshiro's 256-bit state.
std::uint64_t splitmix64(std::uint64_t& state) {
  state += 0x9e3779b97f4a7c15ULL;
  std::uint64_t z = state;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

constexpr std::uint64_t rotl(std::uint64_t x, int k) {
  return (x << k) | (x >> (64 - k));
}

}  // namespace

Rng::Rng(std::uint64_t seed) {
  std::uint64_t state = seed;
  for (std::uint64_t& word : s_) word = splitmix64(state);
}

// xoshiro256** 1.0 (Blackman and Vigna, public domain).
std::uint64_t Rng::next_u64() {
  const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
  const std::uint64_t t = s_[1] << 17;
  s_[2] ^= s_[0];
  s_[3] ^= s_[1];
  s_[1] ^= s_[2];
  s_[0] ^= s_[3];
  s_[2] ^= t;
  s_[3] = rotl(s_[3], 45);
  return result;
}

double Rng::uniform01() {
  return static_cast<double>(next_u64() >> 11) * 0x1.0p-53;
}

double Rng::uniform(double lo, double hi) {
  return lo + (hi - lo) * uniform01();
}

int Rng::uniform_int(int lo, int hi) {
  if (hi <= lo) return lo;
  // n = hi - lo + 1 is at most 2^32, so it fits; draws below 2^64 mod n are rejected so that
  // every residue is equally likely (the threshold method of OpenBSD's arc4random_uniform).
  const std::uint64_t n =
      static_cast<std::uint64_t>(static_cast<std::int64_t>(hi) - static_cast<std::int64_t>(lo)) + 1;
  const std::uint64_t threshold = (0 - n) % n;
  std::uint64_t x = next_u64();
  while (x < threshold) x = next_u64();
  return static_cast<int>(static_cast<std::int64_t>(lo) + static_cast<std::int64_t>(x % n));
}

bool Rng::bernoulli(double p) {
  return uniform01() < p;
}

std::size_t Rng::weighted_index(std::span<const double> weights) {
  double total = 0.0;
  std::size_t last_positive = 0;
  for (std::size_t i = 0; i < weights.size(); ++i) {
    if (weights[i] > 0.0) {
      total += weights[i];
      last_positive = i;
    }
  }
  const double r = uniform01() * total;
  double cumulative = 0.0;
  for (std::size_t i = 0; i < weights.size(); ++i) {
    if (weights[i] <= 0.0) continue;
    cumulative += weights[i];
    if (r < cumulative) return i;
  }
  return last_positive;  // r landed on the total through round-off
}

}  // namespace pb
