// SPDX-License-Identifier: MIT
// palletballet-server: the physics core over HTTP for line controllers, warehouse systems and
// scanner stations. `palletballet-server --help` lists the flags; `palletballet-server bench`
// measures the service's throughput and latency (app/server/bench.cpp).
#include <pthread.h>
#include <signal.h>
#include <CLI/CLI.hpp>

#include <atomic>
#include <chrono>
#include <iostream>
#include <sstream>
#include <thread>

#include "app/server/bench.hpp"
#include "app/server/http_server.hpp"
#include "app/server/service.hpp"
#include "core/inputs/validation.hpp"

#ifndef PB_VERSION
#define PB_VERSION "unknown"
#endif

namespace {

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace pb::server;
  ServiceOptions service;
  service.version = PB_VERSION;
  HttpOptions http;
  std::string cors = "https://boothe.io,https://www.boothe.io,http://localhost:4321";
  BenchOptions bench;
  std::string bench_clients = "1,2,8";

  CLI::App app{
      "palletballet-server: conveyor-motion limits for pallets, over HTTP/JSON (the "
      "reference system's API, and ours under /v1/). GET / lists the routes."};
  app.set_version_flag("--version", std::string(PB_VERSION));
  app.add_option("--host", http.host, "address to listen on")->capture_default_str();
  app.add_option("--port", http.port, "port to listen on (0: any free port, printed)")
      ->check(CLI::Range(0, 65535))
      ->capture_default_str();
  app.add_option("--analyzers", service.pool.analyzers,
                 "analyses that run at once, each with its own MuJoCo data (memory grows with it)")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  app.add_option("--max-waiting", service.pool.max_waiting,
                 "requests that may wait for an analyzer; beyond it: 503 with Retry-After")
      ->check(CLI::Range(0, 100000))
      ->capture_default_str();
  app.add_option("--threads", http.threads, "connection threads (0: analyzers + max-waiting + 4)")
      ->check(CLI::Range(0, 100000))
      ->capture_default_str();
  app.add_option("--max-body", service.max_body_bytes, "largest request body, bytes (413 above)")
      ->check(CLI::Range(std::size_t(1024), std::size_t(1) << 30))
      ->capture_default_str();
  // Above the validation's limit a pallet is refused whatever this says (422, not 413).
  const std::size_t most_items = pb::ValidationLimits{}.max_items;
  app.add_option("--max-items", service.max_items,
                 "most items in one pallet (413 above); at most " + std::to_string(most_items) +
                     ", the most a pallet is validated with")
      ->check(CLI::Range(std::size_t(1), most_items))
      ->capture_default_str();
  app.add_option("--max-batch", service.max_batch, "most pallets in one /safety/batch (413 above)")
      ->check(CLI::Range(std::size_t(1), std::size_t(100000)))
      ->capture_default_str();
  app.add_option("--time-limit", service.time_limit_s,
                 "seconds one request may take, waiting for an analyzer included; its work is then "
                 "stopped (503)")
      ->check(CLI::Range(0.1, 86400.0))
      ->capture_default_str();
  app.add_option("--cache-size", service.pool.max_cached_envelopes,
                 "envelopes kept in the shared cache (the oldest is dropped)")
      ->check(CLI::Range(std::size_t(1), std::size_t(10000000)))
      ->capture_default_str();
  app.add_option("--keep-prepared", service.pool.max_prepared_per_analyzer,
                 "compiled and settled pallets each analyzer keeps for a following solve or "
                 "replay (each is megabytes; hundreds for a large unwrapped load)")
      ->check(CLI::Range(0, 10000))
      ->capture_default_str();
  app.add_option("--cors-origins", cors,
                 "comma-separated origins browsers may call from (* for any; '' for none)")
      ->capture_default_str();
  app.add_option("--estop-decel", service.pool.analyzer.line.estop_decel_mps2,
                 "the line's emergency-stop deceleration, m/s^2")
      ->check(CLI::Range(0.01, 20.0))
      ->capture_default_str();
  app.add_option("--confidence-samples", service.pool.analyzer.confidence.samples,
                 "estimate every analysis's confidence from this many samples (4-5 simulations "
                 "each: a curve in each turn for a load that is not its own mirror image across "
                 "the belt); 0: not estimated, confidence null")
      ->check(CLI::Range(0, 1000))
      ->capture_default_str();
  app.add_option("--curve-radius", service.pool.analyzer.line.curve_radius_m,
                 "the line's tightest curve, m")
      ->check(CLI::Range(0.01, 1000.0))
      ->capture_default_str();

  CLI::App* bench_cmd = app.add_subcommand(
      "bench",
      "Throughput and latency of the service on this machine: an in-process server on a "
      "free port, driven over HTTP by 1, 2 and 8 concurrent clients; analyses of cached "
      "and of distinct (uncached) random pallets. Prints a table (or --json).");
  bench_cmd->add_option("--clients", bench_clients, "concurrent clients, comma-separated")
      ->capture_default_str();
  bench_cmd->add_option("--requests", bench.requests, "requests per row")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  bench_cmd
      ->add_option("--wrap", bench.wrap,
                   "the uncached pallets' wrap: stretch (fast) or none (multi-body)")
      ->check(CLI::IsMember({"none", "shrink", "stretch", "banded"}))
      ->capture_default_str();
  bench_cmd->add_flag("--json", bench.json, "print JSON instead of the table");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; a bad flag exits 2, as the CLI's usage errors do.
    return app.exit(e) == 0 ? 0 : 2;
  }
  http.cors_origins = split_list(cors);

  if (*bench_cmd) {
    for (const auto& c : split_list(bench_clients)) {
      try {
        const int n = std::stoi(c);
        if (n < 1 || n > 256) throw std::out_of_range("clients");
        bench.clients.push_back(n);
      } catch (...) {
        std::cerr << "palletballet-server bench: --clients takes whole numbers from 1 to 256, "
                     "comma-separated, not '"
                  << c << "'\n";
        return 2;
      }
    }
    return run_bench(service, bench);
  }

  // Signals go to one thread, which stops the server; every other thread blocks them.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);

  Service svc(service);
  HttpServer server(svc, http);
  std::string error;
  if (!server.bind(error)) {
    std::cerr << "palletballet-server: " << error << "\n";
    return 1;
  }
  // A signal can arrive before listen() is running, when cpp-httplib's stop() does nothing: the
  // waiter asks again until listen() has returned.
  std::atomic<bool> finished{false};
  std::thread waiter([&] {
    int sig = 0;
    sigwait(&signals, &sig);
    if (finished) return;
    std::cerr << "palletballet-server: stopping\n";
    while (!finished) {
      server.stop();
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  });
  std::cout << "palletballet-server " << PB_VERSION << " listening on http://" << http.host << ":"
            << server.port() << " (" << service.pool.analyzers << " analyzers)" << std::endl;
  server.listen();
  finished = true;
  pthread_kill(waiter.native_handle(), SIGTERM);  // wakes the waiter if no signal came
  waiter.join();
  return 0;
}
