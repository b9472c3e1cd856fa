// SPDX-License-Identifier: MIT
#include "app/server/bench.hpp"

#include <httplib.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <thread>

#include "app/server/http_server.hpp"
#include "core/contract/json_io.hpp"
#include "core/inputs/catalog.hpp"
#include "core/inputs/random_pallet.hpp"
#include "core/inputs/scenario.hpp"

namespace pb::server {

namespace {

struct Row {
  std::string mode;
  int clients = 0;
  int requests = 0;
  int errors = 0;
  double wall_s = 0.0;
  double p50_ms = 0.0, p99_ms = 0.0, max_ms = 0.0;
  long sims = 0;
};

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t k = std::min(v.size() - 1, std::size_t(std::ceil(p * double(v.size())) - 1));
  return v[k];
}

// `bodies` sent by `clients` threads (request i by thread i % clients), each on its own
// keep-alive connection, timed one by one.
Row drive(int port, const std::string& mode, int clients, const std::vector<std::string>& bodies) {
  Row row{mode, clients, int(bodies.size())};
  std::vector<std::vector<double>> latency(static_cast<std::size_t>(clients));
  std::atomic<int> errors{0};
  std::atomic<long> sims{0};
  const auto start = std::chrono::steady_clock::now();
  std::vector<std::thread> threads;
  for (int c = 0; c < clients; ++c) {
    threads.emplace_back([&, c] {
      httplib::Client client("127.0.0.1", port);
      client.set_read_timeout(600, 0);
      client.set_keep_alive(true);
      client.set_tcp_nodelay(true);
      for (std::size_t i = std::size_t(c); i < bodies.size(); i += std::size_t(clients)) {
        const auto t0 = std::chrono::steady_clock::now();
        auto res = client.Post("/safety/analyze", bodies[i], "application/json");
        latency[std::size_t(c)].push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                .count());
        if (!res || res->status != 200) {
          ++errors;
          continue;
        }
        auto json = nlohmann::json::parse(res->body, nullptr, false);
        if (json.is_object() && json["sims_run"].is_number()) sims += json["sims_run"].get<long>();
      }
    });
  }
  for (auto& t : threads) t.join();
  row.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::vector<double> all;
  for (const auto& l : latency) all.insert(all.end(), l.begin(), l.end());
  row.p50_ms = percentile(all, 0.50);
  row.p99_ms = percentile(all, 0.99);
  row.max_ms = all.empty() ? 0.0 : *std::max_element(all.begin(), all.end());
  row.errors = errors;
  row.sims = sims;
  return row;
}

}  // namespace

int run_bench(const ServiceOptions& service_options, const BenchOptions& options) {
  Service service(service_options);
  HttpOptions http;
  http.port = 0;
  HttpServer server(service, http);
  std::string error;
  if (!server.bind(error)) {
    std::cerr << "palletballet-server bench: " << error << "\n";
    return 1;
  }
  std::thread listener([&] { server.listen(); });
  const int port = server.port();

  // Cached: one curated pallet, analysed once before the clock starts.
  const auto slab = load_scenario("stable-dairy-slab");
  const std::string cached_body = pallet_to_json(slab->pallet).dump();
  {
    httplib::Client warm("127.0.0.1", port);
    warm.set_read_timeout(600, 0);
    warm.Post("/safety/analyze", cached_body, "application/json");
  }
  // Uncached: random pallets of distinct seeds (no two rows share one), 2-4 layers.
  std::uint64_t next_seed = 1000;
  auto distinct = [&](int n) {
    std::vector<std::string> bodies;
    while (int(bodies.size()) < n) {
      RandomPalletOptions o;
      o.seed = next_seed++;
      o.min_layers = 2;
      o.max_layers = 4;
      o.wrap = enum_from_string<WrapType>(options.wrap);
      auto pallet = random_pallet(o, Catalog::builtin());
      if (pallet) bodies.push_back(pallet_to_json(*pallet).dump());
    }
    return bodies;
  };

  std::vector<Row> rows;
  for (int clients : options.clients) {
    std::cerr << "bench: cached, " << clients << " client(s)\n";
    rows.push_back(drive(port, "cached", clients,
                         std::vector<std::string>(std::size_t(options.requests), cached_body)));
    std::cerr << "bench: uncached, " << clients << " client(s)\n";
    rows.push_back(drive(port, "uncached", clients, distinct(options.requests)));
  }
  server.stop();
  listener.join();

  int failed = 0;
  if (options.json) {
    nlohmann::json out = nlohmann::json::array();
    for (const auto& r : rows) {
      out.push_back({{"mode", r.mode},
                     {"clients", r.clients},
                     {"requests", r.requests},
                     {"errors", r.errors},
                     {"requests_per_s", r.requests / r.wall_s},
                     {"p50_ms", r.p50_ms},
                     {"p99_ms", r.p99_ms},
                     {"max_ms", r.max_ms},
                     {"sims", r.sims},
                     {"analyzers", service_options.pool.analyzers}});
      failed += r.errors;
    }
    std::cout << out.dump(2) << "\n";
  } else {
    std::printf("analyzers %d, uncached pallets: random, 2-4 layers, wrap %s\n",
                service_options.pool.analyzers, options.wrap.c_str());
    std::printf("%-9s %7s %8s %6s %9s %9s %9s %9s %6s\n", "mode", "clients", "requests", "errors",
                "req/s", "p50_ms", "p99_ms", "max_ms", "sims");
    for (const auto& r : rows) {
      std::printf("%-9s %7d %8d %6d %9.1f %9.1f %9.1f %9.1f %6ld\n", r.mode.c_str(), r.clients,
                  r.requests, r.errors, r.requests / r.wall_s, r.p50_ms, r.p99_ms, r.max_ms,
                  r.sims);
      failed += r.errors;
    }
  }
  return failed > 0 ? 1 : 0;
}

}  // namespace pb::server
