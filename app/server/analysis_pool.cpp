// SPDX-License-Identifier: MIT
#include "app/server/analysis_pool.hpp"

#include <algorithm>

#include "core/base/text.hpp"
#include "core/contract/fingerprint.hpp"

namespace pb::server {

namespace {

constexpr auto kWatchPeriod = std::chrono::milliseconds(20);

double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

}  // namespace

// ---- Ticket ----

Ticket::Ticket(Clock::duration time_limit, std::function<bool()> client_alive)
    : deadline_(Clock::now() + time_limit),
      limit_(time_limit),
      client_alive_(std::move(client_alive)) {}

void Ticket::stop(StopReason why) {
  StopReason expected = StopReason::none;
  reason_.compare_exchange_strong(expected, why);
  cancel_.store(true);
}

bool Ticket::check() {
  if (stopped()) return true;
  if (Clock::now() > deadline_) {
    stop(StopReason::deadline);
  } else if (client_alive_ && !client_alive_()) {
    stop(StopReason::client_gone);
  }
  return stopped();
}

double Ticket::time_limit_s() const {
  return std::chrono::duration<double>(limit_).count();
}

// ---- AnalysisPool ----

/// One computation of an envelope that other calls for the same pallet wait for.
struct AnalysisPool::Flight {
  bool done = false;
  /// The answer (shared), or the core's diagnostics; neither when the leader was stopped (its
  /// followers then try again themselves).
  std::shared_ptr<const CachedEnvelope> value;
  std::optional<Diagnostics> failure;
};

AnalysisPool::AnalysisPool(PoolOptions options) : options_(std::move(options)) {
  options_.analyzers = std::max(1, options_.analyzers);
  for (int i = 0; i < options_.analyzers; ++i) {
    slots_.push_back({std::make_unique<Analyzer>(options_.analyzer), false});
  }
  counters_.analyzers = options_.analyzers;
  watchdog_ = std::thread([this] { watch(); });
}

AnalysisPool::~AnalysisPool() {
  {
    std::lock_guard lock(mutex_);
    shutting_down_ = true;
    for (Ticket* t : watched_) t->stop(StopReason::shutdown);
  }
  watch_wake_.notify_all();
  freed_.notify_all();
  watchdog_.join();
}

void AnalysisPool::watch() {
  std::unique_lock lock(mutex_);
  while (!shutting_down_) {
    watch_wake_.wait_for(lock, kWatchPeriod);
    bool any = false;
    for (Ticket* t : watched_) any = t->check() || any;
    if (any) freed_.notify_all();  // waiters whose ticket stopped give up
  }
}

void AnalysisPool::note_stop(const Ticket& ticket) {
  if (ticket.reason() == StopReason::deadline) ++counters_.stopped_deadline;
  if (ticket.reason() == StopReason::client_gone) ++counters_.stopped_client_gone;
}

std::optional<Refusal> AnalysisPool::run(Ticket& ticket, const Work& work) {
  std::unique_lock lock(mutex_);
  watched_.push_back(&ticket);
  struct Unwatch {
    AnalysisPool* pool;
    Ticket* ticket;
    ~Unwatch() { std::erase(pool->watched_, ticket); }  // with mutex_ held
  };
  Unwatch unwatch{this, &ticket};
  auto free_slot = [&] {
    return std::find_if(slots_.begin(), slots_.end(), [](const Slot& s) { return !s.busy; });
  };
  if (free_slot() == slots_.end()) {
    if (waiting_ >= options_.max_waiting) {
      ++counters_.rejected_busy;
      const std::size_t running = slots_.size();
      return Refusal{Refusal::busy, "the service is busy: " + std::to_string(running) +
                                        (running == 1 ? " analysis is" : " analyses are") +
                                        " running and " + std::to_string(waiting_) +
                                        (waiting_ == 1 ? " is" : " are") +
                                        " waiting, the most it queues; retry later"};
    }
    ++waiting_;
    freed_.wait(lock,
                [&] { return free_slot() != slots_.end() || ticket.stopped() || shutting_down_; });
    --waiting_;
  }
  if (ticket.stopped() || shutting_down_) {
    ticket.stop(StopReason::shutdown);  // no-op unless the service is stopping
    note_stop(ticket);
    return Refusal{Refusal::stopped, ""};
  }
  Slot& slot = *free_slot();
  slot.busy = true;
  lock.unlock();
  Analyzer& analyzer = *slot.analyzer;
  analyzer.set_cancel(&ticket.flag());
  try {
    work(analyzer);
  } catch (...) {
    analyzer.set_cancel(nullptr);
    analyzer.clear_cache();
    lock.lock();
    slot.busy = false;
    freed_.notify_one();
    throw;
  }
  analyzer.set_cancel(nullptr);
  // A cancelled run leaves nothing half-made in the analyzer's caches (the core caches only
  // what finished); bound what finished runs keep.
  if (analyzer.cached_pallets() > std::size_t(options_.max_prepared_per_analyzer)) {
    analyzer.clear_cache();
  }
  lock.lock();
  slot.busy = false;
  freed_.notify_one();
  if (ticket.stopped()) {
    note_stop(ticket);
    return Refusal{Refusal::stopped, ""};
  }
  return std::nullopt;
}

void AnalysisPool::remember(const std::string& key, std::shared_ptr<const CachedEnvelope> value) {
  if (cache_.insert_or_assign(key, std::move(value)).second) cache_order_.push_back(key);
  while (cache_.size() > options_.max_cached_envelopes && !cache_order_.empty()) {
    cache_.erase(cache_order_.front());
    cache_order_.pop_front();
  }
}

namespace {

// A cached envelope is the load's (config_fingerprint leaves the pallet's id out), shared by every
// pallet that carries that load: the answer names the pallet asked about.
std::shared_ptr<const CachedEnvelope> named_for(std::shared_ptr<const CachedEnvelope> value,
                                                const PalletConfig& config) {
  if (value->envelope.result.pallet_id == config.pallet_id) return value;
  auto named = std::make_shared<CachedEnvelope>(*value);
  named->envelope.result.pallet_id = config.pallet_id;
  return named;
}

}  // namespace

std::variant<Analysis, Refusal, Diagnostics> AnalysisPool::analyze(Ticket& ticket,
                                                                   const PalletConfig& config) {
  const auto start = std::chrono::steady_clock::now();
  const std::string key = config_fingerprint(config);
  for (;;) {
    std::shared_ptr<Flight> flight;
    bool leader = false;
    {
      std::unique_lock lock(mutex_);
      if (auto it = cache_.find(key); it != cache_.end()) {
        ++counters_.cache_hits;
        return Analysis{named_for(it->second, config), true, ms_since(start)};
      }
      if (auto it = flights_.find(key); it != flights_.end()) {
        flight = it->second;
      } else {
        flight = std::make_shared<Flight>();
        flights_.emplace(key, flight);
        leader = true;
        ++counters_.cache_misses;
      }
      if (!leader) {  // wait for the leader's answer, watching this ticket meanwhile
        watched_.push_back(&ticket);
        freed_.wait(lock, [&] { return flight->done || ticket.stopped() || shutting_down_; });
        std::erase(watched_, &ticket);
        if (ticket.stopped() || shutting_down_) {
          note_stop(ticket);
          return Refusal{Refusal::stopped, ""};
        }
        if (flight->value) {
          ++counters_.cache_hits;
          return Analysis{named_for(flight->value, config), true, ms_since(start)};
        }
        if (flight->failure) return *flight->failure;
        continue;  // the leader was stopped: try again, perhaps as the leader
      }
    }
    std::optional<Result<Envelope>> computed;
    double compute_ms = 0.0;
    const auto refusal = run(ticket, [&](Analyzer& analyzer) {
      const auto t0 = std::chrono::steady_clock::now();
      computed = analyzer.envelope(config);
      compute_ms = ms_since(t0);
    });
    std::lock_guard lock(mutex_);
    flights_.erase(key);
    flight->done = true;
    freed_.notify_all();
    if (refusal) return *refusal;
    if (!*computed) {
      flight->failure = computed->diagnostics;
      return std::move(computed->diagnostics);
    }
    auto value = std::make_shared<CachedEnvelope>();
    value->envelope = std::move(*computed->value);
    value->compute_ms = compute_ms;
    counters_.simulations += std::uint64_t(std::max(0, value->envelope.result.sims_run));
    flight->value = value;
    remember(key, value);
    return Analysis{std::move(value), false, ms_since(start)};
  }
}

void AnalysisPool::count_simulations(int sims) {
  std::lock_guard lock(mutex_);
  counters_.simulations += std::uint64_t(std::max(0, sims));
}

PoolStats AnalysisPool::stats() const {
  std::lock_guard lock(mutex_);
  PoolStats s = counters_;
  s.busy = int(std::count_if(slots_.begin(), slots_.end(), [](const Slot& x) { return x.busy; }));
  s.waiting = waiting_;
  s.cached_envelopes = cache_.size();
  return s;
}

}  // namespace pb::server
