// SPDX-License-Identifier: MIT
// PalletDocument: every edit kind undoes and redoes exactly, a drag is one undo step, save and
// open round-trip byte for byte, a failed save leaves the old file, bad files are refused with
// pointers and never cost the current document; recent files and the file actions.
#include <sys/resource.h>
#include <QDir>
#include <QFile>
#include <QMenu>
#include <QSignalSpy>
#include <QTemporaryDir>
#include <QTest>
#include <csignal>
#include <functional>

#include "core/contract/json_io.hpp"
#include "core/contract/pallet_metrics.hpp"
#include "core/contract/pallet_type.hpp"
#include "core/inputs/catalog.hpp"
#include "core/inputs/scenario.hpp"
#include "core/inputs/validation.hpp"
#include "ui/models/pallet_document.hpp"
#include "ui/models/recent_files.hpp"
#include "ui/models/stack_builder_model.hpp"
#include "ui/widgets/file_actions.hpp"

using pb::ui::FileActions;
using pb::ui::PalletDocument;
using pb::ui::RecentFiles;

namespace {

pb::Scenario scenario(const char* slug) {
  auto s = pb::load_scenario(slug);
  if (!s) qFatal("curated scenario %s is missing", slug);
  return *s;
}

QByteArray read_all(const QString& path) {
  QFile f(path);
  if (!f.open(QIODevice::ReadOnly)) return {};
  return f.readAll();
}

bool write_all(const QString& path, const QByteArray& bytes) {
  QFile f(path);
  return f.open(QIODevice::WriteOnly) && f.write(bytes) == bytes.size();
}

const QString kSku = QStringLiteral("SKU-FM-001");  // 0.40 x 0.30 x 0.20 m, 10.5 kg

// `pallet` written to a file of its own and opened in `doc`: what File > Open gives.
pb::ui::FileOutcome open_written(PalletDocument& doc, const pb::PalletConfig& pallet) {
  QTemporaryDir dir;
  const QString path = dir.filePath(QStringLiteral("pallet.json"));
  if (!write_all(path, PalletDocument::serialize(pallet)))
    return {false, {QStringLiteral("cannot write")}};
  return doc.open(path);
}

}  // namespace

class TestPalletDocument : public QObject {
  Q_OBJECT

 private slots:
  void startsEmptyAndValid() {
    PalletDocument doc;
    QVERIFY(doc.pallet().items.empty());
    QCOMPARE(doc.pallet().base_dims_m, pb::pallet_type_spec(pb::PalletType::eur).dims_m);
    QVERIFY(doc.isValid());
    QVERIFY(!doc.isModified());
    QVERIFY(doc.filePath().isEmpty());
    QCOMPARE(doc.windowTitle(), QStringLiteral("Untitled[*] — PalletBallet"));
  }

