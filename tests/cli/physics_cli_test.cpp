// SPDX-License-Identifier: MIT
// End-to-end runs of palletballet-cli's physics verbs: mjcf, solve, analyze, bench. Only small
// pallets and the 6-8 item scenarios are simulated, so the whole file runs in seconds.
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QProcess>
#include <QTemporaryDir>
#include <QtTest>

#include <algorithm>

#include <cmath>
#include <string>

#include "core/analysis/replay.hpp"
#include "core/contract/json_io.hpp"
#include "core/physics/engine.hpp"

#include "cli_runner.hpp"

namespace {

using pb::test::cli;
using pb::test::read_file;
using pb::test::Run;
using pb::test::write_file;

// Two 6 kg cartons side by side on an EUR pallet: the cheapest pallet worth simulating.
QJsonObject two_cartons() {
  auto carton = [](double x) {
    return QJsonObject{{QStringLiteral("sku"), QStringLiteral("SKU-FD-002")},
                       {QStringLiteral("dims_m"), QJsonArray{0.35, 0.25, 0.12}},
                       {QStringLiteral("weight_kg"), 6.0},
                       {QStringLiteral("position"), QJsonArray{x, 0.0, 0.15}},
                       {QStringLiteral("center_of_mass"), QJsonArray{x, 0.0, 0.21}},
                       {QStringLiteral("orientation_deg"), 0.0},
                       {QStringLiteral("fragility"), QStringLiteral("rigid")}};
  };
  return {{QStringLiteral("pallet_id"), QStringLiteral("two-cartons")},
          {QStringLiteral("base_pallet_type"), QStringLiteral("EUR")},
          {QStringLiteral("base_dims_m"), QJsonArray{1.2, 0.8, 0.15}},
          {QStringLiteral("base_mass_kg"), 25.0},
          {QStringLiteral("items"), QJsonArray{carton(-0.2), carton(0.2)}},
          {QStringLiteral("wrap"), QStringLiteral("none")},
          {QStringLiteral("env"), QStringLiteral("refrigerated")},
          {QStringLiteral("body_temp_c"), 2.0}};
}

QByteArray bytes(const QJsonObject& o) {
  return QJsonDocument(o).toJson();
}

// The same pallet with a negative weight on its first item.
QJsonObject with_bad_weight(QJsonObject pallet) {
  QJsonArray items = pallet.value(QStringLiteral("items")).toArray();
  QJsonObject first = items[0].toObject();
  first[QStringLiteral("weight_kg")] = -3.0;
  items[0] = first;
  pallet[QStringLiteral("items")] = items;
  return pallet;
}

QJsonObject scenario(const QString& slug) {
  return cli({QStringLiteral("scenarios"), slug}).json().object();
}

double num(const QJsonObject& o, const char* key) {
  return o.value(QLatin1String(key)).toDouble();
}
QString str(const QJsonObject& o, const char* key) {
  return o.value(QLatin1String(key)).toString();
}

}  // namespace

class PhysicsCliTest : public QObject {
  Q_OBJECT

 private slots:
  void verbsAreListed() {
    Run r = cli({QStringLiteral("--help")});
    QCOMPARE(r.exit_code, 0);
    for (const char* verb : {"  mjcf ", "  solve ", "  analyze ", "  bench "}) {
      QVERIFY2(r.out.contains(verb), verb);
    }
  }

  // ---- mjcf ----

  void mjcfOfAScenarioCompiles() {
    Run r = cli({QStringLiteral("mjcf"), QStringLiteral("tall-unwrapped-tower")});
    QVERIFY2(r.exit_code == 0, r.err.constData());
    QVERIFY(r.out.startsWith("<mujoco"));
    QCOMPARE(r.out.count("<body name=\"item_"), 8);
    QCOMPARE(r.out.count("<body "), 10);  // belt, pallet, 8 items
    auto model = pb::compile_mjcf(r.out.toStdString());
    QVERIFY(model.ok());
    QCOMPARE((*model)->nbody, 11);  // and the world
    QVERIFY(r.err.isEmpty());

    // --out writes the same text to a file and nothing to stdout.
    QTemporaryDir dir;
    const QString path = dir.filePath(QStringLiteral("scene.xml"));
    Run out = cli({QStringLiteral("mjcf"), QStringLiteral("tall-unwrapped-tower"),
                   QStringLiteral("--out"), path});
    QCOMPARE(out.exit_code, 0);
    QVERIFY(out.out.isEmpty());
    QCOMPARE(read_file(path), r.out);
  }

