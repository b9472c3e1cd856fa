// SPDX-License-Identifier: MIT
// Issue 12 end to end: a load that cannot stand is refused by validate and analyze with the item
// named, random pallets of any wrap stand, and `study standing` finds no pallet that passes the
// rule but falls on a still belt.
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QtTest>

#include "../cli/cli_runner.hpp"

namespace {

using pb::test::cli;
using pb::test::lab;
using pb::test::Run;

const QString kExample = QStringLiteral(PB_TEST_DATA_DIR "/issue12_brick_half_offsets.json");

}  // namespace

class StandingLabTest : public QObject {
  Q_OBJECT

 private slots:
  // The 70-carton brick of the issue, laid with half-cell offsets: the top layer's end cartons
  // balance on an edge. validate names each one with the shift that stands it; analyze refuses it
  // the same way (no limit, no "0 m/s").
  void theIssuesExampleIsRefusedWithTheItemNamed() {
    Run v = cli({QStringLiteral("validate"), kExample});
    QCOMPARE(v.exit_code, 2);
    for (const char* item : {"60", "64", "68"}) {
      const QByteArray expected = QByteArray("/items/") + item + "/position: item " + item +
                                  " (SKU-FD-003) cannot stand: its centre of mass is 0 mm inside "
                                  "the edge of what it rests on";
      QVERIFY2(v.err.contains(expected), v.err.constData());
    }
    QVERIFY2(v.err.contains("move item 60 (SKU-FD-003) 10 mm towards +x"), v.err.constData());
    Run a = cli({QStringLiteral("analyze"), kExample});
    QVERIFY(a.exit_code != 0);
    QVERIFY2(a.err.contains("/items/60/position: item 60 (SKU-FD-003) cannot stand"),
             a.err.constData());
    QVERIFY(!a.out.contains("max_speed_mps"));
  }

  // The random adapter's wrap, and every pallet it makes validates, unwrapped too.
  void randomPalletsOfAnyWrapStand() {
    for (const char* wrap : {"none", "shrink", "stretch", "banded", "mixed"}) {
      for (const char* seed : {"1", "5", "23"}) {
        Run r = cli({QStringLiteral("random"), QStringLiteral("--seed"), QString::fromLatin1(seed),
                     QStringLiteral("--min-layers"), QStringLiteral("7"),
                     QStringLiteral("--max-layers"), QStringLiteral("7"), QStringLiteral("--wrap"),
                     QString::fromLatin1(wrap)});
        QVERIFY2(r.exit_code == 0, r.err.constData());
        const QString got = r.json().object().value(QStringLiteral("wrap")).toString();
        if (QByteArray(wrap) != "mixed") QCOMPARE(got, QString::fromLatin1(wrap));
        Run v = cli({QStringLiteral("validate"), QStringLiteral("-")}, r.out);
        QVERIFY2(v.exit_code == 0, (QByteArray(wrap) + " seed " + seed + ": " + v.err).constData());
      }
    }
    Run bad = cli({QStringLiteral("random"), QStringLiteral("--wrap"), QStringLiteral("cling")});
    QCOMPARE(bad.exit_code, 2);
    QVERIFY2(bad.err.contains("--wrap is 'cling'; use none, shrink, stretch or banded"),
             bad.err.constData());
  }

  // The rule against the simulation on a few unwrapped random pallets (held 0.5 s on a still
  // belt): the 2x2 table, and no pallet that passes the rule but cannot stand (exit 0).
  void studyStandingFindsNothingTheRuleLetsThrough() {
    Run r = lab({QStringLiteral("study"), QStringLiteral("standing"), QStringLiteral("--corpus"),
                 QStringLiteral("6"), QStringLiteral("--max-layers"), QStringLiteral("3"),
                 QStringLiteral("--hold"), QStringLiteral("0.5"), QStringLiteral("--threads"),
                 QStringLiteral("2")});
    QVERIFY2(r.exit_code == 0, (r.out + r.err).constData());
    QVERIFY2(r.out.contains("study standing: 6 random pallets from seed 0, wrap none, 2-3 layers"),
             r.out.constData());
    QVERIFY2(r.out.contains("rule: stands") && r.out.contains("rule: cannot stand"),
             r.out.constData());
    Run bad = lab({QStringLiteral("study"), QStringLiteral("standing"), QStringLiteral("--hold"),
                   QStringLiteral("-1")});
    QCOMPARE(bad.exit_code, 2);
    QVERIFY2(bad.err.contains("--hold must be 0 to 30 seconds"), bad.err.constData());
  }
};

QTEST_GUILESS_MAIN(StandingLabTest)
#include "standing_lab_test.moc"
