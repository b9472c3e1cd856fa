// SPDX-License-Identifier: MIT
// palletballet-server under load and abuse: 50 concurrent requests answered as serial ones are, a
// client that leaves mid-analysis has its work stopped, a full queue says busy, a request over the
// time limit is stopped with a 503, and SIGTERM ends the process cleanly.
#include <QtTest>

#include <atomic>
#include <thread>
#include <vector>

#include "core/analysis/analyzer.hpp"
#include "core/contract/json_io.hpp"
#include "core/inputs/catalog.hpp"
#include "core/inputs/random_pallet.hpp"
#include "core/inputs/scenario.hpp"
#include "tests/server/server_runner.hpp"

using pb::test::body_of;
using pb::test::Json;
using pb::test::ServerProcess;

namespace {

const char* kJson = "application/json";

// A metric's value in the exposition text (0 if absent).
double metric(httplib::Client& c, const std::string& series) {
  auto res = c.Get("/metrics");
  if (!res) return -1;
  const auto at = res->body.find("\n" + series + " ");
  if (at == std::string::npos) return 0;
  return std::stod(res->body.substr(at + series.size() + 2));
}

std::string slow_pallet() {  // an unwrapped tower: its failure map takes seconds (240 probes)
  return pb::pallet_to_json(pb::load_scenario("tall-unwrapped-tower")->pallet).dump();
}

}  // namespace

class ServiceLoadTest : public QObject {
  Q_OBJECT

 private slots:
  void fifty_concurrent_requests_answer_as_serial_ones_do() {
    ServerProcess server;
    QVERIFY(server.port() > 0);
    // Five wrapped random pallets, each asked for ten times at once.
    std::vector<pb::PalletConfig> pallets;
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
      pb::RandomPalletOptions o;
      o.seed = seed;
      o.min_layers = 2;
      o.max_layers = 4;
      pallets.push_back(*pb::random_pallet(o, pb::Catalog::builtin()).value);
    }
    std::vector<Json> answers(50);
    std::vector<int> status(50, 0);
    std::vector<std::thread> clients;
    for (int i = 0; i < 50; ++i) {
      clients.emplace_back([&, i] {
        auto c = server.client();
        auto res = c->Post("/safety/analyze",
                           pb::pallet_to_json(pallets[std::size_t(i % 5)]).dump(), kJson);
        status[std::size_t(i)] = res ? res->status : -100 - int(res.error());
        answers[std::size_t(i)] = body_of(res);
      });
    }
    for (auto& t : clients) t.join();
    pb::Analyzer serial;
    int computed = 0;
    for (int i = 0; i < 50; ++i) {
      QCOMPARE(status[std::size_t(i)], 200);
      const Json& r = answers[std::size_t(i)]["result"];
      auto expected = serial.analyze(pallets[std::size_t(i % 5)]);
      QVERIFY(expected.ok());
      QCOMPARE(r["max_speed_mps"].get<double>(), expected->max_speed_mps);
      QCOMPARE(r["max_accel_mps2"].get<double>(), expected->max_accel_mps2);
      QCOMPARE(r["max_decel_mps2"].get<double>(), expected->max_decel_mps2);
      QCOMPARE(r["max_lateral_g"].get<double>(), expected->max_lateral_g);
      QCOMPARE(r["dominant_failure_mode"].get<std::string>(),
               std::string(pb::to_string(expected->dominant_failure_mode)));
      QCOMPARE(r["config_hash"].get<std::string>(), expected->config_hash);
      if (answers[std::size_t(i)]["cache_hits"].get<int>() == 0) ++computed;
    }
    QCOMPARE(computed, 5);  // each pallet computed once, whatever the interleaving
    auto c = server.client();
    QCOMPARE(metric(*c, "palletballet_cache_misses_total"), 5.0);
    QCOMPARE(metric(*c, "palletballet_cache_hits_total"), 45.0);
  }

  void a_client_that_leaves_has_its_work_stopped() {
    ServerProcess server;
    QVERIFY(server.port() > 0);
    {
      auto c = server.client(400);  // gives up after 0.4 s, closing its connection
      auto res = c->Post("/v1/map", slow_pallet(), kJson);
      QVERIFY(!res);
    }
    auto c = server.client();
    QTRY_COMPARE_WITH_TIMEOUT(metric(*c, "palletballet_cancelled_total{reason=\"client_gone\"}"),
                              1.0, 5000);
    QTRY_COMPARE_WITH_TIMEOUT(metric(*c, "palletballet_analyzers_busy"), 0.0, 5000);
    QCOMPARE(body_of(c->Get("/healthz"))["cached_envelopes"].get<int>(), 0);
  }

  void a_full_queue_is_busy_and_a_long_request_is_stopped() {
    ServerProcess server({"--analyzers", "1", "--max-waiting", "0", "--time-limit", "1.5"});
    QVERIFY(server.port() > 0);
    std::atomic<int> slow_status{0};
    std::string slow_detail;
    std::thread slow([&] {
      auto c = server.client();
      auto res = c->Post("/v1/map", slow_pallet(), kJson);
      slow_status = res ? res->status : -1;
      slow_detail = body_of(res)["detail"];
    });
    auto c = server.client();
    QTRY_COMPARE_WITH_TIMEOUT(metric(*c, "palletballet_analyzers_busy"), 1.0, 5000);
    auto busy = c->Post("/safety/analyze", slow_pallet(), kJson);
    QCOMPARE(busy->status, 503);
    QCOMPARE(busy->get_header_value("Retry-After"), "1");
    QVERIFY(body_of(busy)["detail"].get<std::string>().find("busy") != std::string::npos);
    slow.join();
    QCOMPARE(slow_status.load(), 503);
    QVERIFY(slow_detail.find("limit of 1.5 s") != std::string::npos);
    QCOMPARE(metric(*c, "palletballet_cancelled_total{reason=\"deadline\"}"), 1.0);
    QCOMPARE(body_of(c->Get("/healthz"))["status"], "ok");
  }

  void sigterm_stops_the_server() {
    ServerProcess server;
    QVERIFY(server.port() > 0);
    server.process().terminate();
    QVERIFY(server.process().waitForFinished(10000));
    QCOMPARE(server.process().exitStatus(), QProcess::NormalExit);
    QCOMPARE(server.process().exitCode(), 0);
  }

  void a_port_in_use_is_a_clear_error() {
    ServerProcess first;
    QVERIFY(first.port() > 0);
    QProcess second;
    second.start(QStringLiteral(PB_BIN_DIR "/palletballet-server"),
                 {"--port", QString::number(first.port())});
    QVERIFY(second.waitForFinished(10000));
    QCOMPARE(second.exitCode(), 1);
    QVERIFY(second.readAllStandardError().contains("choose another --port"));
  }
};

QTEST_APPLESS_MAIN(ServiceLoadTest)
#include "service_load_test.moc"
