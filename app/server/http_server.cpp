// SPDX-License-Identifier: MIT
#include "app/server/http_server.hpp"

#include <arpa/inet.h>
#include <httplib.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <filesystem>
#include <string>
#include <utility>

namespace pb::server {

namespace {

// The port and numeric address of a socket address.
bool address_of(const sockaddr_storage& a, std::string& host, int& port) {
  char text[INET6_ADDRSTRLEN] = {};
  if (a.ss_family == AF_INET) {
    const auto* v4 = reinterpret_cast<const sockaddr_in*>(&a);
    inet_ntop(AF_INET, &v4->sin_addr, text, sizeof text);
    port = ntohs(v4->sin_port);
  } else if (a.ss_family == AF_INET6) {
    const auto* v6 = reinterpret_cast<const sockaddr_in6*>(&a);
    inet_ntop(AF_INET6, &v6->sin6_addr, text, sizeof text);
    port = ntohs(v6->sin6_port);
  } else {
    return false;
  }
  host = text;
  return true;
}

/// The descriptor of this process's connected socket from `remote` to `local_port`, or -1.
/// cpp-httplib 0.11 gives a handler no socket (0.12 added Request::is_connection_closed), so the
/// connection is found by its address pair, once per request that may run long.
int find_connection(const std::string& remote_addr, int remote_port, int local_port) {
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator("/proc/self/fd", ec)) {
    int fd = -1;
    try {
      fd = std::stoi(entry.path().filename().string());
    } catch (...) {
      continue;
    }
    struct stat st {};
    if (fstat(fd, &st) != 0 || !S_ISSOCK(st.st_mode)) continue;
    sockaddr_storage peer{}, self{};
    socklen_t peer_len = sizeof peer, self_len = sizeof self;
    if (getpeername(fd, reinterpret_cast<sockaddr*>(&peer), &peer_len) != 0) continue;
    if (getsockname(fd, reinterpret_cast<sockaddr*>(&self), &self_len) != 0) continue;
    std::string peer_host, self_host;
    int pp = -1, sp = -1;
    if (!address_of(peer, peer_host, pp) || !address_of(self, self_host, sp)) continue;
    if (pp == remote_port && sp == local_port && peer_host == remote_addr) return fd;
  }
  return -1;
}

/// False once the peer has closed (an orderly shutdown reads as 0 bytes) or the socket failed.
bool peer_connected(int fd) {
  char c = 0;
  const ssize_t n = recv(fd, &c, 1, MSG_PEEK | MSG_DONTWAIT);
  if (n > 0) return true;  // a pipelined next request: still there
  if (n == 0) return false;
  return errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR;
}

// A refusal's JSON, as the service's: `detail`, and one error that says it.
std::string refusal_json(const std::string& detail) {
  const nlohmann::json body = {{"detail", detail},
                               {"errors", {{{"pointer", ""}, {"message", detail}}}}};
  return body.dump();
}

// Our JSON for a request that cpp-httplib, or the reading of its body, refused with `status`.
std::string error_body(const httplib::Request& req, int status, std::size_t max_body) {
  std::string detail = "the request could not be read (HTTP " + std::to_string(status) + ")";
  if (status == 413) {
    detail = "the body is larger than this service's limit of " + std::to_string(max_body) +
             " bytes (--max-body); send a smaller document";
    // cpp-httplib parses a form body itself and caps it at 8 KiB, whatever our limit.
    if (req.get_header_value("Content-Type").starts_with("application/x-www-form-urlencoded")) {
      detail =
          "the body was sent as application/x-www-form-urlencoded, which is read only up "
          "to 8192 bytes; send JSON with the header content-type: application/json";
    }
  }
  return refusal_json(detail);  // ASCII only
}

// What is wrong with a request's framing before its body is read, as (status, detail); status 0
// when nothing is. cpp-httplib 0.11 reads Content-Length with strtoull and takes the first of
// several: "-5" wrapped round to 2^64 - 5 and waited 30 s for the body before a 413, "abc" read as
// no body, and two different lengths were taken as the first (RFC 9112 6.3: a request whose
// length is ambiguous must be refused, or a proxy in front that takes the other one is smuggled a
// second request). A declared length far past the limit is refused before the body is sent.
std::pair<int, std::string> framing_error(const httplib::Request& req, std::size_t max_body) {
  const std::size_t lengths = req.get_header_value_count("Content-Length");
  if (lengths == 0) return {0, {}};
  if (req.has_header("Transfer-Encoding")) {
    return {400, "the request has both Transfer-Encoding and Content-Length; send one of them"};
  }
  const std::string first = req.get_header_value("Content-Length", 0);
  for (std::size_t k = 0; k < lengths; ++k) {
    const std::string value = req.get_header_value("Content-Length", k);
    const bool digits =
        !value.empty() && value.size() <= 19 &&
        std::all_of(value.begin(), value.end(), [](char c) { return c >= '0' && c <= '9'; });
    if (!digits) {
      std::string shown = value.substr(0, 40);  // printable ASCII only: the reply is JSON
      for (char& c : shown) c = c >= ' ' && c <= '~' ? c : '?';
      return {400, "Content-Length '" + shown +
                       "' is not a number of bytes; send the body's length in bytes"};
    }
    if (value != first) {
      return {400, "the request has two different Content-Length headers (" + first + " and " +
                       value + "); send one"};
    }
  }
  // A body up to four times the limit is read and dropped (with_body, cpp-httplib), so that a
  // client still sending gets its 413; past that nobody waits for it.
  if (std::stoull(first) > 4 * max_body) {
    return {413, "the body (" + first + " bytes) is larger than this service's limit of " +
                     std::to_string(max_body) + " bytes (--max-body); send a smaller document"};
  }
  return {0, {}};
}

// A request of a method whose body cpp-httplib reads that declares no body: neither a
// Content-Length nor a Transfer-Encoding, so under RFC 9112 6.3 its body is empty. cpp-httplib
// 0.11 would read one until the client closed or its 30 s timeout passed, holding a connection
// thread all the while (eighty such requests kept /healthz from answering for 34 s).
bool without_body(const httplib::Request& req) {
  const bool reads_body = req.method == "POST" || req.method == "PUT" || req.method == "PATCH" ||
                          req.method == "DELETE";
  return reads_body && !req.has_header("Content-Length") && !req.has_header("Transfer-Encoding");
}

}  // namespace