  // Each edit kind changes the pallet as stated; undo restores the pallet before it exactly and
  // redo the pallet after it; each emits changed() and validated().
  void everyEditUndoesAndRedoes_data() {
    QTest::addColumn<QString>("kind");
    for (const char* kind :
         {"add", "move", "delete", "grow", "shrink", "column", "brick", "pinwheel", "wrap",
          "environment", "temperature", "since", "pallet_type", "replace"}) {
      QTest::newRow(kind) << QString::fromLatin1(kind);
    }
  }
  void everyEditUndoesAndRedoes() {
    QFETCH(QString, kind);
    PalletDocument doc;
    // Start from two stacks so moves, deletes and resizes have something to act on.
    QVERIFY(doc.addStack({-0.4, -0.25}, kSku, 3));
    QVERIFY(doc.addStack({0.4, 0.25}, QStringLiteral("SKU-FM-002"), 2));
    const pb::PalletConfig before = doc.pallet();
    const int steps = doc.undoStack()->count();
    QSignalSpy changed(&doc, &PalletDocument::changed);
    QSignalSpy validated(&doc, &PalletDocument::validated);

    std::function<void(const pb::PalletConfig&)> check;
    const double deck = before.base_dims_m[2];
    if (kind == u"add") {
      QVERIFY(doc.addStack({0.0, 0.25}, kSku, 4));
      check = [&](const pb::PalletConfig& p) {
        QCOMPARE(p.items.size(), before.items.size() + 4);
        for (int level = 0; level < 4; ++level) {
          const pb::Item& item = p.items[before.items.size() + level];
          QCOMPARE(item.sku, kSku.toStdString());
          QCOMPARE(item.position[0], 0.0);
          QCOMPARE(item.position[1], 0.25);
          QVERIFY(qAbs(item.position[2] - (deck + 0.2 * level)) < 1e-12);
        }
      };
    } else if (kind == u"move") {
      QVERIFY(doc.moveStack(0, {0.0, -0.25}));
      check = [&](const pb::PalletConfig& p) {
        for (int k = 0; k < 3; ++k) {
          QCOMPARE(p.items[k].position[0], 0.0);
          QCOMPARE(p.items[k].position[1], -0.25);
          QCOMPARE(p.items[k].position[2], before.items[k].position[2]);
        }
      };
    } else if (kind == u"delete") {
      QVERIFY(doc.deleteStack(0));
      check = [&](const pb::PalletConfig& p) {
        QCOMPARE(p.items.size(), std::size_t{2});
        QCOMPARE(p.items[0].sku, std::string("SKU-FM-002"));
      };
    } else if (kind == u"grow") {
      QVERIFY(doc.resizeStack(1, 5));
      check = [&](const pb::PalletConfig& p) {
        const auto stacks = pb::ui::stacks_of(p);
        QCOMPARE(stacks.size(), std::size_t{2});
        QCOMPARE(stacks[1].height(), 5);
        QVERIFY(qAbs(stacks[1].top_z - (deck + 5 * 0.2)) < 1e-9);
      };
    } else if (kind == u"shrink") {
      QVERIFY(doc.resizeStack(0, 1));
      check = [&](const pb::PalletConfig& p) {
        QCOMPARE(pb::ui::stacks_of(p)[0].height(), 1);
        QCOMPARE(p.items.size(), std::size_t{3});
      };
    } else if (kind == u"column" || kind == u"brick" || kind == u"pinwheel") {
      const auto pattern = *pb::enum_from_string<pb::LayerPattern>(kind.toStdString());
      QStringList why;
      QVERIFY2(doc.applyPreset(pattern, kSku, 3, &why), qPrintable(why.join(u'\n')));
      check = [&](const pb::PalletConfig& p) {
        QVERIFY(p.items.size() >= 3 * 6);
        QCOMPARE(p.items.size() % 3, std::size_t{0});
        QVERIFY(!pb::has_errors(pb::validate(p)));
        QCOMPARE(p.wrap, before.wrap);
        QCOMPARE(p.body_temp_c, before.body_temp_c);
      };
    } else if (kind == u"wrap") {
      QVERIFY(doc.setWrap(pb::WrapType::banded));
      check = [&](const pb::PalletConfig& p) { QCOMPARE(p.wrap, pb::WrapType::banded); };
    } else if (kind == u"environment") {
      QVERIFY(doc.setEnvironment(pb::Environment::frozen));
      check = [&](const pb::PalletConfig& p) { QCOMPARE(p.env, pb::Environment::frozen); };
    } else if (kind == u"temperature") {
      QVERIFY(doc.setBodyTemperature(-18.5));
      check = [&](const pb::PalletConfig& p) { QCOMPARE(p.body_temp_c, -18.5); };
    } else if (kind == u"since") {
      QVERIFY(doc.setSecondsSinceTempChange(120.0));
      check = [&](const pb::PalletConfig& p) { QCOMPARE(p.seconds_since_temp_change, 120.0); };
    } else if (kind == u"pallet_type") {
      QVERIFY(doc.setPalletType(pb::PalletType::gma));
      check = [&](const pb::PalletConfig& p) {
        const auto& spec = pb::pallet_type_spec(pb::PalletType::gma);
        QCOMPARE(p.base_pallet_type, pb::PalletType::gma);
        QCOMPARE(p.base_dims_m, spec.dims_m);
        QCOMPARE(p.base_mass_kg, spec.mass_kg);
        // Items ride on the new deck: the bottom ones stand on it.
        QVERIFY(qAbs(p.items[0].position[2] - spec.dims_m[2]) < 1e-12);
        QCOMPARE(p.items[0].position[0], before.items[0].position[0]);
      };
    } else if (kind == u"replace") {
      pb::PalletConfig other = before;
      other.items.pop_back();
      other.notes = "replaced";
      QVERIFY(doc.replacePallet(other, QStringLiteral("Replace")));
      check = [other](const pb::PalletConfig& p) { QCOMPARE(p, other); };
    }
    const pb::PalletConfig after = doc.pallet();
    QVERIFY(after != before);
    check(after);
    QCOMPARE(doc.undoStack()->count(), steps + 1);
    QCOMPARE(changed.count(), 1);
    QCOMPARE(validated.count(), 1);
    QCOMPARE(changed.last().at(0).value<pb::PalletConfig>(), after);
    QVERIFY(doc.isModified());

    doc.undoStack()->undo();
    QCOMPARE(doc.pallet(), before);
    QCOMPARE(doc.diagnostics(), pb::validate(before));
    doc.undoStack()->redo();
    QCOMPARE(doc.pallet(), after);
    check(doc.pallet());
    QCOMPARE(doc.diagnostics(), pb::validate(after));
    QCOMPARE(changed.count(), 3);
  }

