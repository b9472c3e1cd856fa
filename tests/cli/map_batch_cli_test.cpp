// SPDX-License-Identifier: MIT
// End-to-end runs of `map` and `batch` (small inputs: a coarse grid, three pallets).
#include <QJsonArray>
#include <QJsonObject>
#include <QtTest>

#include "cli_runner.hpp"

using namespace pb::test;

class MapBatchCliTest : public QObject {
  Q_OBJECT

 private slots:
  void helpAndUnknownOptions_data() {
    QTest::addColumn<QString>("verb");
    QTest::newRow("map") << QStringLiteral("map");
    QTest::newRow("batch") << QStringLiteral("batch");
  }
  void helpAndUnknownOptions() {
    QFETCH(QString, verb);
    Run r = cli({verb, QStringLiteral("--help")});
    QCOMPARE(r.exit_code, 0);
    QVERIFY2(r.out.startsWith("usage: palletballet-cli " + verb.toUtf8()), r.out.constData());
    Run unknown = cli({verb, QStringLiteral("--no-such-flag")});
    QCOMPARE(unknown.exit_code, 2);
  }

  void mapOfASmallGrid() {
    Run r = cli({QStringLiteral("map"), QStringLiteral("asymmetric-load"),
                 QStringLiteral("--speeds"), QStringLiteral("0.5,2"), QStringLiteral("--accels"),
                 QStringLiteral("1:5:2"), QStringLiteral("--threads"), QStringLiteral("2")});
    QVERIFY2(r.exit_code == 0, r.err.constData());
    const QJsonObject map = r.json().object();
    QCOMPARE(map.value("speeds_mps").toArray().size(), 2);
    QCOMPARE(map.value("accels_mps2").toArray().at(1).toDouble(), 5.0);
    const QJsonArray rows = map.value("cells").toArray();
    QCOMPARE(rows.size(), 2);
    QCOMPARE(rows.at(0).toArray().size(), 2);
    QCOMPARE(map.value("sims").toInt(), 2 * 2 + 2 * 2);
    QCOMPARE(map.value("line_cells").toArray().size(), 2);
    const QJsonObject cell = rows.at(0).toArray().at(0).toObject();
    for (const char* key : {"outcome", "mode", "failure_time_s", "decided_by", "non_monotone"}) {
      QVERIFY2(cell.contains(key), key);
    }
    const QJsonObject env = map.value("envelope").toObject();
    QVERIFY(env.contains("max_speed_mps") && env.contains("max_accel_mps2"));
    QVERIFY(map.value("cell_definition").toString().contains("e-stop"));
  }

  void mapBadGridIsExit2() {
    Run r = cli({QStringLiteral("map"), QStringLiteral("asymmetric-load"),
                 QStringLiteral("--speeds"), QStringLiteral("2,1")});
    QCOMPARE(r.exit_code, 2);
    QVERIFY2(r.err.contains("--speeds") && r.err.contains("ascending"), r.err.constData());
    Run syntax = cli({QStringLiteral("map"), QStringLiteral("asymmetric-load"),
                      QStringLiteral("--accels"), QStringLiteral("1:2")});
    QCOMPARE(syntax.exit_code, 2);
    QVERIFY(syntax.err.contains("FROM:TO:COUNT"));
  }

