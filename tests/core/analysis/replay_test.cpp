// SPDX-License-Identifier: MIT
// Replay: 30 Hz resampling of a 2 ms trace, the compact JSON form and every reading error.
#include "core/analysis/replay.hpp"

#include <QtTest>

#include <cmath>
#include <numbers>

using namespace pb;

namespace {

Quat yaw(double deg) {
  const double half = deg * std::numbers::pi / 360.0;
  return {std::cos(half), 0.0, 0.0, std::sin(half)};
}

PalletConfig pallet(int n_items) {
  PalletConfig config;
  config.pallet_id = "R-1";
  for (int i = 0; i < n_items; ++i) {
    Item item;
    item.sku = "SKU-" + std::to_string(i);
    item.position = {-0.4 + 0.4 * (i % 3), 0.0, 0.15 + 0.2 * (i / 3)};
    config.items.push_back(item);
  }
  return config;
}

// The synthetic motion, in closed form: the belt and pallet accelerate at 0.5 m/s^2 (x = t^2 / 4),
// the pallet yaws at 30 deg/s, item i rises at 1 m/s from z = 0.3 + i.
double belt_x(double t) {
  return 0.25 * t * t;
}
Pose pallet_at(double t) {
  return {{0.25 * t * t, 0.0, 0.075}, yaw(30.0 * t)};
}
Pose item_at(int i, double t) {
  return {{static_cast<double>(i), 0.0, 0.3 + i + t}, yaw(30.0 * t)};
}

// Frames every 2 ms: t = f / 500 for f in [0, last_frame].
Trace trace_2ms(int last_frame, int n_items = 3) {
  Trace trace(n_items);
  for (int f = 0; f <= last_frame; ++f) {
    const double t = f / 500.0;
    std::vector<Pose> items;
    for (int i = 0; i < n_items; ++i) items.push_back(item_at(i, t));
    trace.push(t, {belt_x(t), 0.01 * t, 0.5 * t, 0.01}, pallet_at(t), items);
  }
  return trace;
}

bool near(double a, double b, double tol = 1e-12) {
  return std::abs(a - b) <= tol;
}

const FailureEvent kFailure{FailureMode::load_shift, 0.502, 0.0213, {0, 2}};

Replay sample_replay() {
  return make_replay(trace_2ms(251), pallet(3), ConveyorProfile{}, "failed", kFailure);
}

Json sample_json() {
  return replay_to_json(sample_replay());
}

QString pointers(const Diagnostics& diagnostics) {
  QStringList out;
  for (const auto& d : errors_of(diagnostics)) out << QString::fromStdString(d.pointer);
  return out.join(' ');
}

}  // namespace

class ReplayTest : public QObject {
  Q_OBJECT

 private slots:
  // The pallet as built: one frame at t = 0, box centres where the configuration puts the items,
  // turned by their yaw; it writes and reads back like any replay.
  void asBuiltReplayIsThePalletAtRest() {
    PalletConfig c = pallet(2);
    c.items[1].orientation_deg = 90.0;
    const Replay r = as_built_replay(c);
    QCOMPARE(r.frames.size(), std::size_t(1));
    const ReplayFrame& f = r.frames[0];
    QCOMPARE(f.t, 0.0);
    QCOMPARE(f.pallet.pos[2], c.base_dims_m[2] / 2);
    QCOMPARE(f.items.size(), c.items.size());
    for (std::size_t i = 0; i < c.items.size(); ++i) {
      QCOMPARE(f.items[i].pos[0], c.items[i].position[0]);
      QCOMPARE(f.items[i].pos[2], c.items[i].position[2] + c.items[i].dims_m[2] / 2);
    }
    // 90 degrees about Z: the item's X axis along the world's Y.
    const Vec3 x = rotate(f.items[1].quat, {1.0, 0.0, 0.0});
    QVERIFY(std::abs(x[0]) < 1e-12 && std::abs(x[1] - 1.0) < 1e-12);
    QCOMPARE(r.outcome, std::string("safe"));
    QVERIFY(replay_from_json(replay_to_json(r)));
  }

