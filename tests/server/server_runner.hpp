// SPDX-License-Identifier: MIT
// Starts palletballet-server on a free port of 127.0.0.1 as an operator would, and talks to it
// over HTTP with cpp-httplib's client.
#pragma once

#include <httplib.h>

#include <QProcess>
#include <QString>
#include <QStringList>
#include <QTest>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

namespace pb::test {

using Json = nlohmann::json;

class ServerProcess {
 public:
  /// Starts the server with `flags` (and --port 0); port() is 0 if it did not come up.
  explicit ServerProcess(const QStringList& flags = {}) {
    process_.setProgram(QStringLiteral(PB_BIN_DIR "/palletballet-server"));
    process_.setArguments(QStringList{"--port", "0"} + flags);
    process_.start();
    // The first line says where it listens: "... listening on http://127.0.0.1:PORT (...)".
    for (int i = 0; i < 100 && port_ == 0; ++i) {
      if (!process_.canReadLine()) process_.waitForReadyRead(100);
      if (process_.state() == QProcess::NotRunning) break;
      while (process_.canReadLine()) {
        const QString line = QString::fromUtf8(process_.readLine());
        const qsizetype at = line.indexOf("127.0.0.1:");
        if (at >= 0) port_ = line.mid(at + 10).section(' ', 0, 0).toInt();
      }
    }
  }
  ~ServerProcess() {
    if (process_.state() != QProcess::NotRunning) {
      process_.terminate();
      if (!process_.waitForFinished(10000)) process_.kill();
      process_.waitForFinished();
    }
  }

  int port() const { return port_; }
  QProcess& process() { return process_; }

  /// A client with generous timeouts (an analysis of an unwrapped load takes seconds).
  std::unique_ptr<httplib::Client> client(int read_timeout_ms = 300000) const {
    auto c = std::make_unique<httplib::Client>("127.0.0.1", port_);
    c->set_read_timeout(read_timeout_ms / 1000, (read_timeout_ms % 1000) * 1000);
    c->set_connection_timeout(5, 0);
    c->set_tcp_nodelay(true);
    return c;
  }

 private:
  QProcess process_;
  int port_ = 0;
};

inline Json body_of(const httplib::Result& r) {
  return r ? Json::parse(r->body, nullptr, false) : Json();
}

}  // namespace pb::test
