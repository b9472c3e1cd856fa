// SPDX-License-Identifier: MIT
// --fidelity on analyze, solve and bench: the level reaches the analyzer (reported back), a bad
// value exits 2 naming the flag and the choices; and solve reports the steps it skipped.
#include <QJsonArray>
#include <QJsonObject>
#include <QtTest>

#include "cli_runner.hpp"

using pb::test::cli;
using pb::test::Run;

class FidelityFlagTest : public QObject {
  Q_OBJECT

 private slots:
  void analyzeReportsTheRequestedLevel() {
    // closed_form runs no simulation; full is what an unwrapped pallet gets anyway.
    Run closed = cli({"analyze", "stable-dairy-slab", "--fidelity", "closed_form"});
    QVERIFY2(closed.exit_code == 0, closed.err.constData());
    const QJsonObject c = closed.json().array()[0].toObject();
    QCOMPARE(c.value("fidelity").toString(), QString("closed_form"));
    QCOMPARE(c.value("sims_run").toInt(), 0);
  }

  void badValueExitsTwo_data() {
    QTest::addColumn<QString>("verb");
    QTest::newRow("analyze") << "analyze";
    QTest::newRow("solve") << "solve";
    QTest::newRow("bench") << "bench";
  }
  void badValueExitsTwo() {
    QFETCH(QString, verb);
    QStringList args = {verb};
    if (verb != "bench") args << "stable-dairy-slab";
    args << "--fidelity"
         << "fastest";
    Run r = cli(args);
    QCOMPARE(r.exit_code, 2);
    // solve lists only the levels that simulate (closed_form has no run to show).
    const char* levels = verb == "solve" ? "auto, reduced, clustered or full"
                                         : "auto, closed_form, reduced, clustered or full";
    QVERIFY2(r.err.contains(QByteArray("--fidelity must be one of ") + levels), r.err.constData());
    QVERIFY(r.err.contains("'fastest'"));
    QVERIFY(r.out.isEmpty());
  }

  void solveNeedsASimulation() {
    Run r = cli({"solve", "stable-dairy-slab", "--fidelity", "closed_form"});
    QCOMPARE(r.exit_code, 2);
    QVERIFY2(r.err.contains("--fidelity closed_form"), r.err.constData());
  }

  // The suggested profile of the dairy slab is a ramp and a hold: the steady ramp is jumped.
  void solveReportsSkippedSteps() {
    Run r = cli({"solve", "stable-dairy-slab", "--fidelity", "full"});
    QVERIFY2(r.exit_code == 0, r.err.constData());
    const QJsonObject o = r.json().object();
    const int steps = o.value("steps").toInt(), skipped = o.value("steps_skipped").toInt();
    QVERIFY(skipped > 0 && skipped < steps);
    // The full model steps at its own 1.5 ms (AnalyzerOptions::full_model_timestep_s).
    QCOMPARE(o.value("timestep_s").toDouble(), 0.0015);
    QVERIFY(std::abs(o.value("skipped_s").toDouble() - skipped * 0.0015) < 1e-9);
  }
};

QTEST_APPLESS_MAIN(FidelityFlagTest)
#include "fidelity_flag_test.moc"
