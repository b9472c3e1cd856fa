// SPDX-License-Identifier: MIT
// Recovery of unsaved work: the copy follows the document's unsaved changes and disappears with
// them; a console killed with SIGKILL leaves its copy, which the next console offers and restores.
// The killed console is this test binary itself, run as a child with PB_AUTOSAVE_CHILD set.
#include <QtTest>

#include <csignal>
#include <cstdio>
#include <cstdlib>

#include "core/inputs/scenario.hpp"
#include "ui/models/autosave.hpp"
#include "ui/models/pallet_document.hpp"
#include "ui/models/recent_files.hpp"
#include "ui/widgets/file_actions.hpp"

using pb::ui::Autosave;
using pb::ui::FileActions;
using pb::ui::PalletDocument;

namespace {

const QString kSku = QStringLiteral("SKU-FD-002");

// The child: a console's document and autosave in `dir`; it edits (two stacks), says "saved" once
// the copy is on disk, makes a third edit that is never copied, and waits to be killed.
int runChild(const QString& dir) {
  PalletDocument doc;
  Autosave autosave(&doc, dir, 60'000);
  doc.addStack({-0.3, 0.0}, kSku, 3);
  doc.addStack({0.3, 0.0}, kSku, 2);
  if (!autosave.saveNow()) return 3;
  std::printf("saved %s\n", qPrintable(autosave.path()));
  std::fflush(stdout);
  doc.addStack({0.0, 0.35}, kSku, 1);  // within the delay: lost with the kill
  return QCoreApplication::exec();
}

}  // namespace

class TestAutosave : public QObject {
  Q_OBJECT

 private slots:
  void theCopyFollowsUnsavedChanges() {
    QTemporaryDir dir;
    PalletDocument doc;
    auto autosave = std::make_unique<Autosave>(&doc, dir.path(), 50);
    const QString copy = autosave->path();
    QVERIFY(!QFile::exists(copy));  // nothing unsaved yet
    QVERIFY(doc.addStack({0.0, 0.0}, kSku, 3));
    QTRY_VERIFY(QFile::exists(copy));  // within the delay
    // Its own console is alive: no orphan.
    QVERIFY(Autosave::orphans(dir.path()).isEmpty());
    // Undone to the saved state: nothing left to lose.
    doc.undoStack()->undo();
    QVERIFY(!QFile::exists(copy));
    QVERIFY(doc.addStack({0.0, 0.0}, kSku, 2));
    QTRY_VERIFY(QFile::exists(copy));
    // Saved: gone.
    QVERIFY(doc.saveAs(dir.filePath(QStringLiteral("p.json"))).ok);
    QVERIFY(!QFile::exists(copy));
    QVERIFY(doc.addStack({0.4, 0.3}, kSku, 1));
    QTRY_VERIFY(QFile::exists(copy));
    // A clean exit (even discarding the changes) leaves nothing behind.
    autosave.reset();
    QVERIFY(!QFile::exists(copy));
    QVERIFY(QDir(dir.path()).entryList(QDir::Files).filter(QStringLiteral("recovery")).isEmpty());
  }

