// SPDX-License-Identifier: MIT
// The unwrapped agreement corpus (docs/studies/unwrapped-corpus): the shipped default against the
// reference configuration on the three small unwrapped curated scenarios, frozen-pallet-jerk-start
// and 20 random unwrapped pallets (column, brick, pinwheel; 2-6 layers), limit by limit. The
// reference envelopes are committed (reference-cache/), so a run costs the default's envelopes
// only (about two minutes on 2 cores). Pinned at what was measured when the full model's timestep
// became 1.5 ms (session 30, core/README.md "Timestep of the full model"): 93 of the 96 limits
// (96.9 %) within one search step, none more than one step above the reference (the third miss,
// u2008's start-up and stop, 1.6 and 2.0 steps below). At 1 ms, when the friction cone became
// Coulomb's circle (session 28; every reference recomputed in it): 94 / 96, 0 above. Before, in
// MuJoCo's pyramid against a pyramidal judge: 93 / 96, 0 above (session
// 17, sliding by explicit Coulomb friction); with MuJoCo's cone for sliding pairs (session 15):
// 88 / 96, 0 above; with the softer contacts: 89 / 96, 1 above; with Coulomb friction and curves
// that did not turn (session 14): 86 / 96, 1 above; before friction changed: 91 / 96, 0 above.
// And two hold-out sets, which the corpus's choices were not tuned on. Labelled long.
#include <QDir>
#include <QDirIterator>
#include <QJsonArray>
#include <QJsonObject>
#include <QtTest>

#include "../cli/cli_runner.hpp"

using pb::test::cli;

namespace {

// The shipped default's row of `study speed-accuracy` over `curated` and the pallets of
// docs/studies/<set>/pallets, judged against that set's committed reference envelopes (none
// recomputed).
QJsonObject default_against_references(const QString& set, QStringList pallets,
                                       qsizetype files_expected) {
  const QString dir = QStringLiteral(PB_SOURCE_DIR "/docs/studies/") + set;
  QTemporaryDir out;
  if (!QDir().mkpath(out.filePath("reference-cache"))) return {};
  QDirIterator cached(dir + "/reference-cache", {"*.json"}, QDir::Files);
  while (cached.hasNext()) {
    const QString from = cached.next();
    if (!QFile::copy(from, out.filePath("reference-cache/" + QFileInfo(from).fileName())))
      return {};
  }
  QDirIterator files(dir + "/pallets", {"*.json"}, QDir::Files);
  QStringList set_files;
  while (files.hasNext()) set_files << files.next();
  set_files.sort();
  if (set_files.size() != files_expected) return {};
  // The cache is keyed by the pallet's label as given: the paths the set was run with.
  for (const QString& f : set_files) {
    pallets << "docs/studies/" + set + "/pallets/" + QFileInfo(f).fileName();
  }
  QProcess p;
  p.setWorkingDirectory(QStringLiteral(PB_SOURCE_DIR));
  p.setProgram(QStringLiteral(PB_BIN_DIR "/palletballet-lab"));
  p.setArguments({"study", "speed-accuracy", "--pallets", pallets.join(','), "--corpus", "0",
                  "--configs", "default", "--out", out.path(), "--json"});
  p.start();
  if (!p.waitForFinished(1500000) || p.exitCode() != 0) return {};
  const QByteArray err = p.readAllStandardError();
  if (err.count("(cached)") != pallets.size()) {  // a reference was recomputed
    qWarning("%s", err.constData());
    return {};
  }
  const QJsonArray rows = QJsonDocument::fromJson(p.readAllStandardOutput()).array();
  for (const QJsonValue& v : rows) {
    if (v.toObject().value("config").toString() == "default") return v.toObject();
  }
  return {};
}

// Of the default's row: at least `min_within` of its limits within one search step of the
// reference, none more than one step above it.
void check_agreement(const QJsonObject& def, int pallets, double min_within) {
  QCOMPARE(def.value("pallets").toInt(), pallets);
  const double within = def.value("limits_within_one_step").toDouble();
  const int above = def.value("limits_above").toInt();
  qInfo("limits within one step %.1f %%, more than one step above the reference: %d",
        100.0 * within, above);
  QVERIFY2(within >= min_within, qPrintable(QString::number(within)));
  QVERIFY2(above == 0, qPrintable(QString::number(above)));
}

}  // namespace

class AgreementCorpusLabTest : public QObject {
  Q_OBJECT

 private slots:
  void defaultAgreesWithTheReferenceLimitByLimit() {
    const QJsonObject def =
        default_against_references("unwrapped-corpus",
                                   {"tall-unwrapped-tower", "top-heavy-surprise", "asymmetric-load",
                                    "frozen-pallet-jerk-start"},
                                   20);
    check_agreement(def, 24, 0.96);
  }

  // The hold-out set (docs/studies/unwrapped-holdout): 21 pallets drawn as the corpus was and
  // judged once, not tuned on. Pinned at session 28's 82 of 84 limits (97.6 %) within one step
  // and none above the reference (in the pyramid: session 21's 77 / 84, 0 above; before its two
  // fixes 75 / 84, 3 above).
  void holdOutHasNoLimitAboveTheReference() {
    const QJsonObject def = default_against_references("unwrapped-holdout", {}, 21);
    check_agreement(def, 21, 0.97);
  }
  // A second hold-out set (docs/studies/unwrapped-holdout-2, session 42): 21 pallets drawn as the
  // first was from seeds 4000-4051, judged once with nothing changed after. Pinned at that run's
  // 80 of 84 limits (95.2 %) within one step and none above; the four misses are conservative
  // (two start-ups and stops that fail in the band just above the pallet's slip onset: see its
  // README).
  void secondHoldOutHasNoLimitAboveTheReference() {
    const QJsonObject def = default_against_references("unwrapped-holdout-2", {}, 21);
    check_agreement(def, 21, 0.95);
  }
};

QTEST_APPLESS_MAIN(AgreementCorpusLabTest)
#include "agreement_corpus_lab_test.moc"
