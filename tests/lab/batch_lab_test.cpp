// SPDX-License-Identifier: MIT
// End-to-end runs of `palletballet-lab batch` (small inputs: three to five pallets).
#include <QJsonArray>
#include <QJsonObject>
#include <QtTest>

#include "../cli/cli_runner.hpp"

using namespace pb::test;

class BatchLabTest : public QObject {
  Q_OBJECT

 private slots:
  void helpAndUnknownOptions() {
    Run r = lab({QStringLiteral("batch"), QStringLiteral("--help")});
    QCOMPARE(r.exit_code, 0);
    QVERIFY2(r.out.startsWith("usage: palletballet-lab batch"), r.out.constData());
    Run unknown = lab({QStringLiteral("batch"), QStringLiteral("--no-such-flag")});
    QCOMPARE(unknown.exit_code, 2);
  }

  void batchOfThreePallets() {
    QTemporaryDir dir;
    const QString out = dir.filePath(QStringLiteral("study.json"));
    Run r = lab({QStringLiteral("batch"), QStringLiteral("--n"), QStringLiteral("3"),
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
      Run r = lab({"batch", "--n", "5", "--seed", "3", "--shard", QStringLiteral("%1/3").arg(i),
                   "--out", files.back()});
      QVERIFY2(r.exit_code == 0, r.err.constData());
      QCOMPARE(r.json().object().value("shard").toString(), QStringLiteral("%1/3").arg(i));
    }
    Run whole = lab({"batch", "--n", "5", "--seed", "3"});
    QVERIFY2(whole.exit_code == 0, whole.err.constData());
    Run merged = lab(QStringList{"batch", "--merge"} + QStringList{files[2], files[0], files[1]});
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
    Run twice = lab({"batch", "--merge", files[0], files[0]});
    QCOMPARE(twice.exit_code, 2);
    QVERIFY(twice.err.contains("in both"));
    Run bad = lab({"batch", "--n", "4", "--shard", "4/4"});
    QCOMPARE(bad.exit_code, 2);
    QVERIFY(bad.err.contains("--shard"));
  }

  void batchBadOptionsAreExit2() {
    Run r = lab({QStringLiteral("batch"), QStringLiteral("--n"), QStringLiteral("0")});
    QCOMPARE(r.exit_code, 2);
    QVERIFY2(r.err.contains("--n"), r.err.constData());
    Run bad_out = lab({QStringLiteral("batch"), QStringLiteral("--n"), QStringLiteral("1"),
                       QStringLiteral("--out"), QStringLiteral("/no/such/dir/x.json")});
    QCOMPARE(bad_out.exit_code, 2);
  }
};

QTEST_GUILESS_MAIN(BatchLabTest)
#include "batch_lab_test.moc"
