// SPDX-License-Identifier: MIT
// End-to-end runs of `palletballet-lab study`: speed-accuracy on one two-carton pallet (the table,
// the JSON, the CSV, the PNG and the reference cache), stability on cheap cases, and the reference
// configuration's convergence on one small curated scenario. Labelled long: the reference runs at
// 0.5 and 0.25 ms with plain bisection at half steps.
#include <QDir>
#include <QFileInfo>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QTemporaryDir>
#include <QtTest>

#include "../cli/cli_runner.hpp"

namespace {

using pb::test::lab;
using pb::test::read_file;
using pb::test::Run;
using pb::test::write_file;

// Two 6 kg cartons side by side on an EUR pallet: the cheapest pallet worth simulating.
QByteArray two_cartons() {
  return R"({"pallet_id": "two-cartons", "base_pallet_type": "EUR", "base_dims_m": [1.2, 0.8, 0.15],
  "base_mass_kg": 25.0, "wrap": "none", "env": "refrigerated", "body_temp_c": 2.0,
  "items": [
   {"sku": "SKU-FD-002", "dims_m": [0.35, 0.25, 0.12], "weight_kg": 6.0,
    "position": [-0.2, 0.0, 0.15], "orientation_deg": 0.0, "fragility": "rigid"},
   {"sku": "SKU-FD-002", "dims_m": [0.35, 0.25, 0.12], "weight_kg": 6.0,
    "position": [0.2, 0.0, 0.15], "orientation_deg": 0.0, "fragility": "rigid"}]})";
}

// The convergence test's scenarios: one that moves as one body (wrapped) and the smallest
// unwrapped one (6 cartons).
constexpr const char* kConvergenceScenarios = "stable-dairy-slab,asymmetric-load";

// lab() with a longer patience: the reference at 0.25 ms takes minutes on a loaded machine.
Run slow_lab(const QStringList& args) {
  return lab(args, {}, 1200000);
}

QJsonObject by_config(const QJsonArray& rows, const QString& name) {
  for (const auto& r : rows) {
    if (r.toObject().value(QStringLiteral("config")).toString() == name) return r.toObject();
  }
  return {};
}

}  // namespace

class StudyLabTest : public QObject {
  Q_OBJECT

 private slots:
  void badArgumentsAreUsageErrors() {
    Run r = lab({QStringLiteral("study"), QStringLiteral("fast-and-loose")});
    QCOMPARE(r.exit_code, 2);
    QVERIFY2(r.err.contains("speed-accuracy"), r.err.constData());
    r = lab({QStringLiteral("study"), QStringLiteral("speed-accuracy"), QStringLiteral("--configs"),
             QStringLiteral("default,warp-speed"), QStringLiteral("--corpus"),
             QStringLiteral("0")});
    QCOMPARE(r.exit_code, 2);
    QVERIFY2(r.err.contains("warp-speed") && r.err.contains("reduced-2ms"), r.err.constData());
    r = lab({QStringLiteral("study"), QStringLiteral("stability"), QStringLiteral("--cases"),
             QStringLiteral("dt-1000ms")});
    QCOMPARE(r.exit_code, 2);
    QVERIFY2(r.err.contains("dt-1000ms") && r.err.contains("euler-kv-4"), r.err.constData());
    r = lab({QStringLiteral("study"), QStringLiteral("speed-accuracy"), QStringLiteral("--pallets"),
             QStringLiteral("none"), QStringLiteral("--corpus"), QStringLiteral("0")});
    QCOMPARE(r.exit_code, 2);
    QVERIFY2(r.err.contains("corpus is empty"), r.err.constData());
  }

