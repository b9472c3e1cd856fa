// SPDX-License-Identifier: MIT
// --parallel-probes on analyze: k-section (k probes a round, batched) gives the same envelope as
// serial bisection with more simulations; a bad value exits 2 naming the flag.
#include <QJsonArray>
#include <QJsonObject>
#include <QtTest>

#include "cli_runner.hpp"

using pb::test::cli;
using pb::test::Run;

class ParallelProbesFlagTest : public QObject {
  Q_OBJECT

 private slots:
  // Frozen meat sprint: the limits of each axis are bracketed (half a second of simulation).
  void sameEnvelopeAsBisection() {
    Run serial = cli({"analyze", "frozen-meat-sprint", "--parallel-probes", "1", "--probes"});
    Run parallel = cli({"analyze", "frozen-meat-sprint", "--parallel-probes", "2", "--probes"});
    QVERIFY2(serial.exit_code == 0, serial.err.constData());
    QVERIFY2(parallel.exit_code == 0, parallel.err.constData());
    const QJsonObject a = serial.json().array()[0].toObject();
    const QJsonObject b = parallel.json().array()[0].toObject();
    for (const char* key : {"verdict", "max_speed_mps", "max_accel_mps2", "max_decel_mps2",
                            "max_lateral_g", "accel_mode", "decel_mode", "lateral_mode",
                            "speed_mode", "dominant_failure_mode", "margin_pct", "reason"}) {
      QVERIFY2(a.value(key) == b.value(key), key);
    }
    // Every probe is listed and counted; each start-up probe failed exactly when it was above
    // the limit (failure is monotone here).
    const QJsonArray probes = b.value("probes").toArray();
    QCOMPARE(b.value("sims_run").toInt(), int(probes.size()));
    QVERIFY(probes.size() >= a.value("probes").toArray().size());
    const double limit = b.value("max_accel_mps2").toDouble();
    int accel_probes = 0;
    for (const auto& value : probes) {
      const QJsonObject p = value.toObject();
      if (p["axis"].toString() != "accel") continue;
      ++accel_probes;
      QCOMPARE(p["outcome"].toString() == "failed", p["value"].toDouble() > limit);
    }
    QVERIFY(accel_probes >= 3);
  }

  void badValueExitsTwo() {
    for (const char* value : {"-1", "65", "1.5"}) {
      Run r = cli({"analyze", "frozen-meat-sprint", "--parallel-probes", value});
      QCOMPARE(r.exit_code, 2);
      QVERIFY2(r.err.contains("--parallel-probes"), r.err.constData());
      QVERIFY(r.out.isEmpty());
    }
  }
};

QTEST_APPLESS_MAIN(ParallelProbesFlagTest)
#include "parallel_probes_flag_test.moc"