  void mjcfFromStdinAndFromAScenarioFile() {
    Run r = cli({QStringLiteral("mjcf"), QStringLiteral("-")}, bytes(two_cartons()));
    QVERIFY2(r.exit_code == 0, r.err.constData());
    QCOMPARE(r.out.count("<body name=\"item_"), 2);
    QVERIFY(pb::compile_mjcf(r.out.toStdString()).ok());

    QTemporaryDir dir;
    const QJsonObject s = scenario(QStringLiteral("top-heavy-surprise"));
    Run file = cli({QStringLiteral("mjcf"), write_file(dir, QStringLiteral("s.json"), bytes(s))});
    QCOMPARE(file.exit_code, 0);
    QCOMPARE(file.out.count("<body name=\"item_"), 6);
    // The file and the slug are the same scene.
    QCOMPARE(file.out, cli({QStringLiteral("mjcf"), QStringLiteral("top-heavy-surprise")}).out);
  }

  void mjcfRejectsAnInvalidPallet() {
    QTemporaryDir dir;
    Run plain = cli({QStringLiteral("mjcf"), write_file(dir, QStringLiteral("bad.json"),
                                                        bytes(with_bad_weight(two_cartons())))});
    QCOMPARE(plain.exit_code, 2);
    QVERIFY(plain.out.isEmpty());
    QVERIFY2(plain.err.contains("/items/0/weight_kg: "), plain.err.constData());

    // In a scenario file, the pointers lead into its "pallet".
    QJsonObject s = scenario(QStringLiteral("top-heavy-surprise"));
    s[QStringLiteral("pallet")] = with_bad_weight(s.value(QStringLiteral("pallet")).toObject());
    Run in_scenario =
        cli({QStringLiteral("mjcf"), write_file(dir, QStringLiteral("s.json"), bytes(s))});
    QCOMPARE(in_scenario.exit_code, 2);
    QVERIFY2(in_scenario.err.contains("/pallet/items/0/weight_kg: "), in_scenario.err.constData());

    Run missing = cli({QStringLiteral("mjcf"), dir.filePath(QStringLiteral("nope.json"))});
    QCOMPARE(missing.exit_code, 2);
    QVERIFY2(missing.err.contains("cannot open"), missing.err.constData());
    QVERIFY(missing.err.contains("stable-dairy-slab"));  // the slugs it could have named

    Run bad_out = cli({QStringLiteral("mjcf"), QStringLiteral("top-heavy-surprise"),
                       QStringLiteral("--out"), dir.filePath(QStringLiteral("no/such/dir.xml"))});
    QCOMPARE(bad_out.exit_code, 2);
    QVERIFY2(bad_out.err.contains("cannot write"), bad_out.err.constData());
  }

  // ---- solve ----