  void impossibleEditsChangeNothing() {
    PalletDocument doc;
    QVERIFY(doc.addStack({0.0, 0.0}, kSku, 2));
    const pb::PalletConfig before = doc.pallet();
    QVERIFY(!doc.addStack({0.0, 0.0}, QStringLiteral("NO-SUCH-SKU"), 2));
    QVERIFY(!doc.addStack({0.4, 0.0}, kSku, 0));
    QVERIFY(!doc.moveStack(1, {0.0, 0.0}));
    QVERIFY(!doc.deleteStack(-1));
    QVERIFY(!doc.resizeStack(0, 0));
    QVERIFY(!doc.setBodyTemperature(qQNaN()));
    QStringList why;
    QVERIFY(!doc.applyPreset(pb::LayerPattern::brick, QStringLiteral("NO-SUCH-SKU"), 3, &why));
    QVERIFY(why.join(u' ').contains(u"/sku"));
    QVERIFY(!doc.applyPreset(pb::LayerPattern::irregular, kSku, 3, &why));
    // A load over the height cap: the core's reason (with its pointer) comes back.
    QVERIFY(!doc.applyPreset(pb::LayerPattern::column, kSku, 12, &why));
    QVERIFY2(!why.isEmpty(), "a refused preset says why");
    QCOMPARE(doc.pallet(), before);
    QCOMPARE(doc.undoStack()->count(), 1);
  }

  // A drag (a dial, a spin box, a stack being dragged) is one undo step; endDrag() ends it.
  void dragMergesIntoOneStep() {
    PalletDocument doc;
    const double start = doc.pallet().body_temp_c;
    for (double t : {1.0, 0.0, -1.0, -2.0, -3.0}) {
      QVERIFY(doc.setBodyTemperature(t, PalletDocument::Edit::drag));
    }
    QCOMPARE(doc.undoStack()->count(), 1);
    QCOMPARE(doc.pallet().body_temp_c, -3.0);
    doc.endDrag();
    QVERIFY(doc.setBodyTemperature(-4.0, PalletDocument::Edit::drag));
    QVERIFY(doc.setBodyTemperature(-5.0, PalletDocument::Edit::drag));
    QCOMPARE(doc.undoStack()->count(), 2);
    doc.undoStack()->undo();
    QCOMPARE(doc.pallet().body_temp_c, -3.0);
    doc.undoStack()->undo();
    QCOMPARE(doc.pallet().body_temp_c, start);

    // Step edits never merge, even of the same field.
    PalletDocument steps;
    QVERIFY(steps.setBodyTemperature(1.0));
    QVERIFY(steps.setBodyTemperature(0.0));
    QCOMPARE(steps.undoStack()->count(), 2);

    // A stack dragged across three cells: one step; another kind of drag starts a new step.
    PalletDocument moves;
    QVERIFY(moves.addStack({-0.4, -0.25}, kSku, 2));
    QVERIFY(moves.moveStack(0, {0.0, -0.25}, PalletDocument::Edit::drag));
    QVERIFY(moves.moveStack(0, {0.4, -0.25}, PalletDocument::Edit::drag));
    QVERIFY(moves.moveStack(0, {0.4, 0.25}, PalletDocument::Edit::drag));
    QCOMPARE(moves.undoStack()->count(), 2);
    QVERIFY(moves.setSecondsSinceTempChange(60.0, PalletDocument::Edit::drag));
    QCOMPARE(moves.undoStack()->count(), 3);
    moves.undoStack()->undo();
    moves.undoStack()->undo();
    QCOMPARE(moves.pallet().items[0].position[0], -0.4);
    QCOMPARE(moves.pallet().items[0].position[1], -0.25);
    // Undo ended the drag: a new drag edit is a new step, not merged into the add.
    QVERIFY(moves.moveStack(0, {0.0, 0.25}, PalletDocument::Edit::drag));
    QCOMPARE(moves.undoStack()->count(), 2);
    moves.undoStack()->undo();
    QCOMPARE(moves.pallet().items.size(), std::size_t{2});

    // A drag back to where it started leaves no step at all.
    PalletDocument back;
    QVERIFY(back.setBodyTemperature(5.0, PalletDocument::Edit::drag));
    QVERIFY(back.setBodyTemperature(2.0, PalletDocument::Edit::drag));
    back.endDrag();
    QCOMPARE(back.undoStack()->count(), 0);
    QVERIFY(!back.isModified());
  }

