// SPDX-License-Identifier: MIT
// `palletballet-cli bench`'s side tables: the reference system's search beside ours, `bench scale`
// (unwrapped pallets in child processes) and `bench batch` (the scaling table), with their bad
// input. Tiny sizes: this checks the verb, never a timing.
#include <QJsonArray>
#include <QJsonObject>
#include <QtTest>

#include "cli_runner.hpp"

using pb::test::cli;
using pb::test::Run;

namespace {

double num(const QJsonObject& o, const char* key) {
  return o.value(QLatin1String(key)).toDouble();
}

// `args` refused as bad usage (exit 2), saying `says` on stderr.
void refused(const QStringList& args, const char* says) {
  const Run r = cli(args);
  QCOMPARE(r.exit_code, 2);
  QVERIFY2(r.err.contains(says), r.err.constData());
}

}  // namespace

class BenchCliTest : public QObject {
  Q_OBJECT

 private slots:
  // The reference system's search (core/analysis/reference_search.hpp) runs after ours on the same
  // pallet: its median wall time and the ratio to our envelope's, as positive numbers.
  void referenceColumns() {
    Run r = cli({"bench", "--scenario", "stable-dairy-slab", "--runs", "1", "--json"});
    QVERIFY2(r.exit_code == 0, r.err.constData());
    const QJsonArray rows = r.json().array();
    QCOMPARE(rows.size(), 1);
    const QJsonObject o = rows[0].toObject();
    QVERIFY(o.value("ref_ms").isDouble() && o.value("ratio").isDouble());
    QVERIFY(num(o, "ref_ms") > 0.0);
    QVERIFY(num(o, "ratio") > 0.0);
    QVERIFY(o.value("ref_sims").toInt() >= 2);  // the top of each axis at least
  }

  // bench scale: one unwrapped column pallet of about 24 cases, analysed in a child process whose
  // peak resident memory is the row's.
  void scaleJson() {
    Run r =
        cli({"bench", "scale", "--sizes", "24", "--patterns", "column", "--runs", "1", "--json"});
    QVERIFY2(r.exit_code == 0, r.err.constData());
    const QJsonArray rows = r.json().array();
    QCOMPARE(rows.size(), 1);
    const QJsonObject o = rows[0].toObject();
    QVERIFY2(!o.contains("error"), qPrintable(o.value("error").toString()));
    QCOMPARE(o.value("pattern").toString(), QString("column"));
    const int items = o.value("items").toInt();
    QVERIFY2(items >= 20 && items <= 28, qPrintable(QString::number(items)));
    // Six a free carton, the belt's two and the pallet's six at most (fewer if items merge).
    const int dofs = o.value("dofs").toInt();
    QVERIFY(dofs > 0 && dofs <= 6 * items + 8);
    QVERIFY(o.value("contacts").toInt() >= 4 * items);  // every carton rests on a face
    QVERIFY(num(o, "peak_rss_mb") > 0.0);
    QVERIFY(num(o, "us_per_step") > 0.0 && num(o, "envelope_ms") > 0.0);
    QVERIFY(o.value("sims").toInt() > 0);
    // Every probe steps at least once (the steps a jump skips are not counted).
    QVERIFY2(o.value("steps").toInteger() >= o.value("sims").toInt(),
             qPrintable(QString::number(o.value("steps").toInteger())));
    // Twelve two-high columns, 4 along X x 3 across: the searches along the belt simulate one row
    // of each; the curves every item (a curve turns the load: copies along X are not alike).
    QCOMPARE(o.value("searched_items_along").toInt(), items / 3);
    QCOMPARE(o.value("searched_items_across").toInt(), items);
  }