  void solveRunsASuggestedProfileAndWritesItsReplay() {
    QTemporaryDir dir;
    const QString replay_path = dir.filePath(QStringLiteral("replay.json"));
    Run r = cli({QStringLiteral("solve"), QStringLiteral("tall-unwrapped-tower"),
                 QStringLiteral("--replay"), replay_path});
    QVERIFY2(r.exit_code == 0, r.err.constData());  // a failure is an answer
    const QJsonObject o = r.json().object();
    QCOMPARE(str(o, "outcome"), QStringLiteral("failed"));
    QVERIFY(!o.contains(QStringLiteral("reason")));
    const QJsonObject failure = o.value(QStringLiteral("failure")).toObject();
    const QString mode = str(failure, "mode");
    QVERIFY2(mode == QStringLiteral("tip_over") || mode == QStringLiteral("top_item_slide") ||
                 mode == QStringLiteral("load_shift") || mode == QStringLiteral("pallet_slip"),
             qPrintable(mode));
    QVERIFY(str(failure, "description").startsWith(mode + QStringLiteral(" at ")));
    QVERIFY(failure.value(QStringLiteral("items")).isArray());
    // The verdict is the first failure; the run then follows the wreck (at least 0.25 s, at most
    // 3 s) until the cartons move with the belt again.
    QVERIFY(num(o, "sim_time_s") >= num(failure, "time_s") + 0.25);
    QVERIFY(num(o, "sim_time_s") <= num(failure, "time_s") + 3.0 + 1e-9);
    QVERIFY(!o.contains(QStringLiteral("aftermath_cut")));
    QVERIFY(o.value(QStringLiteral("steps")).toInt() > 0);
    QCOMPARE(o.value(QStringLiteral("stopped_early")).toBool(), false);
    QVERIFY(num(o, "wall_ms") > 0.0);
    // The scenario's suggested profile, as stored.
    const QJsonObject profile = o.value(QStringLiteral("profile")).toObject();
    QCOMPARE(profile, scenario(QStringLiteral("tall-unwrapped-tower"))
                          .value(QStringLiteral("suggested_profile"))
                          .toObject());

    auto json = pb::parse_json(read_file(replay_path).toStdString());
    QVERIFY(json.ok());
    auto replay = pb::replay_from_json(*json);
    QVERIFY(replay.ok());
    QCOMPARE(replay->outcome, std::string("failed"));
    QVERIFY(replay->failure.has_value());
    QCOMPARE(QString::fromStdString(std::string(pb::to_string(replay->failure->mode))), mode);
    QCOMPARE(replay->failure->time_s, num(failure, "time_s"));
    QCOMPARE(replay->pallet.items.size(), std::size_t{8});
    QCOMPARE(replay->hz, 30.0);
    QVERIFY(replay->frames.size() >= 2);
    QCOMPARE(replay->frames.front().t, 0.0);
    QCOMPARE(replay->frames.back().t, num(o, "sim_time_s"));
    // The moment the detector fired is a frame of its own, and the wreck comes after it: cartons
    // that have left the pallet lie on the belt (their centres below the deck's top).
    const double fired = num(failure, "time_s");
    QVERIFY(std::any_of(replay->frames.begin(), replay->frames.end(),
                        [&](const pb::ReplayFrame& f) { return f.t == fired; }));
    const pb::ReplayFrame& end = replay->frames.back();
    const double deck_top = end.pallet.pos[2] + replay->pallet.base_dims_m[2] / 2;
    QVERIFY(std::any_of(end.items.begin(), end.items.end(),
                        [&](const pb::Pose& p) { return p.pos[2] < deck_top; }));
    // None through the belt: a carton above the belt (which reaches 1 m past the pallet's deck on
    // every side) lies on it; one thrown further in the curve has fallen off its side.
    const auto& base = replay->pallet.base_dims_m;
    QVERIFY(std::all_of(end.items.begin(), end.items.end(), [&](const pb::Pose& p) {
      const bool over = std::abs(p.pos[0] - end.belt_x) < base[0] + 1.0 &&
                        std::abs(p.pos[1] - end.belt_y) < base[1] + 1.0;
      return !over || p.pos[2] > 0.0;
    }));
  }