  void samplesAt30HzThroughTheLastFrame() {
    // 0 .. 0.502 s: grid frames k / 30 for k = 0..15 (0.5 s), then the last trace frame.
    const Trace trace = trace_2ms(251);
    const Replay replay = make_replay(trace, pallet(3), {}, "failed", kFailure);
    QCOMPARE(replay.frames.size(), std::size_t{17});
    for (int k = 0; k <= 15; ++k) QCOMPARE(replay.frames[k].t, k / 30.0);
    QCOMPARE(replay.frames.back().t, 251 / 500.0);
    QCOMPARE(replay.hz, 30.0);
    QCOMPARE(replay.outcome, std::string("failed"));
    QVERIFY(replay.failure == kFailure);
    QVERIFY(replay.pallet == pallet(3));
  }

  void gridFramesOnTraceFramesAreExact() {
    const Trace trace = trace_2ms(251);
    const Replay replay = make_replay(trace, pallet(3), {}, "safe", std::nullopt);
    QVERIFY(replay.frames[0].pallet == trace.pallet(0));
    // 0.5 s is trace frame 250.
    QVERIFY(replay.frames[15].pallet == trace.pallet(250));
    QVERIFY(replay.frames.back().pallet == trace.pallet(251));
    QVERIFY(replay.frames.back().items[2] == trace.items(251)[2]);
    QCOMPARE(replay.frames.back().belt_x, trace.belt(251).x);
  }

  void framesBetweenTraceFramesAreInterpolated() {
    const Trace trace = trace_2ms(251);
    const Replay replay = make_replay(trace, pallet(3), {}, "safe", std::nullopt);
    // t = 1/30 s lies between trace frames 16 (0.032 s) and 17 (0.034 s), 2/3 of the way.
    const ReplayFrame& frame = replay.frames[1];
    const double s = (1.0 / 30.0 - 0.032) / 0.002;
    QVERIFY(near(frame.belt_x, belt_x(0.032) + s * (belt_x(0.034) - belt_x(0.032))));
    QVERIFY(frame.belt_x != belt_x(1.0 / 30.0));  // linear, not the exact parabola
    QVERIFY(near(frame.belt_y, 0.01 / 30.0));
    QVERIFY(near(frame.pallet.pos[0], frame.belt_x));
    // Constant-rate yaw: slerp lands on the exact orientation at t.
    for (std::size_t c = 0; c < 4; ++c) QVERIFY(near(frame.pallet.quat[c], yaw(1.0)[c]));
    QCOMPARE(frame.items.size(), std::size_t{3});
    QVERIFY(near(frame.items[2].pos[2], 2.3 + 1.0 / 30.0));
  }

  void lastFrameOnTheGridIsNotRepeated() {
    const Replay replay = make_replay(trace_2ms(250), pallet(3), {}, "safe", std::nullopt);
    QCOMPARE(replay.frames.size(), std::size_t{16});
    QCOMPARE(replay.frames.back().t, 0.5);
  }

  void otherRatesAndEmptyTraces() {
    QCOMPARE(make_replay(trace_2ms(251), pallet(3), {}, "safe", {}, 10.0).frames.size(),
             std::size_t{7});  // 0, 0.1, .. 0.5, 0.502
    QVERIFY(make_replay(Trace(3), pallet(3), {}, "safe", {}).frames.empty());
    QVERIFY(make_replay(trace_2ms(10), pallet(3), {}, "safe", {}, 0.0).frames.empty());
  }

  void traceNotStartingAtZero() {
    // A trace from 0.01 s to 0.104 s: grid frames 1/30, 2/30 and 3/30, then 0.104 s itself.
    Trace trace(0);
    for (int f = 5; f <= 52; ++f) trace.push(f / 500.0, {}, pallet_at(f / 500.0), {});
    const Replay replay = make_replay(trace, pallet(0), {}, "safe", {});
    QCOMPARE(replay.frames.size(), std::size_t{4});
    QCOMPARE(replay.frames[0].t, 1.0 / 30.0);
    QCOMPARE(replay.frames[2].t, 3.0 / 30.0);
    QCOMPARE(replay.frames[3].t, 0.104);
  }