  // bench scale --pallets: the caller's pallets (a file, a curated slug) instead of the recipe, a
  // row each named by its argument; one that cannot be read is a row with its error, and the rest
  // are still measured (exit 1).
  void scalePallets() {
    Run r =
        cli({"bench", "scale", "--pallets", "tall-unwrapped-tower,no-such-pallet.json", "--json"});
    QCOMPARE(r.exit_code, 1);
    const QJsonArray rows = r.json().array();
    QCOMPARE(rows.size(), 2);
    const QJsonObject tower = rows[0].toObject();
    QVERIFY2(!tower.contains("error"), qPrintable(tower.value("error").toString()));
    QCOMPARE(tower.value("pallet").toString(), QString("tall-unwrapped-tower"));
    QCOMPARE(tower.value("items").toInt(), 8);
    QVERIFY(tower.value("sims").toInt() > 0 && num(tower, "envelope_ms") > 0.0);
    const QJsonObject missing = rows[1].toObject();
    QCOMPARE(missing.value("pallet").toString(), QString("no-such-pallet.json"));
    QVERIFY2(missing.value("error").toString().startsWith("cannot open 'no-such-pallet.json'"),
             qPrintable(missing.value("error").toString()));
    refused({"bench", "scale", "--pallets", "tall-unwrapped-tower", "--sizes", "24"},
            "--sizes and --pallets exclude each other");
    refused({"bench", "scale", "--pallets", ","}, "--pallets takes pallet files or curated slugs");
  }

  void scaleBadInput() {
    refused({"bench", "scale", "--sizes", "25"}, "multiples of 12");
    refused({"bench", "scale", "--patterns", "pinwheel"}, "--patterns takes column and brick");
    refused({"bench", "--sizes", "24"}, "--sizes belongs to 'bench scale'");
  }

  void batchJson() {
    Run r = cli({"bench", "batch", "--sims", "4", "--steps", "10", "--runs", "1", "--threads",
                 "1,2", "--nstep", "1,5", "--json"});
    QVERIFY2(r.exit_code == 0, r.err.constData());
    const QJsonArray rows = r.json().array();
    QCOMPARE(rows.size(), 5);  // serial, then threads x nstep
    const QJsonObject serial = rows[0].toObject();
    QCOMPARE(serial.value("mode").toString(), QString("serial"));
    QCOMPARE(serial.value("speedup_vs_serial").toDouble(), 1.0);
    const int expected[4][2] = {{1, 1}, {1, 5}, {2, 1}, {2, 5}};
    for (int k = 0; k < 4; ++k) {
      const QJsonObject o = rows[k + 1].toObject();
      QCOMPARE(o.value("mode").toString(), QString("batch"));
      QCOMPARE(o.value("threads").toInt(), expected[k][0]);
      QCOMPARE(o.value("nstep").toInt(), expected[k][1]);
    }
    for (const auto& row : rows) {
      const QJsonObject o = row.toObject();
      QVERIFY(o.value("steps_per_s").toDouble() > 0.0);
      QVERIFY(o.value("steps_per_cpu_s").toDouble() > 0.0);
      QCOMPARE(o.value("sims").toInt(), 4);
      QCOMPARE(o.value("scenario").toString(), QString("stable-dairy-slab"));
      QVERIFY(o.value("same_result_as_serial").toBool());  // bitwise where the serial loop ended
    }
  }

  void batchTable() {
    Run r = cli({"bench", "batch", "--sims", "2", "--steps", "4", "--runs", "1", "--threads", "2",
                 "--nstep", "2", "--scenario", "top-heavy-surprise"});
    QVERIFY2(r.exit_code == 0, r.err.constData());
    const QList<QByteArray> lines = r.out.trimmed().split('\n');
    QCOMPARE(lines.size(), 4);  // title, header, serial, one batch row
    QVERIFY(lines[0].startsWith("scenario top-heavy-surprise, 2 simulations x 4 steps"));
    QVERIFY(lines[1].startsWith("mode "));
    QVERIFY(lines[2].startsWith("serial "));
    QVERIFY(lines[3].startsWith("batch "));
    QVERIFY(lines[3].endsWith("yes"));
  }

  void batchBadInput() {
    refused({"bench", "batch", "--steps", "10", "--nstep", "3"},
            "--steps (10) must be a multiple of every --nstep");
    refused({"bench", "batch", "--threads", "0"}, "--threads takes whole numbers from 1 to 256");
    refused({"bench", "batch", "--sims", "0"}, "--sims must be between 1 and 100000");
    refused({"bench", "batch", "--scenario", "nope"}, "no curated scenario 'nope'");
    refused({"bench", "sideways"}, "the sub-benchmarks are 'batch' and 'scale'");
    refused({"bench", "--sims", "4"}, "--sims belongs to 'bench batch'");
  }
};

QTEST_GUILESS_MAIN(BenchCliTest)
#include "bench_cli_test.moc"
