// SPDX-License-Identifier: MIT
// The service without the network: a request (method, path, query, body) in, a response (status,
// JSON) out. Every route of the reference system's API with its request and response shapes, and
// ours under /v1/. Thread-safe: the HTTP layer calls handle() from its worker threads at once.
#pragma once

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "app/server/analysis_pool.hpp"
#include "app/server/metrics.hpp"

namespace pb::server {

struct Request {
  std::string method;  ///< "GET", "POST", ...
  std::string path;    ///< without the query
  std::multimap<std::string, std::string> query;
  std::string body;
  std::string content_type;  ///< the Content-Type header ("" when absent)
  /// False once the client has gone (closed its connection); empty: assumed present.
  std::function<bool()> client_alive;
};

struct Response {
  int status = 200;
  std::string body;
  std::string content_type = "application/json";  ///< "" for a response without a body (204)
  std::map<std::string, std::string> headers;
  std::string route;  ///< the route's pattern, for metrics ("" when no route matched)
};

struct ServiceOptions {
  PoolOptions pool;
  std::size_t max_body_bytes = 8u << 20;  ///< larger bodies: 413 (enforced by the HTTP layer)
  std::size_t max_items = 400;            ///< items of one pallet; more: 413
  std::size_t max_batch = 256;            ///< pallets of one /safety/batch; more: 413
  double time_limit_s = 60.0;             ///< per request; beyond it the work stops: 503
  int max_uncertainty_samples = 256;
  std::string version;
};

class Service {
 public:
  explicit Service(ServiceOptions options);

  /// Answers one request; never throws (an internal error is a 500 with its reason).
  Response handle(const Request& request);

  const ServiceOptions& options() const { return options_; }
  AnalysisPool& pool() { return pool_; }
  Metrics& metrics() { return metrics_; }

  /// Counts a request the HTTP layer refused before handle() saw it (a body over the limit, a
  /// framing error), under the route its path matches, so /metrics counts every answer.
  void refused(const std::string& method, const std::string& path, int status, double seconds);

  /// Every route, "METHOD /pattern", in the order they are matched.
  std::vector<std::string> routes() const;

 private:
  using Params = std::map<std::string, std::string>;
  struct Route {
    std::string method;
    std::string pattern;  ///< "/scenarios/{slug}": a {name} segment matches any one segment
    std::function<Response(const Request&, const Params&)> handler;
    /// The query parameters the route reads; any other, or one given twice, is refused.
    std::vector<std::string> query = {};
  };
  Response dispatch(const Request& request, std::string& route);
  static std::optional<Response> query_problem(const Request& request, const Route& route);

  ServiceOptions options_;
  AnalysisPool pool_;
  Metrics metrics_;
  std::vector<Route> routes_;
};

}  // namespace pb::server