  // The player's cursor between 30 Hz frames: lerp positions, slerp orientations, clamped ends.
  void frameAtInterpolatesBetweenFrames() {
    const Replay replay = sample_replay();
    const ReplayFrame& a = replay.frames[3];
    const ReplayFrame& b = replay.frames[4];
    const double t = a.t + 0.25 * (b.t - a.t);
    const ReplayFrame f = frame_at(replay, t);
    QCOMPARE(f.t, t);
    QVERIFY(near(f.belt_x, a.belt_x + 0.25 * (b.belt_x - a.belt_x)));
    QVERIFY(near(f.items[2].pos[2],
                 a.items[2].pos[2] + 0.25 * (b.items[2].pos[2] - a.items[2].pos[2])));
    // Constant-rate yaw of 30 deg/s: slerp lands on the closed-form orientation at t (a linear
    // blend of the quaternions would not be unit length).
    for (std::size_t c = 0; c < 4; ++c) {
      QVERIFY(near(f.pallet.quat[c], yaw(30.0 * t)[c], 1e-9));
      QVERIFY(near(f.items[1].quat[c], yaw(30.0 * t)[c], 1e-9));
    }
    QVERIFY(frame_at(replay, a.t) == a);
    QVERIFY(frame_at(replay, -1.0) == replay.frames.front());
    QVERIFY(frame_at(replay, 99.0) == replay.frames.back());
    QVERIFY(frame_at(replay, std::nan("")) == replay.frames.front());
    QVERIFY(frame_at(Replay{}, 0.3) == ReplayFrame{});
  }

  void jsonLayout() {
    const Json json = sample_json();
    QCOMPARE(json["schema_version"], Json(1));
    QCOMPARE(json["outcome"], Json("failed"));
    QCOMPARE(json["hz"], Json(30.0));
    QCOMPARE(json["failure"], Json::parse(R"({"mode": "load_shift", "time_s": 0.502,
                                              "value": 0.0213, "items": [0, 2]})"));
    QCOMPARE(json["pallet"]["pallet_id"], Json("R-1"));
    QCOMPARE(json["profile"], profile_to_json(ConveyorProfile{}));
    QCOMPARE(json["frames"].size(), std::size_t{17});
    const Json& frame = json["frames"][15];
    QCOMPARE(frame["t"], Json(0.5));
    // x = 0.0625 m; yaw 15 deg: (cos 7.5, 0, 0, sin 7.5) rounded to 1e-6.
    QCOMPARE(frame["pallet"], Json::parse("[0.0625, 0.0, 0.075, 0.991445, 0.0, 0.0, 0.130526]"));
    QCOMPARE(frame["belt"], Json::parse("[0.0625, 0.005]"));
    QCOMPARE(frame["items"].size(), std::size_t{3});
    QCOMPARE(frame["items"][1][2], Json(1.8));
    QCOMPARE(json.find("safe"), json.end());
    QCOMPARE(replay_to_json(make_replay(trace_2ms(5), pallet(3), {}, "safe", {}))["failure"],
             Json(nullptr));
  }

  void jsonRoundTrip() {
    const Json json = sample_json();
    const auto read = replay_from_json(json);
    QVERIFY2(read, qPrintable(pointers(read.diagnostics)));
    QVERIFY(read.diagnostics.empty());
    QCOMPARE(replay_to_json(*read), json);
    QCOMPARE(read->frames.size(), std::size_t{17});
    QVERIFY(read->failure == kFailure);
    QVERIFY(read->pallet == pallet(3));
    QVERIFY(read->profile == ConveyorProfile{});
    // Rounded to display precision: within 0.005 mm and 5e-7.
    const Replay original = sample_replay();
    QVERIFY(near(read->frames[7].items[1].pos[2], original.frames[7].items[1].pos[2], 5e-6));
    QVERIFY(near(read->frames[7].pallet.quat[3], original.frames[7].pallet.quat[3], 5e-7));
    // Exact: times.
    QCOMPARE(read->frames[7].t, original.frames[7].t);
    // Through text too.
    const auto reparsed = replay_from_json(Json::parse(json.dump()));
    QVERIFY(reparsed);
    QCOMPARE(replay_to_json(*reparsed), json);
  }