  void solveBuildsTheProfileFromItsFlags() {
    QTemporaryDir dir;
    const QString path = write_file(dir, QStringLiteral("p.json"), bytes(two_cartons()));
    Run r =
        cli({QStringLiteral("solve"), path, QStringLiteral("--speed"), QStringLiteral("0.5"),
             QStringLiteral("--accel"), QStringLiteral("0.5"), QStringLiteral("--replay"),
             dir.filePath(QStringLiteral("r.json")), QStringLiteral("--hz"), QStringLiteral("10")});
    QVERIFY2(r.exit_code == 0, r.err.constData());
    const QJsonObject o = r.json().object();
    QCOMPARE(str(o, "outcome"), QStringLiteral("safe"));
    QVERIFY(o.value(QStringLiteral("failure")).isNull());
    const QJsonObject profile = o.value(QStringLiteral("profile")).toObject();
    QCOMPARE(str(profile, "shape"), QStringLiteral("accel_hold"));
    QCOMPARE(num(profile, "target_speed_mps"), 0.5);
    QCOMPARE(num(profile, "accel_mps2"), 0.5);
    QCOMPARE(num(profile, "duration_s"), 5.0);  // the reference's 5 s: the 1 s ramp ends within
    // Co-moving after the ramp: nothing can change, so the run stops long before the 5 s.
    QCOMPARE(o.value(QStringLiteral("stopped_early")).toBool(), true);
    QVERIFY(num(o, "sim_time_s") >= 1.0 && num(o, "sim_time_s") < 2.0);
    QCOMPARE(str(o, "fidelity"), QStringLiteral("full"));  // unwrapped: the full model, 1.5 ms
    QCOMPARE(num(o, "timestep_s"), 0.0015);
    QCOMPARE(o.value(QStringLiteral("steps")).toInt(),
             static_cast<int>(std::lround(num(o, "sim_time_s") / num(o, "timestep_s"))));
    auto replay = pb::replay_from_json(
        *pb::parse_json(read_file(dir.filePath(QStringLiteral("r.json"))).toStdString()));
    QVERIFY(replay.ok());
    QCOMPARE(replay->outcome, std::string("safe"));
    QCOMPARE(replay->hz, 10.0);
    QCOMPARE(replay->frames[1].t, 0.1);

    // An e-stop from stdin: no --accel needed; it lasts until the belt stands, plus 1 s, where
    // that is beyond the reference's 5 s (the server's default too: default_duration_s).
    Run estop = cli({QStringLiteral("solve"), QStringLiteral("-"), QStringLiteral("--profile"),
                     QStringLiteral("estop"), QStringLiteral("--speed"), QStringLiteral("1"),
                     QStringLiteral("--decel"), QStringLiteral("0.25"),
                     QStringLiteral("--decel-start"), QStringLiteral("0.2")},
                    bytes(two_cartons()));
    QVERIFY2(estop.exit_code == 0, estop.err.constData());
    const QJsonObject e = estop.json().object().value(QStringLiteral("profile")).toObject();
    QCOMPARE(str(e, "shape"), QStringLiteral("estop"));
    QCOMPARE(num(e, "decel_mps2"), 0.25);
    QCOMPARE(num(e, "decel_start_s"), 0.2);
    QVERIFY(std::abs(num(e, "duration_s") - 5.2) < 1e-12);

    // Every flag overrides its field of a suggested profile, --speed and --accel too; a changed
    // motion runs default_duration_s unless --duration says otherwise.
    Run faster = cli({QStringLiteral("solve"), QStringLiteral("top-heavy-surprise"),
                      QStringLiteral("--speed"), QStringLiteral("0.5")});
    QVERIFY2(faster.exit_code == 0, faster.err.constData());
    const QJsonObject f = faster.json().object().value(QStringLiteral("profile")).toObject();
    QCOMPARE(num(f, "target_speed_mps"), 0.5);
    QCOMPARE(num(f, "accel_mps2"), 4.0);  // the scenario's
    QCOMPARE(str(f, "shape"), QStringLiteral("accel_hold"));
    // Another shape than the suggested one starts from nothing: --speed is required.
    Run slow = cli({QStringLiteral("solve"), QStringLiteral("top-heavy-surprise"),
                    QStringLiteral("--profile"), QStringLiteral("curve")});
    QCOMPARE(slow.exit_code, 2);
    QVERIFY2(slow.err.contains("--speed is required for a --profile other than the scenario's"),
             slow.err.constData());

    Run longer = cli({QStringLiteral("solve"), QStringLiteral("top-heavy-surprise"),
                      QStringLiteral("--duration"), QStringLiteral("0.5")});
    QVERIFY2(longer.exit_code == 0, longer.err.constData());
    const QJsonObject l = longer.json().object().value(QStringLiteral("profile")).toObject();
    QCOMPARE(num(l, "duration_s"), 0.5);
    QCOMPARE(num(l, "accel_mps2"), 4.0);  // the scenario's
    // The run covers the duration and stops within a step of it (1.5 ms does not divide 0.5 s).
    const QJsonObject lo = longer.json().object();
    QVERIFY(num(lo, "sim_time_s") >= 0.5 && num(lo, "sim_time_s") < 0.5 + num(lo, "timestep_s"));
  }