  void saveOpenRoundTripIsByteIdentical() {
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    PalletDocument doc;
    QVERIFY(doc.loadScenario(scenario("random-scanner-feed")));
    QVERIFY(doc.setBodyTemperature(-7.25));
    QVERIFY(doc.isModified());
    QSignalSpy modified(&doc, &PalletDocument::modifiedChanged);
    QSignalSpy titles(&doc, &PalletDocument::titleChanged);
    const QString first = dir.filePath(QStringLiteral("feed.json"));
    QVERIFY(doc.save().messages.join(u' ').contains(u"Save As"));  // no file yet
    const auto saved = doc.saveAs(first);
    QVERIFY2(saved.ok, qPrintable(saved.messages.join(u'\n')));
    QVERIFY(!doc.isModified());
    QCOMPARE(modified.last().at(0).toBool(), false);
    QCOMPARE(doc.filePath(), QFileInfo(first).absoluteFilePath());
    QCOMPARE(titles.last().at(0).toString(), QStringLiteral("feed.json[*] — PalletBallet"));
    const QByteArray bytes = read_all(first);
    QCOMPARE(bytes, PalletDocument::serialize(doc.pallet()));
    QVERIFY(bytes.endsWith('\n'));

    PalletDocument other;
    const auto opened = other.open(first);
    QVERIFY2(opened.ok, qPrintable(opened.messages.join(u'\n')));
    QCOMPARE(other.pallet(), doc.pallet());
    QVERIFY(!other.isModified());
    QCOMPARE(other.undoStack()->count(), 0);
    const QString second = dir.filePath(QStringLiteral("again.json"));
    QVERIFY(other.saveAs(second).ok);
    QCOMPARE(read_all(second), bytes);
    // Save (not Save As) writes to the document's own file.
    QVERIFY(other.setWrap(pb::WrapType::none));
    QVERIFY(other.save().ok);
    PalletDocument third;
    QVERIFY(third.open(second).ok);
    QCOMPARE(third.pallet().wrap, pb::WrapType::none);
  }

  // QSaveFile: a save that fails part-way leaves the old file as it was (the write is refused
  // here by a file-size limit, which binds root too).
  void failedSaveKeepsTheOldFile() {
    QTemporaryDir dir;
    const QString path = dir.filePath(QStringLiteral("keep.json"));
    PalletDocument doc;
    QVERIFY(doc.addStack({0.0, 0.0}, kSku, 2));
    QVERIFY(doc.saveAs(path).ok);
    const QByteArray old = read_all(path);
    // Far more bytes than the limit (the whole pallet replaced in one edit).
    QVERIFY(doc.replacePallet(scenario("frozen-meat-sprint").pallet, QStringLiteral("Replace")));

    rlimit saved{};
    QCOMPARE(getrlimit(RLIMIT_FSIZE, &saved), 0);
    auto* previous = std::signal(SIGXFSZ, SIG_IGN);
    rlimit tight = saved;
    tight.rlim_cur = 512;
    QCOMPARE(setrlimit(RLIMIT_FSIZE, &tight), 0);
    const auto outcome = doc.save();
    setrlimit(RLIMIT_FSIZE, &saved);
    std::signal(SIGXFSZ, previous);

    QVERIFY2(
        !outcome.ok,
        qPrintable(
            QStringLiteral("saved %1 bytes under a 512-byte limit").arg(QFileInfo(path).size())));
    QVERIFY2(outcome.messages.join(u' ').contains(u"unchanged"),
             qPrintable(outcome.messages.join(u' ')));
    QCOMPARE(read_all(path), old);
    QVERIFY(doc.isModified());  // the edit is still unsaved, and still there
    QCOMPARE(doc.pallet(), scenario("frozen-meat-sprint").pallet);
    QCOMPARE(QDir(dir.path()).entryList(QDir::Files), QStringList{QStringLiteral("keep.json")});

    // A folder that does not exist: a message, no file.
    const auto nowhere = doc.saveAs(dir.filePath(QStringLiteral("no/such/dir/p.json")));
    QVERIFY(!nowhere.ok);
    QVERIFY(nowhere.messages.join(u' ').contains(u"cannot write"));
  }

