// SPDX-License-Identifier: MIT
// The unwrapped agreement corpus (docs/studies/unwrapped-corpus): the shipped default against the
// reference configuration on the three small unwrapped curated scenarios, frozen-pallet-jerk-start
// and 20 random unwrapped pallets (column, brick, pinwheel; 2-6 layers), limit by limit. The
// reference envelopes are committed (reference-cache/), so a run costs the default's envelopes
// only (about two minutes on 2 cores). Pinned at what was measured when a sliding pair began to
// slide by explicit Coulomb friction and the search to check a load below its pallet's slip onset
// (session 17, core/physics/step.hpp; every reference recomputed): 93 of the 96 limits (96.9 %)
// within one search step, none more than one step above the reference. Before (MuJoCo's cone
// for sliding pairs, whose sliding pallets hop on their belts, session 15): 88 / 96, 0 above;
// with the softer contacts: 89 / 96, 1 above (asymmetric-load's stop, +1.94); with Coulomb
// friction and curves that did not turn (session 14): 86 / 96, 1 above; before friction changed:
// 91 / 96, 0 above. Labelled long.
#include <QDir>
#include <QDirIterator>
#include <QJsonArray>
#include <QJsonObject>
#include <QtTest>

#include "../cli/cli_runner.hpp"

using pb::test::cli;

class AgreementCorpusLabTest : public QObject {
  Q_OBJECT

 private slots:
  void defaultAgreesWithTheReferenceLimitByLimit() {
    const QString corpus = QStringLiteral(PB_SOURCE_DIR "/docs/studies/unwrapped-corpus");
    QTemporaryDir out;
    QVERIFY(QDir().mkpath(out.filePath("reference-cache")));
    QDirIterator cached(corpus + "/reference-cache", {"*.json"}, QDir::Files);
    while (cached.hasNext()) {
      const QString from = cached.next();
      QVERIFY(QFile::copy(from, out.filePath("reference-cache/" + QFileInfo(from).fileName())));
    }
    QStringList pallets{"tall-unwrapped-tower", "top-heavy-surprise", "asymmetric-load",
                        "frozen-pallet-jerk-start"};
    QDirIterator files(corpus + "/pallets", {"*.json"}, QDir::Files);
    QStringList corpus_files;
    while (files.hasNext()) corpus_files << files.next();
    corpus_files.sort();
    QCOMPARE(corpus_files.size(), 20);
    // The cache is keyed by the pallet's label as given: the paths the corpus was run with.
    for (const QString& f : corpus_files) {
      pallets << "docs/studies/unwrapped-corpus/pallets/" + QFileInfo(f).fileName();
    }
    QProcess p;
    p.setWorkingDirectory(QStringLiteral(PB_SOURCE_DIR));
    p.setProgram(QStringLiteral(PB_BIN_DIR "/palletballet-lab"));
    p.setArguments({"study", "speed-accuracy", "--pallets", pallets.join(','), "--corpus", "0",
                    "--configs", "default", "--out", out.path(), "--json"});
    p.start();
    QVERIFY(p.waitForFinished(1500000));
    QCOMPARE(p.exitCode(), 0);
    const QByteArray err = p.readAllStandardError();
    QVERIFY2(err.count("(cached)") == 24, err);  // no reference was recomputed
    const QJsonArray rows = QJsonDocument::fromJson(p.readAllStandardOutput()).array();
    QJsonObject def;
    for (const QJsonValue& v : rows) {
      if (v.toObject().value("config").toString() == "default") def = v.toObject();
    }
    QCOMPARE(def.value("pallets").toInt(), 24);
    const double within = def.value("limits_within_one_step").toDouble();
    const int above = def.value("limits_above").toInt();
    qInfo("limits within one step %.1f %%, more than one step above the reference: %d",
          100.0 * within, above);
    QVERIFY2(within >= 0.96, qPrintable(QString::number(within)));
    QVERIFY2(above == 0, qPrintable(QString::number(above)));
  }
};

QTEST_APPLESS_MAIN(AgreementCorpusLabTest)
#include "agreement_corpus_lab_test.moc"