  void solveBadInput_data() {
    QTest::addColumn<QStringList>("args");
    QTest::addColumn<QString>("message");
    const QString p = QStringLiteral("P");  // replaced by the pallet file
    auto row = [&](const char* name, QStringList args, const char* message) {
      QTest::newRow(name) << args << QString::fromLatin1(message);
    };
    row("speed not a number", {p, "--speed", "fast", "--accel", "1"}, "--speed expects a number");
    row("no speed", {p, "--accel", "1"}, "--speed is required");
    row("no accel", {p, "--speed", "1"}, "--accel is required for the accel_hold profile");
    row("zero accel", {p, "--speed", "1", "--accel", "0"},
        "--accel: 0 is out of range; write a number in (0, 10] m/s^2");
    row("too fast", {p, "--speed", "6", "--accel", "1"}, "--speed: 6 is out of range");
    row("too long", {p, "--speed", "1", "--accel", "1", "--duration", "40"},
        "--duration: 40 is out of range");
    row("bad curve", {p, "--profile", "curve", "--speed", "1", "--radius", "-2"},
        "--radius: -2 is out of range");
    row("unknown shape", {p, "--profile", "zigzag", "--speed", "1"},
        "accel_hold, constant, ramp_decel, estop, curve or eumos");
    row("zero hz", {p, "--speed", "1", "--accel", "1", "--hz", "0"}, "--hz must be above 0");
    row("bad replay path", {p, "--speed", "1", "--accel", "1", "--replay", "/no/such/dir/r.json"},
        "cannot write");
    row("no file", {"--speed", "1", "--accel", "1"}, "missing argument");
    row("unknown slug", {"no-such-scenario", "--speed", "1", "--accel", "1"}, "cannot open");
  }
  void solveBadInput() {
    QFETCH(QStringList, args);
    QFETCH(QString, message);
    QTemporaryDir dir;
    const QString path = write_file(dir, QStringLiteral("p.json"), bytes(two_cartons()));
    for (QString& a : args) {
      if (a == QStringLiteral("P")) a = path;
    }
    Run r = cli(QStringList{QStringLiteral("solve")} + args);
    QCOMPARE(r.exit_code, 2);
    QVERIFY(r.out.isEmpty());
    QVERIFY2(r.err.contains(message.toUtf8()), r.err.constData());
  }

  void solveRejectsAnInvalidPallet() {
    Run r = cli({QStringLiteral("solve"), QStringLiteral("-"), QStringLiteral("--speed"),
                 QStringLiteral("1"), QStringLiteral("--accel"), QStringLiteral("1")},
                bytes(with_bad_weight(two_cartons())));
    QCOMPARE(r.exit_code, 2);
    QVERIFY(r.out.isEmpty());
    QVERIFY2(r.err.contains("/items/0/weight_kg: "), r.err.constData());
    // With a bad profile too, both are told at once.
    Run both = cli({QStringLiteral("solve"), QStringLiteral("-"), QStringLiteral("--speed"),
                    QStringLiteral("-3"), QStringLiteral("--accel"), QStringLiteral("1")},
                   bytes(with_bad_weight(two_cartons())));
    QCOMPARE(both.exit_code, 2);
    QVERIFY2(both.err.contains("/items/0/weight_kg: ") && both.err.contains("--speed: -3"),
             both.err.constData());
  }

  // ---- analyze ----

  void analyzeAnswersARepeatedFileFromTheCache() {
    QTemporaryDir dir;
    const QJsonObject pallet =
        scenario(QStringLiteral("tall-unwrapped-tower")).value(QStringLiteral("pallet")).toObject();
    const QString good = write_file(dir, QStringLiteral("tower.json"), bytes(pallet));
    const QString bad =
        write_file(dir, QStringLiteral("bad.json"), bytes(with_bad_weight(two_cartons())));
    Run r = cli({QStringLiteral("analyze"), good, bad, good});
    QCOMPARE(r.exit_code, 2);  // the bad file; the others are still analysed
    const QJsonArray list = r.json().array();
    QCOMPARE(list.size(), 3);

    const QJsonObject first = list[0].toObject();
    const QJsonObject error = list[1].toObject();
    const QJsonObject again = list[2].toObject();
    QCOMPARE(str(first, "source"), good);
    QCOMPARE(str(error, "source"), bad);
    QCOMPARE(str(again, "source"), good);

    QCOMPARE(error.size(), 2);  // "source" and "error" only
    const QJsonArray messages = error.value(QStringLiteral("error")).toArray();
    QVERIFY(!messages.isEmpty());
    QVERIFY2(messages[0].toString().startsWith(QStringLiteral("/items/0/weight_kg: ")),
             qPrintable(messages[0].toString()));
    QVERIFY2(r.err.contains(bad.toUtf8() + ": /items/0/weight_kg: "), r.err.constData());

    QVERIFY(first.value(QStringLiteral("sims_run")).toInt() > 0);
    QCOMPARE(again.value(QStringLiteral("sims_run")).toInt(), 0);
    for (const char* key : {"max_speed_mps", "max_accel_mps2", "max_decel_mps2", "max_lateral_g",
                            "margin_pct", "confidence"}) {
      QCOMPARE(num(again, key), num(first, key));
    }
    for (const char* key :
         {"dominant_failure_mode", "accel_mode", "decel_mode", "lateral_mode", "speed_mode",
          "speed_governed_by", "verdict", "reason", "config_hash", "pallet_id"}) {
      QCOMPARE(str(again, key), str(first, key));
    }
    QCOMPARE(str(first, "pallet_id"), QStringLiteral("tall-unwrapped-tower"));
    QCOMPARE(str(first, "config_hash").size(), 64);
    QVERIFY(num(first, "max_accel_mps2") > 0.0);
    QVERIFY(!first.contains(QStringLiteral("probes")));
  }

