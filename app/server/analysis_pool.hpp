// SPDX-License-Identifier: MIT
// The service's physics: a fixed set of Analyzers (one per concurrent analysis), leased to
// requests, and one cache of envelopes shared by all of them, keyed by the pallet's fingerprint.
// Every call runs under a Ticket: a deadline and a test of whether the client is still there; a
// watchdog cancels the ticket's runs (core/base/cancel.hpp) when either fails.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <variant>
#include <vector>

#include "core/analysis/analyzer.hpp"
#include "core/base/cancel.hpp"

namespace pb::server {

/// Why a ticket's work was stopped.
enum class StopReason { none, deadline, client_gone, shutdown };

/// One request's claim on the physics. Thread-safe: the watchdog reads it while a worker runs.
class Ticket {
 public:
  using Clock = std::chrono::steady_clock;
  /// `client_alive` is polled by the watchdog (empty: the client is assumed to stay).
  Ticket(Clock::duration time_limit, std::function<bool()> client_alive = {});

  const CancelFlag& flag() const { return cancel_; }
  bool stopped() const { return cancel_.load(); }
  StopReason reason() const { return reason_.load(); }
  /// Stops the ticket's runs for `why` (the first reason wins).
  void stop(StopReason why);
  /// Stops the ticket when its deadline has passed or its client has gone; true if stopped.
  bool check();
  double time_limit_s() const;

 private:
  CancelFlag cancel_{false};
  std::atomic<StopReason> reason_{StopReason::none};
  Clock::time_point deadline_;
  Clock::duration limit_;
  std::function<bool()> client_alive_;
};

/// An envelope as the service keeps it: the result, its search's probes and what it cost.
struct CachedEnvelope {
  Envelope envelope;
  double compute_ms = 0.0;
};

/// What a call to analyze() gives.
struct Analysis {
  std::shared_ptr<const CachedEnvelope> cached;
  bool cache_hit = false;  ///< answered from the shared cache (no simulation)
  double wall_ms = 0.0;
};

/// The state of the pool at an instant, for /healthz and /metrics.
struct PoolStats {
  int analyzers = 0;
  int busy = 0;     ///< analyzers leased now
  int waiting = 0;  ///< calls waiting for an analyzer
  std::size_t cached_envelopes = 0;
  std::uint64_t cache_hits = 0, cache_misses = 0;
  std::uint64_t simulations = 0;  ///< run by the pool's analyses since it started
  std::uint64_t stopped_deadline = 0, stopped_client_gone = 0;
  std::uint64_t rejected_busy = 0;
};

struct PoolOptions {
  AnalyzerOptions analyzer;
  int analyzers = 2;     ///< concurrent analyses
  int max_waiting = 64;  ///< calls that may wait for an analyzer; more are refused (Busy)
  std::size_t max_cached_envelopes = 4096;  ///< the oldest is dropped beyond this
  /// An Analyzer keeps every pallet it prepared (scene, data, rest state: megabytes each); it
  /// forgets them all once it holds more than this.
  int max_prepared_per_analyzer = 4;
};

/// Why a call gave no answer: the pool is full, or the ticket was stopped.
struct Refusal {
  enum Kind { busy, stopped } kind = busy;
  std::string message;
};

class AnalysisPool {
 public:
  explicit AnalysisPool(PoolOptions options);
  ~AnalysisPool();
  AnalysisPool(const AnalysisPool&) = delete;
  AnalysisPool& operator=(const AnalysisPool&) = delete;

  /// The work a leased Analyzer does for one request; its runs are cancelled by the ticket.
  using Work = std::function<void(Analyzer&)>;

  /// Runs `work` on a free Analyzer, waiting for one; a Refusal when max_waiting calls wait
  /// already or the ticket is stopped (before or during the work: then its answer is not to be
  /// used). The ticket is watched for as long as the call lasts.
  std::optional<Refusal> run(Ticket& ticket, const Work& work);

  /// The pallet's envelope from the shared cache, or computed (once: concurrent calls for the same
  /// pallet wait for the first and share its answer). Core failures come back as diagnostics.
  std::variant<Analysis, Refusal, Diagnostics> analyze(Ticket& ticket, const PalletConfig& config);

  /// Counts simulations a run() call's work ran (analyze() counts its own).
  void count_simulations(int sims);

  PoolStats stats() const;
  const PoolOptions& options() const { return options_; }

 private:
  struct Flight;
  struct Slot {
    std::unique_ptr<Analyzer> analyzer;
    bool busy = false;
  };

  void watch();
  void remember(const std::string& key, std::shared_ptr<const CachedEnvelope> value);
  void note_stop(const Ticket& ticket);

  PoolOptions options_;
  mutable std::mutex mutex_;
  std::condition_variable freed_;
  std::vector<Slot> slots_;
  int waiting_ = 0;
  std::map<std::string, std::shared_ptr<const CachedEnvelope>> cache_;
  std::deque<std::string> cache_order_;  ///< oldest first
  std::map<std::string, std::shared_ptr<Flight>> flights_;
  std::vector<Ticket*> watched_;
  PoolStats counters_;
  bool shutting_down_ = false;
  std::condition_variable watch_wake_;
  std::thread watchdog_;
};

}  // namespace pb::server