  void threeSecondsOf24ItemsIsCompact() {
    const Replay replay = make_replay(trace_2ms(1500, 24), pallet(24), {}, "safe", {});
    QCOMPARE(replay.frames.size(), std::size_t{91});
    const std::size_t bytes = replay_to_json(replay).dump().size();
    QVERIFY2(bytes < 150000, qPrintable(QString::number(bytes)));
  }

  void unknownKeysAreWarnings() {
    Json json = sample_json();
    json["viewer"] = "x";
    json["frames"][3]["color"] = "red";
    const auto read = replay_from_json(json);
    QVERIFY(read);
    QCOMPARE(read.diagnostics.size(), std::size_t{2});
    QCOMPARE(read.diagnostics[0].pointer, std::string("/viewer"));
    QCOMPARE(read.diagnostics[0].severity, Severity::warning);
    QCOMPARE(read.diagnostics[1].pointer, std::string("/frames/3/color"));
  }

  void safeReplayReadsBack() {
    const Json json = replay_to_json(make_replay(trace_2ms(40), pallet(3), {}, "unstable", {}));
    const auto read = replay_from_json(json);
    QVERIFY(read);
    QVERIFY(!read->failure);
    QCOMPARE(read->outcome, std::string("unstable"));
  }

  // Each row breaks the sample document with a JSON Patch (RFC 6902) and names the one error.
  void malformed_data() {
    QTest::addColumn<QString>("patch");
    QTest::addColumn<QString>("pointer");
    const auto row = [](const char* name, const char* patch, const char* pointer) {
      QTest::newRow(name) << QString(patch) << QString(pointer);
    };
    row("not an object", R"({"op": "replace", "path": "", "value": []})", "");
    row("no frames", R"({"op": "remove", "path": "/frames"})", "/frames");
    row("no failure key", R"({"op": "remove", "path": "/failure"})", "/failure");
    row("newer schema", R"({"op": "replace", "path": "/schema_version", "value": 2})",
        "/schema_version");
    row("schema text", R"({"op": "replace", "path": "/schema_version", "value": "1"})",
        "/schema_version");
    row("schema zero", R"({"op": "replace", "path": "/schema_version", "value": 0})",
        "/schema_version");
    row("schema fraction", R"({"op": "replace", "path": "/schema_version", "value": 1.5})",
        "/schema_version");
    row("bad pallet", R"({"op": "replace", "path": "/pallet/items", "value": 3})", "/pallet/items");
    row("bad profile", R"({"op": "replace", "path": "/profile/shape", "value": "zigzag"})",
        "/profile/shape");
    row("unknown outcome", R"({"op": "replace", "path": "/outcome", "value": "exploded"})",
        "/outcome");
    row("outcome not text", R"({"op": "replace", "path": "/outcome", "value": 1})", "/outcome");
    row("failure not object", R"({"op": "replace", "path": "/failure", "value": "x"})", "/failure");
    row("failure mode none", R"({"op": "replace", "path": "/failure/mode", "value": "no_failure"})",
        "/failure/mode");
    row("failure mode missing", R"({"op": "remove", "path": "/failure/mode"})", "/failure/mode");
    row("failure time", R"({"op": "replace", "path": "/failure/time_s", "value": "late"})",
        "/failure/time_s");
    row("failure value", R"({"op": "replace", "path": "/failure/value", "value": null})",
        "/failure/value");
    row("failure items", R"({"op": "replace", "path": "/failure/items", "value": 2})",
        "/failure/items");
    row("failure item type", R"({"op": "replace", "path": "/failure/items/1", "value": 1.5})",
        "/failure/items/1");
    row("failure item negative", R"({"op": "replace", "path": "/failure/items/0", "value": -1})",
        "/failure/items/0");
    row("failure item missing", R"({"op": "replace", "path": "/failure/items/1", "value": 3})",
        "/failure/items/1");
    row("failed without failure", R"({"op": "replace", "path": "/failure", "value": null})",
        "/failure");
    row("safe with failure", R"({"op": "replace", "path": "/outcome", "value": "safe"})",
        "/failure");
    row("hz zero", R"({"op": "replace", "path": "/hz", "value": 0})", "/hz");
    row("hz text", R"({"op": "replace", "path": "/hz", "value": "30"})", "/hz");
    row("frames not array", R"({"op": "replace", "path": "/frames", "value": {}})", "/frames");
    row("frame not object", R"({"op": "replace", "path": "/frames/2", "value": 0.1})", "/frames/2");
    row("frame without t", R"({"op": "remove", "path": "/frames/1/t"})", "/frames/1/t");
    row("t not number", R"({"op": "replace", "path": "/frames/1/t", "value": "0.03"})",
        "/frames/1/t");
    row("belt length", R"({"op": "add", "path": "/frames/1/belt/-", "value": 0})",
        "/frames/1/belt");
    row("belt value", R"({"op": "replace", "path": "/frames/1/belt/1", "value": true})",
        "/frames/1/belt/1");
    row("pallet length", R"({"op": "remove", "path": "/frames/1/pallet/6"})", "/frames/1/pallet");
    row("pallet value", R"({"op": "replace", "path": "/frames/1/pallet/3", "value": null})",
        "/frames/1/pallet/3");
    row("pallet quaternion zero",
        R"({"op": "replace", "path": "/frames/1/pallet", "value": [0, 0, 0, 0, 0, 0, 0]})",
        "/frames/1/pallet");
    row("pallet quaternion long",
        R"({"op": "replace", "path": "/frames/1/pallet", "value": [0, 0, 0, 1.002, 0, 0, 0]})",
        "/frames/1/pallet");
    row("items not array", R"({"op": "replace", "path": "/frames/1/items", "value": "none"})",
        "/frames/1/items");
    row("items count", R"({"op": "remove", "path": "/frames/1/items/2"})", "/frames/1/items");
    row("item length", R"({"op": "replace", "path": "/frames/1/items/2", "value": [1, 2, 3]})",
        "/frames/1/items/2");
    row("item value", R"({"op": "replace", "path": "/frames/1/items/2/6", "value": "z"})",
        "/frames/1/items/2/6");
    row("repeated time", R"({"op": "copy", "from": "/frames/1/t", "path": "/frames/2/t"})",
        "/frames/2/t");
    row("time goes back", R"({"op": "replace", "path": "/frames/16/t", "value": 0.1})",
        "/frames/16/t");
  }
  void malformed() {
    QFETCH(QString, patch);
    QFETCH(QString, pointer);
    const Json json = sample_json().patch(Json::array({Json::parse(patch.toStdString())}));
    const auto read = replay_from_json(json);
    QVERIFY(!read);
    QCOMPARE(pointers(read.diagnostics), pointer);
    for (const auto& d : read.diagnostics) {
      QVERIFY2(d.message.find("; ") != std::string::npos, d.message.c_str());
    }
  }

  // A quaternion rounded for display (|q| within 1e-3 of 1) is accepted.
  void nearlyUnitQuaternionIsAccepted() {
    Json json = sample_json();
    json["frames"][1]["pallet"] = Json::parse("[0, 0, 0, 0.9995, 0, 0, 0]");
    QVERIFY(replay_from_json(json));
  }

  void everyProblemIsReported() {
    Json json = sample_json();
    json["hz"] = -1;
    json["frames"][0]["t"] = "0";
    json["frames"][4]["items"][0][0] = "x";
    QCOMPARE(pointers(replay_from_json(json).diagnostics),
             QStringLiteral("/hz /frames/0/t /frames/4/items/0/0"));
  }
};

QTEST_APPLESS_MAIN(ReplayTest)
#include "replay_test.moc"