  // With several files each warning names its file, and analyze warns of what validate does
  // (a weight far from its SKU's): a warning without its file could not be told apart.
  void analyzeNamesTheFileOfEachWarning() {
    QTemporaryDir dir;
    QJsonObject pallet =
        scenario(QStringLiteral("stable-dairy-slab")).value(QStringLiteral("pallet")).toObject();
    const QString plain = write_file(dir, QStringLiteral("plain.json"), bytes(pallet));
    QJsonArray items = pallet.value(QStringLiteral("items")).toArray();
    QJsonObject first = items[0].toObject();
    first[QStringLiteral("weight_kg")] = first.value(QStringLiteral("weight_kg")).toDouble() * 1.1;
    items[0] = first;
    pallet[QStringLiteral("items")] = items;
    const QString heavier = write_file(dir, QStringLiteral("heavier.json"), bytes(pallet));
    Run r = cli({QStringLiteral("analyze"), plain, heavier});
    QCOMPARE(r.exit_code, 0);
    QVERIFY2(r.err.contains(heavier.toUtf8() + ": warning: /items/0/weight_kg: "),
             r.err.constData());
    QVERIFY2(!r.err.contains(plain.toUtf8() + ": warning"), r.err.constData());
    // Once each, also where the analysis returns validate's warnings itself (closed form).
    Run closed = cli({QStringLiteral("analyze"), heavier, QStringLiteral("--fidelity"),
                      QStringLiteral("closed_form")});
    QCOMPARE(closed.exit_code, 0);
    QCOMPARE(closed.err.count("warning: /items/0/weight_kg: "), qsizetype(1));
  }