struct HttpServer::Impl {
  httplib::Server server;
  int listen_socket = -1;  ///< the listening socket, seen as cpp-httplib creates it
};

HttpServer::HttpServer(Service& service, HttpOptions options) : impl_(std::make_unique<Impl>()) {
  httplib::Server& s = impl_->server;
  const PoolOptions& pool = service.options().pool;
  const int threads = options.threads > 0 ? options.threads : pool.analyzers + pool.max_waiting + 4;
  s.new_task_queue = [threads] { return new httplib::ThreadPool(std::size_t(threads)); };
  s.set_payload_max_length(service.options().max_body_bytes);
  // SO_REUSEADDR only: cpp-httplib's default adds SO_REUSEPORT, which would let a second instance
  // bind the same port silently and take half its connections.
  s.set_socket_options([this](int sock) {
    int yes = 1;
    setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    impl_->listen_socket = sock;
  });
  s.set_keep_alive_timeout(options.keep_alive_s);
  s.set_tcp_nodelay(true);  // a response written in two parts must not wait for an ACK
  s.set_read_timeout(30, 0);
  s.set_write_timeout(30, 0);
  const std::vector<std::string> origins = options.cors_origins;
  auto cors = [origins](const httplib::Request& req, httplib::Response& res) {
    const std::string origin = req.get_header_value("Origin");
    if (origin.empty() || origins.empty()) return;
    const bool any = std::find(origins.begin(), origins.end(), "*") != origins.end();
    if (!any && std::find(origins.begin(), origins.end(), origin) == origins.end()) return;
    res.set_header("Access-Control-Allow-Origin", any ? "*" : origin);
    if (!any) res.set_header("Vary", "Origin");
  };
  const std::size_t max_body = service.options().max_body_bytes;
  auto handle = [&service, cors](const httplib::Request& req, std::string body,
                                 httplib::Response& res) {
    Request request;
    request.method = req.method;
    request.path = req.path;
    for (const auto& [k, v] : req.params) request.query.emplace(k, v);
    request.body = std::move(body);
    request.content_type = req.get_header_value("Content-Type");
    // Looked up lazily, by the watchdog's first poll: cheap requests never pay for it.
    auto fd = std::make_shared<int>(-2);
    const std::string remote = req.remote_addr;
    const int remote_port = req.remote_port, local_port = req.local_port;
    request.client_alive = [fd, remote, remote_port, local_port] {
      if (*fd == -2) *fd = find_connection(remote, remote_port, local_port);
      return *fd < 0 || peer_connected(*fd);
    };
    Response response = service.handle(request);
    cors(req, res);
    for (const auto& [k, v] : response.headers) res.set_header(k, v);
    res.status = response.status;
    if (!response.content_type.empty()) res.set_content(response.body, response.content_type);
  };
  // A body is read here, not by cpp-httplib: 0.11 holds a body to set_payload_max_length only
  // when it comes with a Content-Length, and reads a chunked one whole, however large (a 60 MB
  // chunked upload was read and parsed). A multipart body goes through cpp-httplib's parser and is
  // dropped: the service takes JSON. Past the limit a body is read on and dropped, up to four times
  // the limit, so that the client, still sending, gets the 413 rather than a closed connection.
  auto with_body = [handle, max_body, &service](const httplib::Request& req, httplib::Response& res,
                                                const httplib::ContentReader& read) {
    const auto start = std::chrono::steady_clock::now();
    std::string body;
    std::size_t seen = 0;
    auto keep = [&](const char* data, std::size_t n) {
      seen += n;
      if (seen <= max_body && data != nullptr) body.append(data, n);
      return seen <= 4 * max_body;
    };
    const bool read_all = req.is_multipart_form_data()
                              ? read([](const httplib::MultipartFormData&) { return true; },
                                     [&](const char*, std::size_t n) { return keep(nullptr, n); })
                              : read(keep);
    if (!read_all || seen > max_body) {
      res.status = seen > max_body || res.status == 413 ? 413 : 400;
      if (!read_all) res.set_header("Connection", "close");  // the rest of it is not read
      res.set_content(error_body(req, res.status, max_body), "application/json");
      service.refused(
          req.method, req.path, res.status,
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      return;
    }
    handle(req, std::move(body), res);
  };
  s.Get(".*", [handle](const httplib::Request& req, httplib::Response& res) {
    handle(req, req.body, res);
  });
  s.Post(".*", with_body);
  s.Put(".*", with_body);
  s.Delete(".*", with_body);
  s.Patch(".*", with_body);
  // A preflight: the service says which methods the path answers (204; a path with no route is
  // a 404), and a browser may send any header.
  s.Options(".*", [handle](const httplib::Request& req, httplib::Response& res) {
    handle(req, req.body, res);
    if (res.status != 204) return;
    res.set_header("Access-Control-Allow-Headers", "*");
    res.set_header("Access-Control-Max-Age", "600");
  });
  // A body whose framing is wrong is refused before it is read, with Connection: close (the
  // client must not send on it; cpp-httplib 0.11 keeps it open and reads what follows as a request,
  // which it refuses).
  s.set_pre_routing_handler(
      [max_body, cors, handle, &service](const httplib::Request& req, httplib::Response& res) {
        auto [status, detail] = framing_error(req, max_body);
        if (status == 0 && without_body(req)) {  // answered now, with its empty body
          handle(req, std::string(), res);
          return httplib::Server::HandlerResponse::Handled;
        }
        if (status == 0) return httplib::Server::HandlerResponse::Unhandled;
        cors(req, res);
        res.status = status;
        res.set_header("Connection", "close");
        res.set_content(refusal_json(detail), "application/json");
        service.refused(req.method, req.path, status, 0.0);
        return httplib::Server::HandlerResponse::Handled;
      });
  // What cpp-httplib answers itself (an oversized body, a malformed request) gets our JSON.
  // (Every answer of ours has a body: an empty one is cpp-httplib's own, counted here.)
  s.set_error_handler([max_body, &service](const httplib::Request& req, httplib::Response& res) {
    if (!res.body.empty()) return;
    res.set_content(error_body(req, res.status, max_body), "application/json");
    service.refused(req.method.empty() ? "unknown" : req.method, req.path, res.status, 0.0);
  });
  s.set_exception_handler([](const httplib::Request&, httplib::Response& res, std::exception_ptr) {
    res.status = 500;
    res.set_content(
        R"({"detail":"internal error","errors":[{"pointer":"","message":"internal error"}]})",
        "application/json");
  });
  port_ = options.port;
  host_ = options.host;
}

HttpServer::~HttpServer() = default;

bool HttpServer::bind(std::string& error) {
  httplib::Server& s = impl_->server;
  if (port_ == 0) {
    port_ = s.bind_to_any_port(host_);
    if (port_ < 0) {
      error = "cannot listen on " + host_ + ": no free port";
      return false;
    }
  } else if (!s.bind_to_port(host_, port_)) {
    error = "cannot listen on " + host_ + ":" + std::to_string(port_) +
            " (in use, or not an address of this machine); choose another --port or --host";
    return false;
  }
  // cpp-httplib listens with a backlog of 5: a burst of clients connecting at once would see
  // connections dropped. Listening again on the same socket only raises the backlog.
  if (impl_->listen_socket >= 0) ::listen(impl_->listen_socket, SOMAXCONN);
  return true;
}

void HttpServer::listen() {
  impl_->server.listen_after_bind();
}

void HttpServer::stop() {
  impl_->server.stop();
}

}  // namespace pb::server
