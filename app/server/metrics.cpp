// SPDX-License-Identifier: MIT
#include "app/server/metrics.hpp"

#include <sstream>

namespace pb::server {

namespace {

std::string labels(const std::string& method, const std::string& route) {
  return "method=\"" + method + "\",route=\"" + route + "\"";
}

// Bucket bounds as Prometheus clients write them ("0.005", "1", "10").
std::string bound(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

}  // namespace

void Metrics::observe(const std::string& method, const std::string& route, int status,
                      double seconds) {
  std::lock_guard lock(mutex_);
  ++requests_[{method, route, status}];
  Histogram& h = latency_[{method, route}];
  for (std::size_t i = 0; i < kBuckets.size(); ++i) {
    if (seconds <= kBuckets[i]) ++h.buckets[i];
  }
  ++h.count;
  h.sum += seconds;
}

std::string Metrics::text(const PoolStats& pool) const {
  std::ostringstream out;
  out.precision(9);
  std::lock_guard lock(mutex_);
  out << "# HELP palletballet_requests_total HTTP requests answered, by route and status.\n"
         "# TYPE palletballet_requests_total counter\n";
  for (const auto& [key, n] : requests_) {
    const auto& [method, route, status] = key;
    out << "palletballet_requests_total{" << labels(method, route) << ",status=\"" << status
        << "\"} " << n << "\n";
  }
  out << "# HELP palletballet_request_duration_seconds Time from request to response.\n"
         "# TYPE palletballet_request_duration_seconds histogram\n";
  for (const auto& [key, h] : latency_) {
    const std::string l = labels(key.first, key.second);
    for (std::size_t i = 0; i < kBuckets.size(); ++i) {
      out << "palletballet_request_duration_seconds_bucket{" << l << ",le=\"" << bound(kBuckets[i])
          << "\"} " << h.buckets[i] << "\n";
    }
    out << "palletballet_request_duration_seconds_bucket{" << l << ",le=\"+Inf\"} " << h.count
        << "\n";
    out << "palletballet_request_duration_seconds_sum{" << l << "} " << h.sum << "\n";
    out << "palletballet_request_duration_seconds_count{" << l << "} " << h.count << "\n";
  }
  auto metric = [&](const char* name, const char* type, const char* help, auto value) {
    out << "# HELP " << name << " " << help << "\n# TYPE " << name << " " << type << "\n"
        << name << " " << value << "\n";
  };
  metric("palletballet_simulations_total", "counter", "Simulations run by the service's analyses.",
         pool.simulations);
  metric("palletballet_cache_hits_total", "counter",
         "Analyses answered from the shared envelope cache.", pool.cache_hits);
  metric("palletballet_cache_misses_total", "counter", "Analyses that had to be computed.",
         pool.cache_misses);
  metric("palletballet_cached_envelopes", "gauge", "Envelopes held in the shared cache.",
         pool.cached_envelopes);
  metric("palletballet_analyzers", "gauge", "Analyses that can run at once.", pool.analyzers);
  metric("palletballet_analyzers_busy", "gauge", "Analyses running now.", pool.busy);
  metric("palletballet_queue_depth", "gauge", "Requests waiting for an analyzer.", pool.waiting);
  metric("palletballet_rejected_busy_total", "counter",
         "Requests refused (503) because the queue was full.", pool.rejected_busy);
  out << "# HELP palletballet_cancelled_total Work stopped before it finished, by reason.\n"
         "# TYPE palletballet_cancelled_total counter\n"
      << "palletballet_cancelled_total{reason=\"deadline\"} " << pool.stopped_deadline << "\n"
      << "palletballet_cancelled_total{reason=\"client_gone\"} " << pool.stopped_client_gone
      << "\n";
  return out.str();
}

}  // namespace pb::server