  void aKilledConsoleIsRecovered() {
    QTemporaryDir dir;
    QProcess child;
    QProcessEnvironment env = QProcessEnvironment::systemEnvironment();
    env.insert(QStringLiteral("PB_AUTOSAVE_CHILD"), dir.path());
    child.setProcessEnvironment(env);
    child.start(QCoreApplication::applicationFilePath(), {});
    QVERIFY(child.waitForStarted());
    QByteArray out;
    QTRY_VERIFY2_WITH_TIMEOUT((out += child.readAllStandardOutput()).startsWith("saved"),
                              (out + child.readAllStandardError()).constData(), 20000);
    ::kill(pid_t(child.processId()), SIGKILL);
    QVERIFY(child.waitForFinished());
    QCOMPARE(child.exitStatus(), QProcess::CrashExit);

    // The next console: a document of its own, then the offer.
    PalletDocument doc;
    pb::ui::RecentFiles recent(dir.filePath(QStringLiteral("settings.ini")));
    FileActions actions(&doc, &recent, nullptr);
    const auto lost = Autosave::orphans(dir.path());
    QCOMPARE(lost.size(), 1);
    QCOMPARE(lost.front().pallet.items.size(), std::size_t{5});  // two stacks; the third was lost
    QCOMPARE(lost.front().name, QStringLiteral("Untitled"));
    QVERIFY(lost.front().savedAt.secsTo(QDateTime::currentDateTimeUtc()) < 60);

    QStringList asked;
    FileActions::Hooks hooks;
    hooks.askRestore = [&](const QString& text) {
      asked << text;
      return asked.size() == 1 ? FileActions::Lost::later : FileActions::Lost::restore;
    };
    actions.setHooks(hooks);
    QVERIFY(!actions.offerRecovery(dir.path()));  // Later: kept for the next start
    QCOMPARE(Autosave::orphans(dir.path()).size(), 1);
    QVERIFY(asked.front().contains(QStringLiteral("Untitled")));
    QVERIFY(actions.offerRecovery(dir.path()));  // Restore
    QCOMPARE(doc.pallet(), lost.front().pallet);
    QVERIFY(doc.isModified());  // still unsaved work
    QVERIFY(Autosave::orphans(dir.path()).isEmpty());
    doc.undoStack()->undo();  // back to what the console had saved: nothing
    QVERIFY(doc.pallet().items.empty());
  }

  void aRestoredFileKeepsItsName() {
    QTemporaryDir dir;
    const QString file = dir.filePath(QStringLiteral("dairy.json"));
    PalletDocument saved;
    QVERIFY(saved.loadScenario(*pb::load_scenario("stable-dairy-slab")));
    QVERIFY(saved.saveAs(file).ok);
    pb::PalletConfig edited = saved.pallet();
    edited.items.pop_back();

    PalletDocument doc;
    doc.restoreUnsaved(edited, file, QStringLiteral("dairy.json"));
    QCOMPARE(doc.filePath(), file);
    QCOMPARE(doc.pallet(), edited);
    QVERIFY(doc.isModified());
    doc.undoStack()->undo();
    QCOMPARE(doc.pallet(), saved.pallet());  // Undo shows the file as saved
    QVERIFY(!doc.isModified());
    // The file is gone: a new document of that name, the work still unsaved.
    QVERIFY(QFile::remove(file));
    PalletDocument orphan;
    orphan.restoreUnsaved(edited, file, QStringLiteral("dairy.json"));
    QCOMPARE(orphan.pallet(), edited);
    QVERIFY(orphan.filePath().isEmpty());
    QCOMPARE(orphan.displayName(), QStringLiteral("dairy.json"));
    QVERIFY(orphan.isModified());
  }

  void anUnreadableCopyIsNamedAndKept() {
    QTemporaryDir dir;
    const QString bad = dir.filePath(QStringLiteral("recovery-999999.json"));
    QFile f(bad);
    QVERIFY(f.open(QIODevice::WriteOnly));
    f.write("{\"kind\": \"palletballet-recovery\", \"pallet\": {\"items\": 3}}");
    f.close();
    QStringList problems;
    QVERIFY(Autosave::orphans(dir.path(), &problems).isEmpty());
    QCOMPARE(problems.size(), 1);
    QVERIFY(problems.front().startsWith(bad));
    QVERIFY(QFile::exists(bad));  // nothing is deleted that was not read
  }
};

int main(int argc, char** argv) {
  QApplication app(argc, argv);
  if (const QByteArray dir = qgetenv("PB_AUTOSAVE_CHILD"); !dir.isEmpty()) {
    return runChild(QString::fromLocal8Bit(dir));
  }
  TestAutosave test;
  return QTest::qExec(&test, argc, argv);
}

#include "tst_autosave.moc"
