// SPDX-License-Identifier: MIT
// End-to-end runs of `map` (small inputs: a coarse grid).
#include <QJsonArray>
#include <QJsonObject>
#include <QtTest>

#include "cli_runner.hpp"

using namespace pb::test;

class MapCliTest : public QObject {
  Q_OBJECT

 private slots:
  void helpAndUnknownOptions() {
    Run r = cli({QStringLiteral("map"), QStringLiteral("--help")});
    QCOMPARE(r.exit_code, 0);
    QVERIFY2(r.out.startsWith("usage: palletballet-cli map"), r.out.constData());
    Run unknown = cli({QStringLiteral("map"), QStringLiteral("--no-such-flag")});
    QCOMPARE(unknown.exit_code, 2);
  }

  // The studies are palletballet-lab's: the product's CLI links the core only.
  void theStudiesAreTheLabs() {
    for (const char* verb : {"study", "batch"}) {
      Run r = cli({QString::fromLatin1(verb), QStringLiteral("--help")});
      QCOMPARE(r.exit_code, 2);
      QVERIFY2(r.err.contains("unknown verb"), r.err.constData());
      Run l = lab({QString::fromLatin1(verb), QStringLiteral("--help")});
      QCOMPARE(l.exit_code, 0);
      QVERIFY2(l.out.startsWith("usage: palletballet-lab " + QByteArray(verb)), l.out.constData());
    }
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
};

QTEST_GUILESS_MAIN(MapCliTest)
#include "map_cli_test.moc"
