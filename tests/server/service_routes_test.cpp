// SPDX-License-Identifier: MIT
// palletballet-server over real HTTP, route by route: the reference system's calls from its post
// answered in its shapes, ours under /v1/, and every kind of bad request refused with a status and
// a sentence that names what to change.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>
#include <QtTest>
#include <set>

#include "core/analysis/analyzer.hpp"
#include "core/contract/json_io.hpp"
#include "core/inputs/scenario.hpp"
#include "tests/server/server_runner.hpp"

using pb::test::body_of;
using pb::test::Json;
using pb::test::ServerProcess;

namespace {

// Sends `request` on a new connection to the server and returns the reply, up to the end of its
// JSON body (the connection may stay open); empty when nothing came within 10 s.
std::string raw_exchange(int port, const std::string& request) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  if (fd < 0) return {};
  timeval timeout{10, 0};
  setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<std::uint16_t>(port));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  std::string reply;
  if (::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0 &&
      ::send(fd, request.data(), request.size(), MSG_NOSIGNAL) == ssize_t(request.size())) {
    char buffer[4096];
    for (;;) {
      const auto head_end = reply.find("\r\n\r\n");
      if (head_end != std::string::npos && reply.ends_with("}")) break;
      const ssize_t n = ::recv(fd, buffer, sizeof buffer, 0);
      if (n <= 0) break;
      reply.append(buffer, std::size_t(n));
    }
  }
  ::close(fd);
  return reply;
}

const char* kJson = "application/json";

std::string pallet_of(httplib::Client& c, const std::string& slug) {
  return body_of(c.Get(("/scenarios/" + slug).c_str()))["pallet"].dump();
}

// {members..., "pallet": pallet} posted to a route.
httplib::Result post_wrapped(httplib::Client& c, const char* route, const std::string& members,
                             const std::string& pallet) {
  return c.Post(route, "{" + members + ", \"pallet\": " + pallet + "}", kJson);
}

}  // namespace

class ServiceRoutesTest : public QObject {
  Q_OBJECT

 private slots:
  void initTestCase() {
    server_ = std::make_unique<ServerProcess>(QStringList{"--max-body", "200000"});
    QVERIFY2(server_->port() > 0, "the server did not start");
    client_ = server_->client();
  }
  void cleanupTestCase() {
    client_.reset();
    server_.reset();
  }

  void index_health_and_metrics() {
    const Json index = body_of(client_->Get("/"));
    QVERIFY(index["routes"].size() >= 20);
    const Json health = body_of(client_->Get("/healthz"));
    QCOMPARE(health["status"], "ok");
    QCOMPARE(health["analyzers"].get<int>(), 2);
    auto metrics = client_->Get("/metrics");
    QVERIFY(metrics && metrics->status == 200);
    QVERIFY(metrics->get_header_value("Content-Type").starts_with("text/plain"));
    QVERIFY(metrics->body.find("palletballet_requests_total{method=\"GET\",route=\"/healthz\","
                               "status=\"200\"}") != std::string::npos);
    QVERIFY(metrics->body.find("palletballet_request_duration_seconds_bucket") !=
            std::string::npos);
    QVERIFY(metrics->body.find("palletballet_queue_depth 0") != std::string::npos);
    // HEAD is GET without its body (a load balancer's probe); a POST route still refuses it.
    auto head = client_->Head("/healthz");
    QVERIFY(head && head->status == 200);
    QVERIFY(head->body.empty());
    QVERIFY(head->get_header_value("Content-Type").starts_with("application/json"));
    auto post_only = client_->Head("/v1/analyze");
    QVERIFY(post_only && post_only->status == 405);
    QCOMPARE(post_only->get_header_value("Allow"), std::string("POST"));
  }

  // The post: curl -s .../scenarios | jq -r '.[].slug'; .../scenarios/tall-unwrapped-tower | jq
  // .pallet
  void scenarios() {
    const Json list = body_of(client_->Get("/scenarios"));
    QCOMPARE(list.size(), pb::scenario_slugs().size());
    QCOMPARE(list[0]["slug"], "stable-dairy-slab");
    for (const char* key : {"name", "tag", "description", "expected_failure", "item_count",
                            "total_mass_kg", "stack_height_m"}) {
      QVERIFY2(list[0].contains(key), key);
    }
    const Json tower = body_of(client_->Get("/scenarios/tall-unwrapped-tower"));
    QVERIFY(tower["pallet"]["items"].is_array());
    QVERIFY(tower.contains("suggested_profile"));
    auto missing = client_->Get("/scenarios/no-such-pallet");
    QCOMPARE(missing->status, 404);
    QVERIFY(body_of(missing)["detail"].get<std::string>().find("stable-dairy-slab") !=
            std::string::npos);
  }