  void analyzeListsProbesAndUsesTheLine() {
    Run r =
        cli({QStringLiteral("analyze"), QStringLiteral("-"), QStringLiteral("--probes"),
             QStringLiteral("--estop-decel"), QStringLiteral("1.5"),
             QStringLiteral("--curve-radius"), QStringLiteral("4"), QStringLiteral("--accel-max"),
             QStringLiteral("4"), QStringLiteral("--speed-max"), QStringLiteral("1.5")},
            bytes(two_cartons()));
    QVERIFY2(r.exit_code == 0, r.err.constData());
    const QJsonArray list = r.json().array();
    QCOMPARE(list.size(), 1);
    const QJsonObject o = list[0].toObject();
    QCOMPARE(str(o, "source"), QStringLiteral("-"));
    QCOMPARE(num(o, "line_estop_decel_mps2"), 1.5);
    QCOMPARE(num(o, "line_curve_radius_m"), 4.0);
    QVERIFY(num(o, "max_accel_mps2") <= 4.0);
    QVERIFY(num(o, "max_speed_mps") <= 1.5);
    const QJsonArray probes = o.value(QStringLiteral("probes")).toArray();
    QCOMPARE(probes.size(), o.value(QStringLiteral("sims_run")).toInt());
    QSet<QString> axes;
    for (const QJsonValue& v : probes) {
      const QJsonObject p = v.toObject();
      // axis, value, outcome, mode, failure_time_s, sim_time_s, steps, peak_ratio,
      // load_peak_ratio, confirmation (false: --confirm-limits not given), wall_ms; the turn of a
      // curve's probe; and
      // projected: true where a pallet slip was decided before its threshold
      const bool curve = str(p, "axis") == QStringLiteral("lateral");
      const bool projected = p.contains(QStringLiteral("projected"));
      QCOMPARE(p.size(), (curve ? 12 : 11) + (projected ? 1 : 0));
      if (projected) {
        QCOMPARE(p.value(QStringLiteral("projected")), QJsonValue(true));
        QCOMPARE(str(p, "mode"), QStringLiteral("pallet_slip"));
      }
      if (curve)
        QVERIFY(str(p, "turn") == QStringLiteral("left") ||
                str(p, "turn") == QStringLiteral("right"));
      QCOMPARE(p.value(QStringLiteral("confirmation")), QJsonValue(false));
      axes.insert(str(p, "axis"));
      const bool failed = str(p, "outcome") == QStringLiteral("failed");
      // How near it came to failing: past every threshold once failed, within them all if safe.
      QVERIFY(failed ? num(p, "peak_ratio") >= 1.0
                     : num(p, "peak_ratio") >= 0.0 && num(p, "peak_ratio") <= 1.0);
      // The load's own detectors are among them: never nearer than all of them.
      QVERIFY(num(p, "load_peak_ratio") >= 0.0 &&
              num(p, "load_peak_ratio") <= num(p, "peak_ratio"));
      QVERIFY(failed || str(p, "outcome") == QStringLiteral("safe"));
      QCOMPARE(p.value(QStringLiteral("failure_time_s")).isNull(), !failed);
      QCOMPARE(str(p, "mode") == QStringLiteral("no_failure"), !failed);
      if (failed) QVERIFY(num(p, "failure_time_s") > 0.0);
      if (str(p, "axis") == QStringLiteral("accel")) QVERIFY(num(p, "value") <= 4.0);
      if (str(p, "axis") == QStringLiteral("speed")) QVERIFY(num(p, "value") <= 1.5);
    }
    // The e-stop speed is derived when the stop search found the line's 1.5 m/s^2 safe.
    QVERIFY(axes.contains(QStringLiteral("accel")) && axes.contains(QStringLiteral("decel")) &&
            axes.contains(QStringLiteral("lateral")));
    QCOMPARE(axes.contains(QStringLiteral("speed")), num(o, "max_decel_mps2") < 1.5);
  }

  void analyzeBadInput() {
    Run none = cli({QStringLiteral("analyze")});
    QCOMPARE(none.exit_code, 2);
    QVERIFY(none.err.contains("missing argument"));
    Run speed = cli({QStringLiteral("analyze"), QStringLiteral("top-heavy-surprise"),
                     QStringLiteral("--speed-max"), QStringLiteral("0.05")});
    QCOMPARE(speed.exit_code, 2);
    QVERIFY2(speed.err.contains("--speed-max must be above 0.1 and at most 5 m/s"),
             speed.err.constData());
    Run decel = cli({QStringLiteral("analyze"), QStringLiteral("top-heavy-surprise"),
                     QStringLiteral("--estop-decel"), QStringLiteral("hard")});
    QCOMPARE(decel.exit_code, 2);
    QVERIFY(decel.err.contains("--estop-decel expects a number"));
    // A line too tight for the pallet names the flag that sets it, not a member of the file.
    Run tight = cli({QStringLiteral("analyze"), QStringLiteral("stable-dairy-slab"),
                     QStringLiteral("--curve-radius"), QStringLiteral("0.3")});
    QCOMPARE(tight.exit_code, 2);
    QVERIFY2(tight.err.contains("stable-dairy-slab: --curve-radius: a curve of radius 0.3 m") &&
                 !tight.err.contains("/line/"),
             tight.err.constData());
    Run missing = cli({QStringLiteral("analyze"), QStringLiteral("no-such-file.json")});
    QCOMPARE(missing.exit_code, 2);
    const QJsonArray list = missing.json().array();
    QCOMPARE(list.size(), 1);
    QCOMPARE(str(list[0].toObject(), "source"), QStringLiteral("no-such-file.json"));
    QVERIFY(list[0]
                .toObject()
                .value(QStringLiteral("error"))
                .toArray()[0]
                .toString()
                .contains(QStringLiteral("cannot open 'no-such-file.json'")));
  }

  // ---- bench ----

