// SPDX-License-Identifier: MIT
// Fuzz target: a request to palletballet-server, without the network. The input's first line is
// "METHOD target" (a path with an optional ?query, percent-decoding left to the HTTP layer), the
// rest is the body. Service::handle must answer every request with a status and a JSON body (a
// 500 is a finding: the service's own error), never crash, throw or hang: an analysis stops at a
// short time limit (503), as a slow one does in production.
#include <cstdio>
#include <cstdlib>
#include <string>

#include "app/server/service.hpp"
#include "core/contract/json_io.hpp"
#include "tests/fuzz/fuzz_target.hpp"

namespace {

pb::server::Service& service() {
  static pb::server::Service s([] {
    pb::server::ServiceOptions o;
    o.pool.analyzers = 1;
    o.pool.max_cached_envelopes = 16;
    o.pool.max_prepared_per_analyzer = 1;
    o.time_limit_s = 0.2;
    o.max_uncertainty_samples = 2;
    o.version = "fuzz";
    return o;
  }());
  return s;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text = pb::fuzz::as_text(data, size);
  const auto eol = text.find('\n');
  const std::string_view line = text.substr(0, eol);
  pb::server::Request request;
  const auto space = line.find(' ');
  request.method = std::string(line.substr(0, space));
  std::string target = space == std::string_view::npos ? "/" : std::string(line.substr(space + 1));
  if (const auto q = target.find('?'); q != std::string::npos) {
    std::string query = target.substr(q + 1);
    target.resize(q);
    std::size_t start = 0;
    while (start <= query.size()) {
      const auto amp = std::min(query.find('&', start), query.size());
      const std::string pair = query.substr(start, amp - start);
      const auto eq = pair.find('=');
      request.query.emplace(pair.substr(0, eq), eq == std::string::npos ? "" : pair.substr(eq + 1));
      start = amp + 1;
    }
  }
  request.path = target;
  if (eol != std::string_view::npos) request.body = std::string(text.substr(eol + 1));
  const pb::server::Response response = service().handle(request);
  const bool failed = response.status >= 500 && response.status != 503;
  if (failed || (response.content_type == "application/json" && !pb::parse_json(response.body))) {
    std::fprintf(stderr, "%s %s -> %d %s\n", request.method.c_str(), request.path.c_str(),
                 response.status, response.body.substr(0, 2000).c_str());
    std::abort();
  }
  return 0;
}