  void batchOfThreePallets() {
    QTemporaryDir dir;
    const QString out = dir.filePath(QStringLiteral("study.json"));
    Run r = cli({QStringLiteral("batch"), QStringLiteral("--n"), QStringLiteral("3"),
                 QStringLiteral("--seed"), QStringLiteral("0"), QStringLiteral("--threads"),
                 QStringLiteral("2"), QStringLiteral("--out"), out});
    QVERIFY2(r.exit_code == 0, r.err.constData());
    const QJsonObject summary = r.json().object();
    QCOMPARE(summary.value("n").toInt(), 3);
    QCOMPARE(summary.value("analysed").toInt() + summary.value("errors").toInt(), 3);
    QVERIFY(summary.value("pallets_per_s").toDouble() > 0.0);
    QVERIFY(summary.value("sims_run").toInt() > 0);
    QVERIFY(summary.contains("dominant_modes") && summary.contains("reject_modes"));
    QVERIFY(!summary.contains("pallets"));
    const QJsonObject full = QJsonDocument::fromJson(read_file(out)).object();
    const QJsonArray pallets = full.value("pallets").toArray();
    QCOMPARE(pallets.size(), 3);
    QCOMPARE(pallets.at(2).toObject().value("pallet_id").toString(), QStringLiteral("R-2"));
    QVERIFY(pallets.at(0).toObject().value("result").toObject().contains("max_speed_mps"));
    int modes = 0;
    for (const QJsonValue v : full.value("dominant_modes").toObject()) modes += v.toInt();
    QCOMPARE(modes, summary.value("analysed").toInt());
  }

  // Shards of a study, run apart and merged, give the study one run gives: the same pallets in
  // seed order with the same results, and the same summary.
  void batchShardsMergeIntoTheWholeStudy() {
    QTemporaryDir dir;
    QStringList files;
    for (int i = 0; i < 3; ++i) {
      files << dir.filePath(QStringLiteral("s%1.json").arg(i));
      Run r = cli({"batch", "--n", "5", "--seed", "3", "--shard", QStringLiteral("%1/3").arg(i),
                   "--out", files.back()});
      QVERIFY2(r.exit_code == 0, r.err.constData());
      QCOMPARE(r.json().object().value("shard").toString(), QStringLiteral("%1/3").arg(i));
    }
    Run whole = cli({"batch", "--n", "5", "--seed", "3"});
    QVERIFY2(whole.exit_code == 0, whole.err.constData());
    Run merged = cli(QStringList{"batch", "--merge"} + QStringList{files[2], files[0], files[1]});
    QVERIFY2(merged.exit_code == 0, merged.err.constData());
    const QJsonObject w = whole.json().object(), m = merged.json().object();
    QCOMPARE(m.value("shards").toInt(), 3);
    const QJsonArray wp = w.value("pallets").toArray(), mp = m.value("pallets").toArray();
    QCOMPARE(mp.size(), 5);
    for (int i = 0; i < 5; ++i) {
      QJsonObject a = wp.at(i).toObject().value("result").toObject();
      QJsonObject b = mp.at(i).toObject().value("result").toObject();
      QCOMPARE(mp.at(i).toObject().value("seed").toInt(), 3 + i);
      a.remove("sim_runtime_ms");
      b.remove("sim_runtime_ms");
      QCOMPARE(a, b);
    }
    for (const char* key : {"n", "seed", "analysed", "errors", "rejects", "dominant_modes",
                            "speed_governed_by", "limits", "sims_run"}) {
      QVERIFY2(w.value(key) == m.value(key), key);
    }
    // A shard given twice, or a shard that is not a study, is refused.
    Run twice = cli({"batch", "--merge", files[0], files[0]});
    QCOMPARE(twice.exit_code, 2);
    QVERIFY(twice.err.contains("in both"));
    Run bad = cli({"batch", "--n", "4", "--shard", "4/4"});
    QCOMPARE(bad.exit_code, 2);
    QVERIFY(bad.err.contains("--shard"));
  }

  void batchBadOptionsAreExit2() {
    Run r = cli({QStringLiteral("batch"), QStringLiteral("--n"), QStringLiteral("0")});
    QCOMPARE(r.exit_code, 2);
    QVERIFY2(r.err.contains("--n"), r.err.constData());
    Run bad_out = cli({QStringLiteral("batch"), QStringLiteral("--n"), QStringLiteral("1"),
                       QStringLiteral("--out"), QStringLiteral("/no/such/dir/x.json")});
    QCOMPARE(bad_out.exit_code, 2);
  }
};

QTEST_GUILESS_MAIN(MapBatchCliTest)
#include "map_batch_cli_test.moc"