  void benchJson() {
    Run r = cli({QStringLiteral("bench"), QStringLiteral("--runs"), QStringLiteral("1"),
                 QStringLiteral("--json"), QStringLiteral("--scenario"),
                 QStringLiteral("tall-unwrapped-tower")});
    QVERIFY2(r.exit_code == 0, r.err.constData());
    const QJsonArray rows = r.json().array();
    QCOMPARE(rows.size(), 1);
    const QJsonObject o = rows[0].toObject();
    QCOMPARE(str(o, "scenario"), QStringLiteral("tall-unwrapped-tower"));
    QCOMPARE(o.value(QStringLiteral("items")).toInt(), 8);
    QCOMPARE(o.value(QStringLiteral("runs")).toInt(), 1);
    for (const char* key : {"solve_ms_median", "envelope_ms_median", "prepare_ms_median",
                            "steps_per_s", "us_per_step", "max_speed_mps", "max_accel_mps2"}) {
      QVERIFY2(num(o, key) > 0.0, key);
    }
    QVERIFY(o.value(QStringLiteral("sims_run")).toInt() > 0);
    // Rates are per step actually taken (steps jumped by the co-moving skip excluded).
    const int steps =
        o.value(QStringLiteral("steps")).toInt() - o.value(QStringLiteral("steps_skipped")).toInt();
    QVERIFY(steps > 0);
    QVERIFY(num(o, "envelope_ms_median") > num(o, "prepare_ms_median"));
    QVERIFY(std::abs(num(o, "steps_per_s") * num(o, "solve_ms_median") / 1000.0 - steps) < 1e-6);
    QVERIFY(std::abs(num(o, "us_per_step") * steps - num(o, "solve_ms_median") * 1000.0) < 1e-6);
    QCOMPARE(str(o, "outcome"), QStringLiteral("failed"));  // as `solve` of the same scenario
    QCOMPARE(str(o, "verdict"), QStringLiteral("ok"));
    // The reference system's search on the same pallet, and the ratio of the two.
    QVERIFY(num(o, "ref_ms") > 0.0);
    QVERIFY(o.value(QStringLiteral("ref_sims")).toInt() >= 2);
    QVERIFY(std::abs(num(o, "ratio") - num(o, "ref_ms") / num(o, "envelope_ms_median")) < 1e-9);
  }

  // --no-reference skips it: the keys are there, null.
  void benchWithoutReference() {
    Run r = cli({QStringLiteral("bench"), QStringLiteral("--runs"), QStringLiteral("1"),
                 QStringLiteral("--json"), QStringLiteral("--no-reference"),
                 QStringLiteral("--scenario"), QStringLiteral("stable-dairy-slab")});
    QVERIFY2(r.exit_code == 0, r.err.constData());
    const QJsonObject o = r.json().array()[0].toObject();
    QVERIFY(o.value(QStringLiteral("ref_ms")).isNull() &&
            o.value(QStringLiteral("ratio")).isNull());
  }

  void benchTable() {
    Run r = cli({QStringLiteral("bench"), QStringLiteral("--runs"), QStringLiteral("1"),
                 QStringLiteral("--scenario"), QStringLiteral("top-heavy-surprise")});
    QVERIFY2(r.exit_code == 0, r.err.constData());
    const QList<QByteArray> lines = r.out.trimmed().split('\n');
    QCOMPARE(lines.size(), 2);
    QVERIFY(lines[0].startsWith("scenario "));
    QVERIFY(lines[0].contains("solve_ms") && lines[0].contains("envelope_ms"));
    QVERIFY(lines[1].startsWith("top-heavy-surprise "));
    QCOMPARE(lines[1].simplified().split(' ').size(), 17);  // one cell per column
    QVERIFY(!lines[1].endsWith(' '));
  }

  void benchBadInput() {
    Run runs = cli({QStringLiteral("bench"), QStringLiteral("--runs"), QStringLiteral("0")});
    QCOMPARE(runs.exit_code, 2);
    QVERIFY(runs.err.contains("--runs must be between 1 and 1000"));
    Run word = cli({QStringLiteral("bench"), QStringLiteral("--runs"), QStringLiteral("many")});
    QCOMPARE(word.exit_code, 2);
    QVERIFY(word.err.contains("--runs expects a whole number"));
    Run slug = cli({QStringLiteral("bench"), QStringLiteral("--scenario"), QStringLiteral("nope")});
    QCOMPARE(slug.exit_code, 2);
    QVERIFY(slug.err.contains("no curated scenario 'nope'"));
  }
};

QTEST_GUILESS_MAIN(PhysicsCliTest)
#include "physics_cli_test.moc"
