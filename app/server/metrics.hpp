// SPDX-License-Identifier: MIT
// The service's counters in the Prometheus text format (version 0.0.4): requests by route and
// status, a latency histogram by route, and the analysis pool's gauges and counters.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <utility>

#include "app/server/analysis_pool.hpp"

namespace pb::server {

class Metrics {
 public:
  /// Latency buckets (seconds), Prometheus' "le" bounds; +Inf is implied.
  static constexpr std::array<double, 12> kBuckets{0.001, 0.005, 0.01, 0.025, 0.05, 0.1,
                                                   0.25,  0.5,   1.0,  2.5,   5.0,  10.0};

  /// One answered request. `route` is the route's pattern ("/scenarios/{slug}"), never the raw
  /// path, so that a client cannot grow the label set.
  void observe(const std::string& method, const std::string& route, int status, double seconds);

  /// The exposition text: these counters and the pool's state now.
  std::string text(const PoolStats& pool) const;

 private:
  struct Histogram {
    std::array<std::uint64_t, kBuckets.size()> buckets{};
    std::uint64_t count = 0;
    double sum = 0.0;
  };
  mutable std::mutex mutex_;
  std::map<std::tuple<std::string, std::string, int>, std::uint64_t> requests_;
  std::map<std::pair<std::string, std::string>, Histogram> latency_;
};

}  // namespace pb::server