  // Bad files are refused with the pointer of what is wrong; the current document stays.
  void badFilesGiveMessagesWithPointers_data() {
    QTest::addColumn<QByteArray>("content");
    QTest::addColumn<QString>("expected");
    QTest::newRow("syntax") << QByteArray("{\"items\": [") << QString();
    QTest::newRow("not an object") << QByteArray("[1, 2]") << QStringLiteral("");
    QTest::newRow("missing items") << QByteArray(R"({"env": "frozen", "body_temp_c": -20})")
                                   << QStringLiteral("/items: the required key 'items'");
    QTest::newRow("wrong type") << QByteArray(R"({"items": [], "env": "frozen",
        "body_temp_c": "cold"})")
                                << QStringLiteral("/body_temp_c: ");
    QTest::newRow("unknown wrap") << QByteArray(R"({"items": [], "env": "frozen",
        "body_temp_c": -20, "wrap": "cling"})")
                                  << QStringLiteral("/wrap: ");
    // Never opened as a stretch-wrapped load: the supervisor is told to say which wrap it has.
    QTest::newRow("missing wrap") << QByteArray(R"({"items": [], "env": "frozen",
        "body_temp_c": -20})") << QStringLiteral("/wrap: the required key 'wrap' is missing");
    QTest::newRow("scenario item") << QByteArray(R"({"name": "x", "pallet": {"env": "frozen",
        "body_temp_c": -20, "items": [{"sku": "A", "weight_kg": "heavy"}]}})")
                                   << QStringLiteral("/pallet/items/0/weight_kg: ");
    QTest::newRow("newer schema") << QByteArray(R"({"schema_version": 99, "items": [],
        "env": "frozen", "body_temp_c": -20})")
                                  << QStringLiteral("/schema_version: ");
  }
  void badFilesGiveMessagesWithPointers() {
    QFETCH(QByteArray, content);
    QFETCH(QString, expected);
    QTemporaryDir dir;
    const QString mine = dir.filePath(QStringLiteral("mine.json"));
    const QString bad = dir.filePath(QStringLiteral("bad.json"));
    QVERIFY(write_all(bad, content));
    PalletDocument doc;
    QVERIFY(doc.addStack({0.0, 0.0}, kSku, 2));
    QVERIFY(doc.saveAs(mine).ok);
    QVERIFY(doc.setWrap(pb::WrapType::banded));  // unsaved work
    const pb::PalletConfig before = doc.pallet();
    QSignalSpy changed(&doc, &PalletDocument::changed);

    const auto outcome = doc.open(bad);
    QVERIFY(!outcome.ok);
    QVERIFY(!outcome.messages.isEmpty());
    const QString text = outcome.messages.join(u'\n');
    QVERIFY2(expected.isEmpty() || text.contains(expected), qPrintable(text));
    QCOMPARE(doc.pallet(), before);
    QCOMPARE(doc.filePath(), QFileInfo(mine).absoluteFilePath());
    QVERIFY(doc.isModified());
    QCOMPARE(doc.undoStack()->count(), 2);
    QCOMPARE(changed.count(), 0);

    const auto missing = doc.open(dir.filePath(QStringLiteral("absent.json")));
    QVERIFY(!missing.ok);
    QVERIFY(missing.messages.join(u' ').contains(u"cannot open"));
    QCOMPARE(doc.pallet(), before);
  }

  // A pallet that reads but breaks a physical rule opens, with its findings as messages.
  void physicallyInvalidPalletOpensWithFindings() {
    pb::PalletConfig p;
    p.items.push_back(pb::make_item(*pb::Catalog::builtin().find("SKU-FM-001"), {0, 0, 0.15}));
    p.items.push_back(pb::make_item(*pb::Catalog::builtin().find("SKU-FM-001"), {0.1, 0, 0.15}));
    PalletDocument doc;
    const auto outcome = open_written(doc, p);
    QVERIFY(outcome.ok);
    QVERIFY(!doc.isValid());
    QVERIFY2(outcome.messages.join(u'\n').contains(u"/items/1"),
             qPrintable(outcome.messages.join(u'\n')));
  }

  // Many items with one finding (each twice its SKU's weight) are told once after the first
  // three.
  void manyItemsWithOneFindingAreToldOnce() {
    pb::PalletConfig p;
    const pb::SkuTemplate& sku = *pb::Catalog::builtin().find("SKU-FM-001");
    for (int i = 0; i < 6; ++i) {
      p.items.push_back(pb::make_item(sku, {0, 0, 0.15 + sku.dims_m[2] * i}));
      p.items.back().weight_kg *= 2.0;
    }
    PalletDocument doc;
    const auto outcome = open_written(doc, p);
    QVERIFY(outcome.ok);
    const QString text = outcome.messages.join(u'\n');
    QVERIFY2(text.contains(u"/items/2/weight_kg") && !text.contains(u"/items/3/weight_kg") &&
                 text.contains(u"/items/*/weight_kg: the same for 3 more items: 3-5"),
             qPrintable(text));
  }

  // A scenario file opens as its pallet, with no file to save to (never overwritten).
  void scenarioFileOpensWithoutAPath() {
    const pb::Scenario s = scenario("top-heavy-surprise");
    QTemporaryDir dir;
    const QString path = dir.filePath(QStringLiteral("scenario.json"));
    QVERIFY(write_all(path, QByteArray::fromStdString(pb::scenario_to_json(s).dump(2))));
    PalletDocument doc;
    const auto outcome = doc.open(path);
    QVERIFY2(outcome.ok, qPrintable(outcome.messages.join(u'\n')));
    QCOMPARE(doc.pallet(), s.pallet);
    QVERIFY(doc.filePath().isEmpty());
    QCOMPARE(doc.displayName(), QString::fromStdString(s.name) + QStringLiteral(" (scenario)"));
    QVERIFY(!doc.save().ok);
    QCOMPARE(read_all(path), QByteArray::fromStdString(pb::scenario_to_json(s).dump(2)));
  }

  // A scenario opens as a document of its own, as a file does: named after it, unmodified, no
  // file yet, a fresh undo history (New does not ask to save it; Save asks where).
  void aScenarioOpensAsADocument() {
    PalletDocument doc;
    QVERIFY(doc.addStack({0.0, 0.0}, kSku, 2));
    QVERIFY(doc.isModified());
    QSignalSpy titles(&doc, &PalletDocument::titleChanged);
    const pb::Scenario s = scenario("tall-unwrapped-tower");
    QVERIFY(doc.loadScenario(s));
    QCOMPARE(doc.pallet(), s.pallet);
    QVERIFY(!doc.isModified());
    QCOMPARE(doc.undoStack()->count(), 0);
    QVERIFY(doc.windowTitle().startsWith(QString::fromStdString(s.name)));
    QCOMPARE(titles.last().at(0).toString(), doc.windowTitle());
    QVERIFY(doc.save().messages.join(u' ').contains(u"Save As"));  // no file yet
  }

  void newDocumentResets() {
    PalletDocument doc;
    QVERIFY(doc.loadScenario(scenario("asymmetric-load")));
    QSignalSpy changed(&doc, &PalletDocument::changed);
    doc.newDocument();
    QVERIFY(doc.pallet().items.empty());
    QCOMPARE(doc.undoStack()->count(), 0);
    QVERIFY(!doc.isModified());
    QCOMPARE(changed.count(), 1);
  }

  void recentFilesKeepOrderWithoutDuplicates() {
    QTemporaryDir dir;
    RecentFiles recent(dir.filePath(QStringLiteral("settings.ini")));
    QSignalSpy changed(&recent, &RecentFiles::filesChanged);
    QVERIFY(recent.files().isEmpty());
    for (int i = 0; i < 10; ++i) recent.add(dir.filePath(QStringLiteral("p%1.json").arg(i)));
    QCOMPARE(recent.files().size(), RecentFiles::maxCount());
    QCOMPARE(recent.files().first(), dir.filePath(QStringLiteral("p9.json")));
    recent.add(dir.filePath(QStringLiteral("p5.json")));
    QCOMPARE(recent.files().first(), dir.filePath(QStringLiteral("p5.json")));
    QCOMPARE(recent.files().count(dir.filePath(QStringLiteral("p5.json"))), 1);
    QCOMPARE(recent.files().size(), RecentFiles::maxCount());
    QCOMPARE(changed.count(), 11);
    // Another instance on the same settings sees them (they persist).
    RecentFiles again(dir.filePath(QStringLiteral("settings.ini")));
    QCOMPARE(again.files(), recent.files());
    recent.remove(dir.filePath(QStringLiteral("p5.json")));
    QVERIFY(!recent.files().contains(dir.filePath(QStringLiteral("p5.json"))));
  }

  // The actions with their dialogs replaced: open and save feed the recent files; a bad file
  // shows its pointers and keeps the document; unsaved changes are asked about.
  void fileActionsDriveTheDocument() {
    QTemporaryDir dir;
    RecentFiles recent(dir.filePath(QStringLiteral("settings.ini")));
    PalletDocument doc;
    FileActions actions(&doc, &recent, nullptr);
    QString nextPath;
    auto unsaved = FileActions::Unsaved::cancel;
    int asked = 0;
    QStringList errors;
    actions.setHooks({[&] { return nextPath; }, [&](const QString&) { return nextPath; },
                      [&] {
                        ++asked;
                        return unsaved;
                      },
                      [&](const QString&, const QString& text) { errors << text; },
                      [](const QString&) { return FileActions::Lost::later; }});

    QVERIFY(doc.addStack({0.0, 0.0}, kSku, 3));
    nextPath = dir.filePath(QStringLiteral("a.json"));
    actions.saveAction()->trigger();  // no file yet: Save asks for a name
    QVERIFY(!doc.isModified());
    QCOMPARE(recent.files(), QStringList{QFileInfo(nextPath).absoluteFilePath()});
    QCOMPARE(actions.recentMenu()->actions().size(), 1);

    QVERIFY(doc.setWrap(pb::WrapType::none));
    unsaved = FileActions::Unsaved::cancel;
    QVERIFY(!actions.newDocument());
    QCOMPARE(asked, 1);
    QCOMPARE(doc.pallet().items.size(), std::size_t{3});

    const QString bad = dir.filePath(QStringLiteral("bad.json"));
    QVERIFY(write_all(bad, "{\"items\": 3, \"env\": \"frozen\", \"body_temp_c\": 1}"));
    unsaved = FileActions::Unsaved::discard;
    QVERIFY(!actions.openPath(bad));
    QCOMPARE(errors.size(), 1);
    QVERIFY2(errors[0].contains(u"/items: "), qPrintable(errors[0]));
    QCOMPARE(doc.pallet().items.size(), std::size_t{3});
    QCOMPARE(doc.pallet().wrap, pb::WrapType::none);

    unsaved = FileActions::Unsaved::save;  // saves to a.json, then opens it
    QSignalSpy opened(&actions, &FileActions::opened);
    QVERIFY(actions.openPath(dir.filePath(QStringLiteral("a.json"))));
    QCOMPARE(opened.count(), 1);
    QCOMPARE(doc.pallet().wrap, pb::WrapType::none);  // the change was saved first
    QVERIFY(!doc.isModified());

    nextPath = dir.filePath(QStringLiteral("b.json"));
    actions.saveAsAction()->trigger();
    QCOMPARE(recent.files().first(), QFileInfo(nextPath).absoluteFilePath());
    QCOMPARE(actions.recentMenu()->actions().size(), 2);
    QVERIFY(actions.undoAction() != nullptr);
    QVERIFY(actions.fileMenu()->actions().contains(actions.openAction()));
  }
};

QTEST_MAIN(TestPalletDocument)
#include "tst_pallet_document.moc"
