// SPDX-License-Identifier: MIT
// `palletballet-server bench`: the service's throughput and latency on this machine, measured
// over real HTTP against an in-process server (no timing in tests: numbers belong here).
#pragma once

#include <string>
#include <vector>

#include "app/server/service.hpp"

namespace pb::server {

struct BenchOptions {
  std::vector<int> clients;  ///< concurrent clients per row
  int requests = 40;         ///< requests per row, shared among the clients
  std::string wrap = "stretch";
  bool json = false;
};

/// Runs the rows (cached and uncached /safety/analyze at each client count), prints them, and
/// returns 0, or 1 if any request failed.
int run_bench(const ServiceOptions& service, const BenchOptions& options);

}  // namespace pb::server