  void catalog_and_friction() {
    const Json skus = body_of(client_->Get("/catalog/skus"));
    QVERIFY(skus.size() > 10);
    const std::string sku = skus[0]["sku"];
    QCOMPARE(body_of(client_->Get(("/catalog/skus/" + sku).c_str()))["sku"], sku);
    QCOMPARE(client_->Get("/catalog/skus/NOPE")->status, 404);
    const Json pairs = body_of(client_->Get("/friction/pairs"));
    QVERIFY(std::find(pairs.begin(), pairs.end(), "wood_pallet/rubber_belt") != pairs.end());
    const Json curve = body_of(client_->Get("/friction/curve?pair=wood_pallet/rubber_belt&n=5"));
    QCOMPARE(curve["points"].size(), 5u);
    QCOMPARE(curve["surface_pair"][0], "wood_pallet");
    QCOMPARE(curve["points"][0]["temp_c"].get<double>(), -30.0);
    const Json point = body_of(client_->Get("/friction?temp_c=-20"));
    QVERIFY(point["mu_static"].get<double>() >= point["mu_dynamic"].get<double>());
    auto bad = client_->Get("/friction?temp_c=hot");
    QCOMPARE(bad->status, 422);
    QVERIFY(body_of(bad)["detail"].get<std::string>().find("temp_c") != std::string::npos);
    QCOMPARE(client_->Get("/friction/curve?pair=ice/ice")->status, 422);
  }

  // The post: POST /pallet/random {"seed": 23, "anomaly_rate": 0.25, "min_layers": 2, ...}
  void random_pallets_are_seeded() {
    const std::string req =
        R"({"seed": 23, "anomaly_rate": 0.25, "min_layers": 2, "max_layers": 5})";
    auto a = client_->Post("/pallet/random", req, kJson);
    auto b = client_->Post("/pallet/random", req, kJson);
    QCOMPARE(a->status, 200);
    QCOMPARE(a->body, b->body);
    const Json pallet = body_of(a);
    QVERIFY(pallet["items"].size() > 0);
    auto bad = client_->Post("/pallet/random", R"({"min_layers": 5, "max_layers": 2})", kJson);
    QCOMPARE(bad->status, 422);
    QVERIFY(!body_of(bad)["errors"].empty());
    QCOMPARE(client_->Post("/pallet/random", R"({"wrap": "cling"})", kJson)->status, 422);
    QCOMPARE(client_->Post("/pallet/random", "", kJson)->status, 200);  // every default
  }

  void validate_and_mjcf() {
    const std::string pallet = pallet_of(*client_, "stable-dairy-slab");
    QCOMPARE(client_->Post("/pallet/validate", pallet, kJson)->status, 200);
    Json broken = Json::parse(pallet);
    broken["items"][0]["dims_m"][2] = -0.1;
    auto refused = client_->Post("/pallet/validate", broken.dump(), kJson);
    QCOMPARE(refused->status, 422);
    QCOMPARE(body_of(refused)["errors"][0]["pointer"], "/items/0/dims_m/2");
    const Json report = body_of(client_->Post("/v1/validate", broken.dump(), kJson));
    QCOMPARE(report["valid"], false);
    // An invalid pallet's report keeps its warnings, as the CLI's does (a stale stored height),
    // and its metrics, wrapped or not.
    broken["stack_height_m"] = 0.1;
    for (const Json& body : {broken, Json{{"pallet", broken}}}) {
      const Json warned = body_of(client_->Post("/v1/validate", body.dump(), kJson));
      QCOMPARE(warned["valid"], false);
      const Json& warnings = warned["warnings"];
      QVERIFY2(std::any_of(warnings.begin(), warnings.end(),
                           [](const Json& w) {
                             return w["pointer"].get<std::string>().ends_with("/stack_height_m");
                           }),
               warned.dump().c_str());
      QVERIFY(warned.contains("total_mass_kg"));
    }
    // Valid is what an analysis will not refuse: no friction data for a plastic pallet on steel.
    Json unmodelled = Json::parse(pallet);
    unmodelled["base_pallet_type"] = "CHEP";
    unmodelled["belt_surface"] = "steel_roller";
    for (const char* route : {"/pallet/validate", "/safety/analyze"}) {
      auto no_friction = client_->Post(route, unmodelled.dump(), kJson);
      QCOMPARE(no_friction->status, 422);
      QCOMPARE(body_of(no_friction)["errors"][0]["pointer"], "/belt_surface");
    }
    QCOMPARE(body_of(client_->Post("/v1/validate", unmodelled.dump(), kJson))["valid"], false);
    // Wrapped as the /v1 routes and the CLI take it ({"pallet": ...}), too.
    const std::string wrapped = R"({"pallet": )" + pallet + "}";
    QCOMPARE(body_of(client_->Post("/pallet/validate", wrapped, kJson)), Json::parse(pallet));
    Json wrapped_broken = {{"pallet", broken}};
    QCOMPARE(body_of(client_->Post("/pallet/validate", wrapped_broken.dump(),
                                   kJson))["errors"][0]["pointer"],
             "/pallet/items/0/dims_m/2");
    QCOMPARE(client_->Post("/mjcf/build", wrapped, kJson)->status, 200);
    const Json mjcf = body_of(client_->Post("/mjcf/build", pallet, kJson));
    QVERIFY(mjcf["mjcf_xml"].get<std::string>().starts_with("<mujoco"));
    QCOMPARE(mjcf["bytes"].get<std::size_t>(), mjcf["mjcf_xml"].get<std::string>().size());
  }

