// SPDX-License-Identifier: MIT
// The service on the network: HTTP/1.1 from cpp-httplib (Debian's libcpp-httplib), a bounded pool
// of connection threads, CORS for an allowlist of origins, a body limit, and a test of whether a
// request's client is still connected (so that abandoned work is cancelled).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "app/server/service.hpp"

namespace pb::server {

struct HttpOptions {
  std::string host = "127.0.0.1";
  int port = 8000;  ///< 0: any free port (port() says which)
  int threads = 0;  ///< connection threads; 0: analyzers + max_waiting + 4
  /// Origins whose browsers may call the service ("*": any); empty: no CORS headers.
  std::vector<std::string> cors_origins;
  int keep_alive_s = 5;
};

class HttpServer {
 public:
  HttpServer(Service& service, HttpOptions options);
  ~HttpServer();

  /// Binds the address; false (with `error` set) if it cannot.
  bool bind(std::string& error);
  int port() const { return port_; }
  /// Serves until stop() (from another thread or a signal handler's thread).
  void listen();
  void stop();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  int port_ = 0;
  std::string host_;
};

}  // namespace pb::server