  void speedAccuracyWritesTableCsvChartAndCachesTheReference() {
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    const QString pallet = write_file(dir, QStringLiteral("two.json"), two_cartons());
    const QString out = dir.filePath(QStringLiteral("out"));
    const QStringList args = {QStringLiteral("study"),     QStringLiteral("speed-accuracy"),
                              QStringLiteral("--pallets"), pallet,
                              QStringLiteral("--corpus"),  QStringLiteral("0"),
                              QStringLiteral("--configs"), QStringLiteral("default,closed-form"),
                              QStringLiteral("--out"),     out,
                              QStringLiteral("--json")};
    Run r = lab(args);
    QVERIFY2(r.exit_code == 0, r.err.constData());
    QVERIFY2(r.err.contains("from the cache: 0"), r.err.constData());
    const QJsonArray rows = r.json().array();
    QCOMPARE(rows.size(), 3);  // the reference is always run
    for (const auto& v : rows) {
      const QJsonObject o = v.toObject();
      for (const char* key : {"config", "median_ms", "within_one_step", "is_default",
                              "is_reference_equivalent", "worst_error_steps", "pareto"}) {
        QVERIFY2(o.contains(QLatin1String(key)), key);
      }
      QCOMPARE(o.value(QStringLiteral("pallets")).toInt(), 1);
      QCOMPARE(o.value(QStringLiteral("errors")).toInt(), 0);
    }
    const QJsonObject ref = by_config(rows, QStringLiteral("reference"));
    QCOMPARE(ref.value(QStringLiteral("within_one_step")).toDouble(), 1.0);
    QVERIFY(ref.value(QStringLiteral("median_ms")).toDouble() > 0.0);
    const QJsonObject def = by_config(rows, QStringLiteral("default"));
    QVERIFY(def.value(QStringLiteral("is_default")).toBool());
    QVERIFY(!def.value(QStringLiteral("is_reference_equivalent")).toBool());
    // The closed form alone is a bound, not a measurement: it answers in microseconds.
    const QJsonObject closed = by_config(rows, QStringLiteral("closed-form"));
    QVERIFY(closed.value(QStringLiteral("median_ms")).toDouble() <
            def.value(QStringLiteral("median_ms")).toDouble());

    const QByteArray csv = read_file(QDir(out).filePath(QStringLiteral("speed_accuracy.csv")));
    QVERIFY(csv.startsWith("config,"));
    QCOMPARE(csv.count('\n'), 4);
    const QByteArray samples =
        read_file(QDir(out).filePath(QStringLiteral("speed_accuracy_samples.csv")));
    QCOMPARE(samples.count('\n'), 4);
    if (r.err.contains("speed_accuracy.png")) {
      const QByteArray png = read_file(QDir(out).filePath(QStringLiteral("speed_accuracy.png")));
      QVERIFY(png.startsWith("\x89PNG"));
      QVERIFY(png.size() > 10000);
    } else {
      QVERIFY2(r.err.contains("PB_BUILD_UI=OFF"), r.err.constData());
    }

    // A rerun takes the reference from the cache, and the table says the same.
    Run again = lab(args);
    QVERIFY2(again.exit_code == 0, again.err.constData());
    QVERIFY2(again.err.contains("from the cache: 1"), again.err.constData());
    const QJsonObject ref2 = by_config(again.json().array(), QStringLiteral("reference"));
    QCOMPARE(ref2.value(QStringLiteral("median_ms")).toDouble(),
             ref.value(QStringLiteral("median_ms")).toDouble());
    const QJsonObject def2 = by_config(again.json().array(), QStringLiteral("default"));
    QCOMPARE(def2.value(QStringLiteral("within_one_step")).toDouble(),
             def.value(QStringLiteral("within_one_step")).toDouble());

    Run table = lab(QStringList(args.begin(), args.end() - 1));
    QVERIFY2(table.exit_code == 0, table.err.constData());
    QVERIFY(table.out.contains("reference (R)"));
    QVERIFY(table.out.contains("default (D)"));
  }

  void stabilityClassifiesEachCase() {
    Run r = lab({QStringLiteral("study"), QStringLiteral("stability"), QStringLiteral("--cases"),
                 QStringLiteral("euler-kv-4,dt-2ms-carton,nconmax-2"), QStringLiteral("--json")});
    QVERIFY2(r.exit_code == 0, r.err.constData());
    const QJsonArray rows = r.json().array();
    QCOMPARE(rows.size(), 3);
    QCOMPARE(rows[0].toObject().value(QStringLiteral("classification")).toString(),
             QStringLiteral("detected unstable"));
    QCOMPARE(rows[1].toObject().value(QStringLiteral("classification")).toString(),
             QStringLiteral("correct"));
    QCOMPARE(rows[2].toObject().value(QStringLiteral("classification")).toString(),
             QStringLiteral("detected unstable"));
    for (const auto& v : rows)
      QVERIFY(!v.toObject().value(QStringLiteral("missing_guard")).toBool());
  }

  // The reference configuration converges: halving its timestep (0.5 -> 0.25 ms) moves no limit
  // of a load that moves as one by more than one of its search steps (half the shipped ones). A
  // load whose items can move converges to one shipped step only: with Coulomb friction an item
  // held between its mu_d g and mu_s g slides when its carrier's rocking breaks it loose, which
  // the timestep changes (asymmetric-load: 1.53, 0.77, 1.53 and 0 reference steps; session 14,
  // core/README "Friction"). It converged to one reference step with a single coefficient.
  void referenceConvergesOnSmallCuratedScenarios() {
    Run r = slow_lab({QStringLiteral("study"), QStringLiteral("convergence"),
                      QStringLiteral("--pallets"), QString::fromLatin1(kConvergenceScenarios),
                      QStringLiteral("--json")});
    QVERIFY2(r.exit_code == 0 || r.exit_code == 1, (r.err + r.out).constData());
    const QJsonArray rows = r.json().array();
    QCOMPARE(rows.size(), 2);
    const QJsonObject wrapped = rows[0].toObject();
    QVERIFY2(wrapped.value(QStringLiteral("within_one_step")).toBool(), r.out.constData());
    QVERIFY(wrapped.value(QStringLiteral("worst_steps")).toDouble() <= 1.0 + 1e-6);
    const QJsonObject loose = rows[1].toObject();
    QVERIFY2(loose.value(QStringLiteral("worst_steps")).toDouble() <= 2.0 + 1e-6,
             r.out.constData());
  }
};

QTEST_GUILESS_MAIN(StudyLabTest)
#include "study_lab_test.moc"