  // The post: POST /solve {pallet: tower, profile: a 1.8 m curve at 2 m/s, include_replay}
  // -> failure {"mode": "top_item_slide", "time_s": 1.003, "items": [7]}.
  void solve_as_the_post_shows() {
    const std::string pallet = pallet_of(*client_, "tall-unwrapped-tower");
    const std::string req =
        R"({"pallet": )" + pallet +
        R"(, "profile": {"shape": "curve", "target_speed_mps": 2.0, "curve_radius_m": 1.8,
            "duration_s": 2.2}, "include_replay": true})";
    auto res = client_->Post("/solve", req, kJson);
    QCOMPARE(res->status, 200);
    const Json s = body_of(res);
    QCOMPARE(s["failure"]["mode"], "top_item_slide");
    QVERIFY(s["failure"]["time_s"].get<double>() > 0.1 &&
            s["failure"]["time_s"].get<double>() < 1.5);
    const Json& r = s["replay"];
    const std::size_t frames = r["times_s"].size();
    QVERIFY(frames > 5);
    for (const char* key :
         {"belt_disp_m", "pallet_pos_m", "pallet_quat_wxyz", "item_pos_m", "item_quat_wxyz"}) {
      QCOMPARE(r[key].size(), frames);
    }
    QCOMPARE(r["items"].size(), Json::parse(pallet)["items"].size());
    QCOMPARE(r["item_pos_m"][0].size(), r["items"].size());
    QCOMPARE(r["pallet_quat_wxyz"][0].size(), 4u);
    QCOMPARE(s["trace"]["times_s"].size(), frames);
    // Without include_replay: no replay, the same verdict.
    Json plain = Json::parse(req);
    plain["include_replay"] = false;
    const Json p = body_of(client_->Post("/solve", plain.dump(), kJson));
    QVERIFY(p["replay"].is_null());
    QCOMPARE(p["failure"], s["failure"]);
    plain["include_replay"] = "yes";  // not a boolean: refused, not a 500
    QCOMPARE(client_->Post("/solve", plain.dump(), kJson)->status, 422);
    plain["include_replay"] = false;
    // Thresholds other than the service's are refused, not ignored.
    plain["thresholds"] = {{"tip_angle_deg", 20.0}};
    QCOMPARE(client_->Post("/solve", plain.dump(), kJson)->status, 422);
    plain.erase("thresholds");
    plain["profile"]["accel_mps2"] = 50.0;
    auto bad = client_->Post("/solve", plain.dump(), kJson);
    QCOMPARE(bad->status, 422);
    QCOMPARE(body_of(bad)["errors"][0]["pointer"], "/profile/accel_mps2");
  }

  // A load that rides its belt's ramp is jumped over by the simulation (co-moving skip), and the
  // trace still shows the ramp: the conveyor's velocity is a t at every frame, the pallet's
  // matches it and the replay's belt travel is a t^2 / 2 (across one jump they were a held value,
  // a mean and a straight line: the pallet outran its belt).
  void aRideTheSimulationJumpsIsTracedAsTheRamp() {
    const std::string pallet = pallet_of(*client_, "stable-dairy-slab");
    const double a = 2.0, v = 1.0;
    const std::string req = R"({"pallet": )" + pallet +
                            R"(, "profile": {"shape": "accel_hold", "target_speed_mps": 1.0,
            "accel_mps2": 2.0}, "include_replay": true})";
    const Json s = body_of(client_->Post("/solve", req, kJson));
    QCOMPARE(s["outcome"], "safe");
    const Json& t = s["trace"];
    const Json& r = s["replay"];
    QVERIFY(s["n_steps_simulated"].get<double>() < 0.5 * t["times_s"].back().get<double>() / 1e-3);
    for (std::size_t k = 0; k < t["times_s"].size(); ++k) {
      const double time = t["times_s"][k], conveyor = t["conveyor_vel_mps"][k];
      const double ramp = std::min(v, a * time);
      QVERIFY2(std::abs(conveyor - ramp) < 0.01 + 2.0 * a * 2e-3,
               qPrintable(QString("t %1: conveyor %2").arg(time).arg(conveyor)));
      QVERIFY2(
          std::abs(t["pallet_vel_x_mps"][k].get<double>() - conveyor) < 0.05,
          qPrintable(
              QString("t %1: pallet %2").arg(time).arg(t["pallet_vel_x_mps"][k].get<double>())));
      const double travel = time <= v / a ? 0.5 * a * time * time : v * (time - 0.5 * v / a);
      QVERIFY2(
          std::abs(r["belt_disp_m"][k].get<double>() - travel) < 0.005,
          qPrintable(QString("t %1: belt %2").arg(time).arg(r["belt_disp_m"][k].get<double>())));
    }
  }

  // The post: POST /safety/analyze (a pallet) | jq .result; POST /safety/batch [P, P] ->
  // sims_run [n, 0]. The answer is the core's, as an Analyzer in this process gives it.
  void analyze_and_batch_share_the_cache() {
    const std::string pallet = pallet_of(*client_, "top-heavy-surprise");
    auto res = client_->Post("/safety/analyze", pallet, kJson);
    QCOMPARE(res->status, 200);
    const Json a = body_of(res);
    for (const char* key : {"result", "sims_run", "cache_hits", "sweep_points"})
      QVERIFY(a.contains(key));
    QVERIFY(a["sims_run"].get<int>() > 0);
    QCOMPARE(a["cache_hits"].get<int>(), 0);
    pb::Analyzer analyzer;
    const auto scenario = pb::load_scenario("top-heavy-surprise");
    auto direct = analyzer.analyze(scenario->pallet);
    QVERIFY(direct.ok());
    QCOMPARE(a["result"]["max_accel_mps2"].get<double>(), direct->max_accel_mps2);
    QCOMPARE(a["result"]["max_decel_mps2"].get<double>(), direct->max_decel_mps2);
    QCOMPARE(a["result"]["max_lateral_g"].get<double>(), direct->max_lateral_g);
    QCOMPARE(a["result"]["max_speed_mps"].get<double>(), direct->max_speed_mps);
    QCOMPARE(a["result"]["dominant_failure_mode"].get<std::string>(),
             std::string(pb::to_string(direct->dominant_failure_mode)));
    const Json batch =
        body_of(client_->Post("/safety/batch", "[" + pallet + "," + pallet + "]", kJson));
    QCOMPARE(batch.size(), 2u);
    QCOMPARE(batch[0]["sims_run"].get<int>(), 0);  // analysed above: cached
    QCOMPARE(batch[1]["cache_hits"].get<int>(), 1);
    QCOMPARE(batch[0]["result"]["max_accel_mps2"], a["result"]["max_accel_mps2"]);
    QCOMPARE(batch[0]["sweep_points"], a["sweep_points"]);
    // The cache holds the load's envelope; each answer names the pallet asked about.
    Json renamed = Json::parse(pallet);
    renamed["pallet_id"] = "ANOTHER-PALLET-7";
    const Json again = body_of(client_->Post("/safety/analyze", renamed.dump(), kJson));
    QCOMPARE(again["cache_hits"].get<int>(), 1);
    QCOMPARE(again["result"]["pallet_id"], "ANOTHER-PALLET-7");
    QCOMPARE(again["result"]["max_accel_mps2"], a["result"]["max_accel_mps2"]);
    const Json both =
        body_of(client_->Post("/safety/batch", "[" + renamed.dump() + "," + pallet + "]", kJson));
    QCOMPARE(both[0]["result"]["pallet_id"], "ANOTHER-PALLET-7");
    QCOMPARE(both[1]["result"]["pallet_id"], Json::parse(pallet)["pallet_id"]);
    // One invalid pallet refuses the batch, pointing into the list.
    Json broken = Json::parse(pallet);
    broken["items"][0]["weight_kg"] = -1;
    auto refused = client_->Post("/safety/batch", "[" + pallet + "," + broken.dump() + "]", kJson);
    QCOMPARE(refused->status, 422);
    QCOMPARE(body_of(refused)["errors"][0]["pointer"], "/1/items/0/weight_kg");
  }

  void ours_under_v1() {
    const std::string pallet = pallet_of(*client_, "top-heavy-surprise");
    const Json a = body_of(client_->Post("/v1/analyze", pallet, kJson));
    for (const char* axis : {"accel", "decel", "lateral", "speed"})
      QVERIFY(a["axes"].contains(axis));
    QVERIFY(!a["probes"].empty());
    // The range the limits were searched in, as the console's dials span it.
    QCOMPARE(a["line"]["range"]["speed_mps"], Json({0.1, 2.0}));
    QCOMPARE(a["line"]["range"]["accel_mps2"], Json({0.1, 5.0}));
    QVERIFY(a["result"]["max_speed_mps"].get<double>() <= 2.0);
    QVERIFY(!a["explain"]["reason"].get<std::string>().empty());
    QVERIFY(a["explain"]["compared_with"].get<std::string>().find("table") != std::string::npos);
    QCOMPARE(body_of(client_->Post("/v1/explain", pallet, kJson))["grade"], a["explain"]["grade"]);
    // The replay of the failing probe of the tightest axis: a failure just above its limit.
    const Json r = body_of(client_->Post("/v1/replay", pallet, kJson));
    QCOMPARE(r["outcome"], "failed");
    QVERIFY(r["value"].get<double>() > r["limit"].get<double>());
    QVERIFY(r["replay"]["frames"].size() > 2);
    const Json lateral = body_of(
        client_->Post("/v1/replay", R"({"axis": "lateral", "pallet": )" + pallet + "}", kJson));
    QCOMPARE(lateral["axis"], "lateral");
    QCOMPARE(
        client_->Post("/v1/replay", R"({"axis": "up", "pallet": )" + pallet + "}", kJson)->status,
        422);
    // A small map, the uncertainty at an operating point, a solve in our replay format.
    const Json map = body_of(client_->Post(
        "/v1/map", R"({"speeds_mps": [0.5, 1.5], "accels_mps2": [1, 4], "pallet": )" + pallet + "}",
        kJson));
    QCOMPARE(map["cells"].size(), 2u);
    QCOMPARE(map["cells"][0].size(), 2u);
    const std::string op = R"({"profile": {"target_speed_mps": 1, "accel_mps2": 1, "duration_s": 2},
                               "samples": 4, "pallet": )" +
                           pallet + "}";
    const Json u = body_of(client_->Post("/v1/uncertainty", op, kJson));
    QCOMPARE(u["samples"].get<int>(), 4);
    QVERIFY(u["p_fail"].get<double>() >= 0.0 && u["p_fail"].get<double>() <= 1.0);
    const Json s = body_of(client_->Post(
        "/v1/solve",
        R"({"profile": {"target_speed_mps": 1, "accel_mps2": 1}, "pallet": )" + pallet + "}",
        kJson));
    QVERIFY(s["replay"]["frames"].is_array());
    QVERIFY(s.contains("fidelity"));
  }

  void a_load_that_cannot_stand_is_refused_with_the_item_named() {
    Json pallet = Json::parse(pallet_of(*client_, "tall-unwrapped-tower"));
    // The top carton pushed most of the way off what carries it: validation refuses it (422).
    const std::size_t top = pallet["items"].size() - 1;
    pallet["items"][top]["position"][0] = pallet["items"][top]["position"][0].get<double>() + 0.25;
    auto res = client_->Post("/safety/analyze", pallet.dump(), kJson);
    QCOMPARE(res->status, 422);
    QVERIFY(body_of(res)["errors"][0]["pointer"].get<std::string>().starts_with("/items/"));
  }

  // A curve too tight for the pallet (its centre would lie under the pallet) is the profile's
  // fault, pointed at in the request's own profile, not inside the pallet.
  void a_curve_tighter_than_the_pallet_is_refused_at_the_profile() {
    const std::string pallet = pallet_of(*client_, "stable-dairy-slab");
    auto res = client_->Post("/v1/solve",
                             R"({"profile": {"shape": "curve", "target_speed_mps": 1,
                                 "curve_radius_m": 0.35}, "pallet": )" +
                                 pallet + "}",
                             kJson);
    QCOMPARE(res->status, 422);
    const Json error = body_of(res)["errors"][0];
    QCOMPARE(error["pointer"].get<std::string>(), std::string("/profile/curve_radius_m"));
    QVERIFY(error["message"].get<std::string>().find("more than 0.4 m") != std::string::npos);
  }

  // A service whose own line is too tight for a pallet (--curve-radius) says so at the whole
  // request, naming its setting, and its validation says what its analysis would; a run of a
  // straight profile, which takes no curve, still runs.
  void a_service_line_too_tight_for_the_pallet_is_named() {
    ServerProcess tight(QStringList{"--curve-radius", "0.3"});
    QVERIFY2(tight.port() > 0, "the server did not start");
    auto client = tight.client();
    const std::string pallet = pallet_of(*client, "stable-dairy-slab");
    for (const char* route : {"/v1/analyze", "/safety/analyze", "/pallet/validate"}) {
      auto res = client->Post(route, pallet, kJson);
      QCOMPARE(res->status, 422);
      const Json error = body_of(res)["errors"][0];
      QCOMPARE(error["pointer"].get<std::string>(), std::string());
      QVERIFY2(error["message"].get<std::string>().find("--curve-radius") != std::string::npos &&
                   error["message"].get<std::string>().find("more than 0.4 m") != std::string::npos,
               res->body.c_str());
    }
    const Json report = body_of(client->Post("/v1/validate", pallet, kJson));
    QCOMPARE(report["valid"], false);
    QCOMPARE(report["errors"].size(), 1u);
    auto straight = post_wrapped(*client, "/v1/solve",
                                 R"("profile": {"target_speed_mps": 1, "accel_mps2": 1})", pallet);
    QCOMPARE(straight->status, 200);
  }

  void bad_requests() {
    auto not_json = client_->Post("/safety/analyze", "{pallet", kJson);
    QCOMPARE(not_json->status, 400);
    QVERIFY(body_of(not_json)["detail"].get<std::string>().find("not valid JSON") !=
            std::string::npos);
    QCOMPARE(client_->Post("/safety/analyze", "", kJson)->status, 400);
    QCOMPARE(client_->Post("/safety/analyze", "[1, 2]", kJson)->status, 422);
    QCOMPARE(client_->Post("/safety/analyze", "42", kJson)->status, 422);
    QCOMPARE(client_->Post("/safety/batch", "{}", kJson)->status, 422);
    // Deep nesting is read without recursion and refused as a pallet.
    QCOMPARE(
        client_->Post("/safety/analyze", std::string(20000, '[') + std::string(20000, ']'), kJson)
            ->status,
        422);
    // Over the body limit (--max-body 200000): 413 with the limit named.
    auto big = client_->Post("/safety/analyze", std::string(300000, ' '), kJson);
    QCOMPARE(big->status, 413);
    QVERIFY(body_of(big)["detail"].get<std::string>().find("200000") != std::string::npos);
    // Sent in chunks, with no length: the same limit (cpp-httplib 0.11 read such a body whole).
    auto chunks = [](std::string body) {
      return [body = std::move(body)](std::size_t offset, httplib::DataSink& sink) {
        if (offset < body.size()) {
          sink.write(body.data() + offset, std::min<std::size_t>(65536, body.size() - offset));
        } else {
          sink.done();
        }
        return true;
      };
    };
    auto chunked = client_->Post("/safety/analyze", chunks(std::string(300000, ' ')), kJson);
    QVERIFY(chunked);
    QCOMPARE(chunked->status, 413);
    QVERIFY(body_of(chunked)["detail"].get<std::string>().find("200000") != std::string::npos);
    auto small =
        client_->Post("/v1/validate", chunks(pallet_of(*client_, "stable-dairy-slab")), kJson);
    QVERIFY(small);
    QCOMPARE(small->status, 200);
    // Over the item limit: 413 before any work.
    Json pallet = Json::parse(pallet_of(*client_, "stable-dairy-slab"));
    Json many = Json::array();
    for (int i = 0; i < 401; ++i) many.push_back(pallet["items"][0]);
    pallet["items"] = many;
    auto crowded = client_->Post("/safety/analyze", pallet.dump(), kJson);
    QCOMPARE(crowded->status, 413);
    QVERIFY(body_of(crowded)["detail"].get<std::string>().find("400") != std::string::npos);
    QCOMPARE(client_->Get("/no/such/route")->status, 404);
    auto wrong_method = client_->Get("/safety/analyze");
    QCOMPARE(wrong_method->status, 405);
    QCOMPARE(wrong_method->get_header_value("Allow"), "POST");
    QCOMPARE(body_of(client_->Get("/healthz"))["status"], "ok");  // still serving
  }

  // A body's framing that cannot be trusted is refused at once, before the body is read: a length
  // that is not a number (cpp-httplib read "-5" as 2^64 - 5 and waited 30 s for it, "abc" as no
  // body), two different lengths (it took the first: a request smuggled past a proxy that takes
  // the other), both a length and chunks, a length far past the limit.
  void framingThatCannotBeTrustedIsRefused() {
    const std::string head =
        "POST /v1/validate HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n";
    const std::pair<const char*, int> cases[] = {
        {"Content-Length: -5\r\n", 400},
        {"Content-Length: abc\r\n", 400},
        {"Content-Length: \xff\xfe\r\n", 400},  // not UTF-8: the reply's JSON still is
        {"Content-Length: 99999999999999999999\r\n", 400},
        {"Content-Length: 7\r\nContent-Length: 9\r\n", 400},
        {"Content-Length: 7\r\nTransfer-Encoding: chunked\r\n", 400},
        {"Content-Length: 9000000000\r\n", 413},
        {"Content-Length: 7\r\nContent-Length: 7\r\n", 200},
    };
    for (const auto& [headers, status] : cases) {
      const std::string reply = raw_exchange(server_->port(), head + headers + "\r\n{\"a\":1}");
      QVERIFY2(reply.starts_with("HTTP/1.1 " + std::to_string(status)),
               qPrintable(QString::fromStdString(headers + std::string(" -> ") + reply)));
      const Json body = Json::parse(reply.substr(reply.find("\r\n\r\n") + 4));
      if (status != 200) QVERIFY(!body["errors"][0]["message"].get<std::string>().empty());
    }
    QCOMPARE(body_of(client_->Get("/healthz"))["status"], "ok");  // still serving
    // Refused before the service saw them, they are counted all the same, under their route.
    const std::string metrics = client_->Get("/metrics")->body;
    for (const char* line :
         {"palletballet_requests_total{method=\"POST\",route=\"/v1/validate\",status=\"400\"}",
          "palletballet_requests_total{method=\"POST\",route=\"/v1/validate\",status=\"413\"}"}) {
      QVERIFY2(metrics.find(line) != std::string::npos, line);
    }
  }

  // A request that declares no body (neither Content-Length nor Transfer-Encoding) has none
  // (RFC 9112 6.3) and is answered at once: cpp-httplib read one until the client closed or 30 s
  // passed, holding a connection thread, so eighty of them stalled the service for 34 s (and
  // raw_exchange, which waits 10 s, got no reply).
  void aRequestWithoutALengthHasNoBody() {
    const std::pair<const char*, int> cases[] = {
        {"POST /safety/analyze", 400},  // no body: say so
        {"PUT /healthz", 405},          // the wrong method: say which
        {"DELETE /v1/validate", 405},
        {"PATCH /v1/analyze", 405},
    };
    for (const auto& [line, status] : cases) {
      const std::string reply = raw_exchange(
          server_->port(),
          std::string(line) + " HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n\r\n");
      QVERIFY2(reply.starts_with("HTTP/1.1 " + std::to_string(status)),
               qPrintable(QString::fromStdString(std::string(line) + " -> " + reply)));
      const Json body = Json::parse(reply.substr(reply.find("\r\n\r\n") + 4));
      QVERIFY(!body["errors"][0]["message"].get<std::string>().empty());
    }
    QCOMPARE(body_of(client_->Get("/healthz"))["status"], "ok");  // still serving
  }

  // Whatever refuses a request, "errors" says why: a client reading only it never finds [].
  void every_refusal_lists_its_error() {
    std::vector<httplib::Result> refusals;
    refusals.push_back(client_->Get("/no/such/route"));
    refusals.push_back(client_->Get("/v1/analyze"));
    refusals.push_back(client_->Get("/friction?temp_c=hot"));
    refusals.push_back(client_->Get("/catalog/skus/NOPE"));
    refusals.push_back(client_->Post("/safety/analyze", std::string(300000, ' '), kJson));
    for (const auto& res : refusals) {
      QVERIFY(res && res->status >= 400);
      const Json body = body_of(res);
      QVERIFY2(!body["errors"].empty(), res->body.c_str());
      QCOMPARE(body["errors"][0]["message"], body["detail"]);
    }
  }

  // "detail" is for people: many items with one problem are told once there after the first
  // three; "errors" lists every one with its pointer.
  void many_items_with_one_problem_are_told_once_in_the_detail() {
    Json pallet = Json::parse(pallet_of(*client_, "stable-dairy-slab"));
    const std::size_t n = pallet["items"].size();
    for (std::size_t i = 0; i < n; ++i) pallet["items"][i]["weight_kg"] = -1.0 - double(i);
    auto res = client_->Post("/safety/analyze", pallet.dump(), kJson);
    QVERIFY(res);
    QCOMPARE(res->status, 422);
    const Json body = body_of(res);
    QCOMPARE(body["errors"].size(), n);
    const std::string detail = body["detail"];
    QVERIFY2(detail.find("/items/2/weight_kg: ") != std::string::npos &&
                 detail.find("/items/3/weight_kg: ") == std::string::npos &&
                 detail.find("/items/*/weight_kg: the same for " + std::to_string(n - 3) +
                             " more items: 3-" + std::to_string(n - 1)) != std::string::npos,
             detail.c_str());
  }

  // A /v1/ request wrapping its pallet names only the members its route reads: a misspelt one,
  // or a line (the service's own), would otherwise be ignored and the answer computed without it.
  void unknown_members_of_a_v1_request_are_refused() {
    const std::string pallet = pallet_of(*client_, "stable-dairy-slab");
    const std::string profile = R"("profile": {"target_speed_mps": 1, "accel_mps2": 1})";
    auto typo = post_wrapped(*client_, "/v1/uncertainty", profile + R"(, "sample": 4)", pallet);
    QCOMPARE(typo->status, 422);
    QCOMPARE(body_of(typo)["errors"][0]["pointer"], "/sample");
    QVERIFY(body_of(typo)["detail"].get<std::string>().find("'samples'") != std::string::npos);
    auto line = post_wrapped(*client_, "/v1/analyze", R"("line": {"estop_decel_mps2": 4})", pallet);
    QCOMPARE(line->status, 422);
    QCOMPARE(body_of(line)["errors"][0]["pointer"], "/line");
    QVERIFY(body_of(line)["detail"].get<std::string>().find("--estop-decel") != std::string::npos);
    for (const char* route :
         {"/v1/explain", "/v1/validate", "/v1/map", "/v1/replay", "/v1/solve"}) {
      auto res = post_wrapped(*client_, route, R"("bogus": 1)", pallet);
      QCOMPARE(res->status, 422);
      QCOMPARE(body_of(res)["errors"][0]["pointer"], "/bogus");
    }
    // The reference API's routes ignore extra members, as its clients expect.
    QCOMPARE(post_wrapped(*client_, "/solve", R"("bogus": 1)", pallet)->status, 200);
  }

  // A /v1/ profile is required and holds only a profile's members: "speed_mps" for
  // "target_speed_mps" ran the default 0.5 m/s and answered safe for a profile nobody sent. What
  // reading the pallet found is among /v1/solve's warnings, as /v1/analyze lists it.
  void a_v1_profile_is_required_and_strict() {
    const std::string pallet = pallet_of(*client_, "stable-dairy-slab");
    for (const char* route : {"/v1/solve", "/v1/uncertainty"}) {
      auto typo = post_wrapped(*client_, route, R"("profile": {"speed_mps": 2})", pallet);
      QCOMPARE(typo->status, 422);
      QCOMPARE(body_of(typo)["errors"][0]["pointer"], "/profile/speed_mps");
      auto none = post_wrapped(*client_, route, R"("samples": 2)", pallet);
      QCOMPARE(none->status, 422);
    }
    auto none = post_wrapped(*client_, "/v1/solve", R"("hz": 10)", pallet);
    QCOMPARE(none->status, 422);
    QCOMPARE(body_of(none)["errors"][0]["pointer"], "/profile");
    // The reference's route keeps its clients' leniency: the default profile, the typo warned.
    auto lenient = post_wrapped(*client_, "/solve", R"("profile": {"speed_mps": 2})", pallet);
    QCOMPARE(lenient->status, 200);
    Json extra = Json::parse(pallet);
    extra["bogus_key"] = 1;
    const Json s = body_of(post_wrapped(*client_, "/v1/solve",
                                        R"("profile": {"target_speed_mps": 1, "accel_mps2": 1})",
                                        extra.dump()));
    bool warned = false;
    for (const Json& w : s["warnings"]) warned = warned || w["pointer"] == "/pallet/bogus_key";
    QVERIFY2(warned, s["warnings"].dump().c_str());
  }

  // A request with a bad pallet and a bad profile (or grid) is refused with both, so the client
  // fixes them at once.
  void every_bad_member_of_a_request_is_named_at_once() {
    Json bad = Json::parse(pallet_of(*client_, "stable-dairy-slab"));
    bad["items"][0]["weight_kg"] = -1.0;
    const std::string pallet = bad.dump();
    auto pointers = [](const httplib::Result& res) {
      std::vector<std::string> out;
      const Json body = body_of(res);
      for (const Json& e : body["errors"]) out.push_back(e["pointer"]);
      return out;
    };
    using Pointers = std::vector<std::string>;
    for (const char* route : {"/solve", "/v1/solve", "/v1/uncertainty"}) {
      auto res = post_wrapped(*client_, route, R"("profile": {"target_speed_mps": -3})", pallet);
      QCOMPARE(res->status, 422);
      QCOMPARE(pointers(res), Pointers({"/pallet/items/0/weight_kg", "/profile/target_speed_mps"}));
      const std::string detail = body_of(res)["detail"];
      QVERIFY2(detail.find("weight_kg") != std::string::npos &&
                   detail.find("target_speed_mps") != std::string::npos,
               detail.c_str());
    }
    auto map = post_wrapped(*client_, "/v1/map",
                            R"("speeds_mps": [], "accels_mps2": [1, "x", null])", pallet);
    QCOMPARE(map->status, 422);
    QCOMPARE(pointers(map), Pointers({"/pallet/items/0/weight_kg", "/speeds_mps", "/accels_mps2/1",
                                      "/accels_mps2/2"}));
  }

  // A count is a whole number (2.5 samples was run as 2); a grid that is there holds numbers; a
  // body a web page may POST to any origin without asking (text/plain, a form), or one that says
  // it is not JSON, is refused (415).
  void counts_grids_and_content_types_are_checked() {
    const std::string pallet = pallet_of(*client_, "stable-dairy-slab");
    const std::string profile = R"("profile": {"target_speed_mps": 1, "accel_mps2": 1})";
    auto half = post_wrapped(*client_, "/v1/uncertainty", profile + R"(, "samples": 2.5)", pallet);
    QCOMPARE(half->status, 422);
    QCOMPARE(body_of(half)["errors"][0]["pointer"], "/samples");
    auto empty = post_wrapped(*client_, "/v1/map", R"("speeds_mps": [])", pallet);
    QCOMPARE(empty->status, 422);
    QCOMPARE(body_of(empty)["errors"][0]["pointer"], "/speeds_mps");
    auto word = post_wrapped(*client_, "/v1/map", R"("speeds_mps": [1, "x"])", pallet);
    QCOMPARE(word->status, 422);
    QCOMPARE(body_of(word)["errors"][0]["pointer"], "/speeds_mps/1");
    // Every bad member of both grids at once: the word, and the numbers out of range or order.
    auto several = post_wrapped(
        *client_, "/v1/map", R"("speeds_mps": [-1, "a", 2, 1.5], "accels_mps2": [1e308])", pallet);
    QCOMPARE(several->status, 422);
    const Json refused = body_of(several);
    std::set<std::string> named;
    for (const Json& e : refused["errors"]) named.insert(e["pointer"].get<std::string>());
    const std::set<std::string> all{"/speeds_mps/0", "/speeds_mps/1", "/speeds_mps/3",
                                    "/accels_mps2/0"};
    QVERIFY2(named == all, refused.dump().c_str());
    QCOMPARE(client_->Get("/friction/curve?pair=carton/carton&n=2.7")->status, 422);
    // A query parameter the route does not read (a misspelt one would leave its default in
    // force), or one given twice, is refused with its name.
    auto misspelt = client_->Get("/friction/curve?pair=carton/carton&count=5");
    QCOMPARE(misspelt->status, 422);
    const std::string why = body_of(misspelt)["detail"];
    QVERIFY2(why.find("'count' is not read by GET /friction/curve") != std::string::npos &&
                 why.find("t_min, t_max, n") != std::string::npos,
             why.c_str());
    auto twice = client_->Get("/friction?temp_c=-20&temp_c=5");
    QCOMPARE(twice->status, 422);
    QVERIFY(body_of(twice)["detail"].get<std::string>().find("'temp_c' is given 2 times") !=
            std::string::npos);
    QVERIFY(!body_of(twice)["errors"].empty());
    auto none = client_->Get("/healthz?verbose=1");
    QCOMPARE(none->status, 422);
    QVERIFY(body_of(none)["detail"].get<std::string>().find("it takes none") != std::string::npos);
    for (const char* type : {"text/plain", "application/x-www-form-urlencoded; charset=utf-8",
                             "application/xml", "text/html"}) {
      auto form = client_->Post("/v1/validate", pallet, type);
      QCOMPARE(form->status, 415);
      QVERIFY(body_of(form)["detail"].get<std::string>().find("application/json") !=
              std::string::npos);
    }
    // JSON by any of its names, parameters and case aside, is read.
    for (const char* type : {"Application/JSON; charset=utf-8", "application/vnd.pallet+json"}) {
      QCOMPARE(client_->Post("/v1/validate", pallet, type)->status, 200);
    }
    // A file upload (curl -F): the HTTP layer drops its parts, and it is still a 415.
    const httplib::MultipartFormDataItems upload{{"a", pallet, "pallet.json", "application/json"}};
    auto multipart = client_->Post("/safety/analyze", upload);
    QCOMPARE(multipart->status, 415);
    QVERIFY(body_of(multipart)["detail"].get<std::string>().find("multipart/form-data") !=
            std::string::npos);
  }

  void cors_follows_the_allowlist() {
    httplib::Headers allowed{{"Origin", "https://boothe.io"}};
    auto yes = client_->Get("/healthz", allowed);
    QCOMPARE(yes->get_header_value("Access-Control-Allow-Origin"), "https://boothe.io");
    httplib::Headers other{{"Origin", "https://evil.example"}};
    QVERIFY(!client_->Get("/healthz", other)->has_header("Access-Control-Allow-Origin"));
    auto preflight = client_->Options("/safety/analyze", allowed);
    QCOMPARE(preflight->status, 204);
    QCOMPARE(preflight->get_header_value("Access-Control-Allow-Methods"), "POST, OPTIONS");
    // No content: no body, and no content type claiming JSON for it.
    QVERIFY(preflight->body.empty());
    QVERIFY(!preflight->has_header("Content-Type"));
    QCOMPARE(preflight->get_header_value("Access-Control-Allow-Origin"), "https://boothe.io");
    QCOMPARE(client_->Options("/scenarios/stable-dairy-slab", allowed)
                 ->get_header_value("Access-Control-Allow-Methods"),
             "GET, OPTIONS");
    // A path with no route is not found, preflight or not.
    auto nowhere = client_->Options("/no/such/route", allowed);
    QCOMPARE(nowhere->status, 404);
    QVERIFY(!body_of(nowhere)["errors"].empty());
  }

 private:
  std::unique_ptr<ServerProcess> server_;
  std::unique_ptr<httplib::Client> client_;
};

QTEST_APPLESS_MAIN(ServiceRoutesTest)
#include "service_routes_test.moc"
