// SPDX-License-Identifier: MIT
// The console without OpenGL (PB_NO_OPENGL=1, as on a machine with no usable driver): the replay
// area says why, and everything else works: a scenario loads, a dispatch runs through the
// analysis service and fills the replay, trace plots and results; a replay exported as JSON opens
// again without re-simulating, and a broken replay file gets a message with its pointer. The
// window's PNG is an artifact.
#include <QAbstractButton>
#include <QAbstractSlider>
#include <QAbstractSpinBox>
#include <QAction>
#include <QComboBox>
#include <QDir>
#include <QFile>
#include <QLabel>
#include <QLineEdit>
#include <QMenu>
#include <QMenuBar>
#include <QScrollBar>
#include <QSignalSpy>
#include <QStandardPaths>
#include <QTabBar>
#include <QTemporaryDir>
#include <QTest>
#include <QToolButton>
#include <QtCharts/QLineSeries>

#include "core/inputs/scenario.hpp"
#include "ui/models/pallet_document.hpp"
#include "ui/models/replay_player.hpp"
#include "ui/replay/replay_panel.hpp"
#include "ui/widgets/dial_panel.hpp"
#include "ui/widgets/failure_map_view.hpp"
#include "ui/widgets/results_panel.hpp"
#include "ui/widgets/trace_plots.hpp"
#include "ui/window/main_window.hpp"

using pb::ui::MainWindow;

class TestMainWindow : public QObject {
  Q_OBJECT

 private slots:
  void initTestCase() {
    qputenv("PB_NO_OPENGL", "1");
    QStandardPaths::setTestModeEnabled(true);  // recent files away from the user's settings
  }

  void noOpenGlIsSaidAndEverythingElseWorks() {
    MainWindow window;
    window.resize(1400, 900);
    window.show();
    QVERIFY(QTest::qWaitForWindowExposed(&window));
    pb::ui::ReplayPanel* replay = window.replayPanel();
    QCOMPARE(replay->view(), nullptr);
    QVERIFY(replay->glProblem().contains(QStringLiteral("OpenGL")));
    auto* label = replay->findChild<QLabel*>(QStringLiteral("replayNoOpenGl"));
    QVERIFY(label != nullptr);
    QVERIFY(label->isVisible());
    QCOMPARE(label->text(), replay->glProblem());

    QVERIFY(window.loadScenario(QStringLiteral("tall-unwrapped-tower")));
    const auto scenario = pb::load_scenario("tall-unwrapped-tower");
    QCOMPARE(window.windowTitle(), window.document()->windowTitle());
    QVERIFY(!window.isWindowModified());  // a scenario opens as a document of its own
    QSignalSpy finished(&window, &MainWindow::dispatchFinished);
    window.dispatch(scenario->suggested_profile, false);
    QVERIFY(finished.wait(30000));
    QCOMPARE(finished.at(0).at(0).toBool(), true);
    QVERIFY(replay->hasReplay());
    QCOMPARE(replay->replay().failure->items, std::vector<int>{7});
    QVERIFY(replay->player()->isPlaying());  // the replay starts when it arrives
    replay->player()->pause();
    replay->player()->setTime(*replay->player()->failureTime());
    auto* tilt = window.tracePlots()->series(pb::ui::TracePlots::Tilt);
    QCOMPARE(tilt->count(), static_cast<int>(replay->replay().frames.size()));
    QCOMPARE(window.tracePlots()->cursorTime(), replay->replay().failure->time_s);

    QVERIFY(QDir().mkpath(QStringLiteral(PB_TEST_ARTIFACTS_DIR)));
    const QString path = QStringLiteral(PB_TEST_ARTIFACTS_DIR "/console_no_opengl.png");
    QVERIFY(window.grab().save(path));
    qInfo("screenshot: %s", qPrintable(path));

    // A frame PNG without OpenGL is the message itself, not a crash.
    QTemporaryDir dir;
    QCOMPARE(replay->exportFramePng(dir.filePath(QStringLiteral("frame.png"))), QString());
  }

  // A result is shown only for the pallet it was computed for: a failure map still computing
  // when the pallet changes is stopped and never appears under the new one; a map computed once
  // is answered from the cache on the next dispatch of the same pallet (no simulation).
  void noMapOfThePreviousPalletAndMapsAreCached() {
    MainWindow window;
    window.resize(1400, 900);
    QVERIFY(window.loadScenario(QStringLiteral("tall-unwrapped-tower")));  // a 5-10 s map
    QSignalSpy finished(&window, &MainWindow::dispatchFinished);
    QSignalSpy maps(window.service(), &pb::ui::AnalysisService::failureMapReady);
    QSignalSpy progress(window.service(), &pb::ui::AnalysisService::progress);
    window.dispatch(pb::load_scenario("tall-unwrapped-tower")->suggested_profile, false, true);
    QVERIFY(finished.wait(60000));  // the replay is there; the map is still being computed
    QVERIFY(window.service()->pendingCount() > 0);
    QVERIFY(window.loadScenario(QStringLiteral("stable-dairy-slab")));  // the pallet changes
    QCOMPARE(window.service()->pendingCount(), 0);
    QTest::qWait(200);
    QCOMPARE(maps.count(), 0);
    QVERIFY(!window.resultsPanel()->mapView()->hasGrid());

    const auto slab = pb::load_scenario("stable-dairy-slab")->suggested_profile;
    window.dispatch(slab, false, true);
    QTRY_VERIFY_WITH_TIMEOUT(window.resultsPanel()->mapView()->hasGrid(), 60000);
    QCOMPARE(maps.count(), 1);
    progress.clear();
    window.dispatch(slab, false, true);
    QTRY_COMPARE_WITH_TIMEOUT(maps.count(), 2, 60000);
    QVERIFY(window.resultsPanel()->mapView()->hasGrid());
    for (const auto& p : progress) {
      QVERIFY(!p.at(1).toString().contains(QStringLiteral("Mapping")));  // from the cache
    }
  }

  // The 3D view shows the pallet being edited, at rest, as soon as it changes: not the previous
  // pallet's replay, and nothing to play or export until a dispatch.
  void theViewShowsThePalletBeingEdited() {
    MainWindow window;
    pb::ui::ReplayPanel* replay = window.replayPanel();
    QVERIFY(replay->showsPreview());
    QVERIFY(window.loadScenario(QStringLiteral("tall-unwrapped-tower")));
    QVERIFY(replay->showsPreview() && !replay->hasReplay());
    QCOMPARE(replay->replay().frames.at(0).items.size(), std::size_t(8));
    QSignalSpy finished(&window, &MainWindow::dispatchFinished);
    window.dispatch(pb::load_scenario("tall-unwrapped-tower")->suggested_profile, false);
    QVERIFY(finished.wait(30000));
    QVERIFY(replay->hasReplay() && !replay->showsPreview());
    QCOMPARE(window.statusText(), QStringLiteral("Replay ready"));
    QVERIFY(window.loadScenario(QStringLiteral("top-heavy-surprise")));  // the pallet changes
    QVERIFY(replay->showsPreview() && !replay->hasReplay());
    QVERIFY2(!window.statusText().contains(QStringLiteral("ready")),  // no word of the old one
             qPrintable(window.statusText()));
    QCOMPARE(replay->replay().frames.at(0).items.size(), std::size_t(6));
    QCOMPARE(replay->replay().pallet, window.document()->pallet());
  }

  // A pallet validation refuses is not dispatched: nothing is simulated, and the dial panel and
  // the status bar say why, in the stack builder's words (stacks counted from 1).
  void anInvalidPalletIsNotDispatched() {
    MainWindow window;
    pb::PalletConfig bad = pb::load_scenario("tall-unwrapped-tower")->pallet;
    bad.items[3].weight_kg = -5.0;  // a negative mass: an error at /items/3/weight_kg
    QVERIFY(window.document()->replacePallet(bad, QStringLiteral("Bad mass")));
    QVERIFY(!window.document()->isValid());
    QSignalSpy finished(&window, &MainWindow::dispatchFinished);
    window.dialPanel()->dispatch();
    QCOMPARE(finished.count(), 1);
    QCOMPARE(finished.at(0).at(0).toBool(), false);
    const QString why = finished.at(0).at(1).toString();
    QVERIFY2(why.startsWith(QStringLiteral("Not dispatched")), qPrintable(why));
    QVERIFY2(why.contains(QStringLiteral("Stack 1")), qPrintable(why));
    QVERIFY2(!why.contains(QStringLiteral("/items")), qPrintable(why));
    QCOMPARE(window.service()->pendingCount(), 0);
    QCOMPARE(window.dialPanel()->statusText(), why);
    QVERIFY(!window.dialPanel()->game().dispatched());
  }

  void replayFilesRoundTripAndBadOnesAreExplained() {
    MainWindow window;
    pb::ui::ReplayPanel* replay = window.replayPanel();
    QTemporaryDir dir;
    const QString path = dir.filePath(QStringLiteral("replay.json"));
    QVERIFY(!replay->exportReplay(path).isEmpty());  // nothing to export yet
    QVERIFY(window.loadScenario(QStringLiteral("tall-unwrapped-tower")));
    QSignalSpy finished(&window, &MainWindow::dispatchFinished);
    window.dispatch(pb::load_scenario("tall-unwrapped-tower")->suggested_profile, false);
    QVERIFY(finished.wait(30000));
    QCOMPARE(replay->exportReplay(path), QString());
    const pb::Json written = pb::replay_to_json(replay->replay());

    MainWindow other;
    QCOMPARE(other.replayPanel()->openReplayFile(path), QString());
    QVERIFY(pb::replay_to_json(other.replayPanel()->replay()) == written);
    QCOMPARE(other.replayPanel()->player()->failureTime(), replay->player()->failureTime());

    QFile bad(dir.filePath(QStringLiteral("bad.json")));
    QVERIFY(bad.open(QIODevice::WriteOnly));
    bad.write(R"({"hz": -1})");
    bad.close();
    const QString message = other.replayPanel()->openReplayFile(bad.fileName());
    QVERIFY2(message.contains(QStringLiteral("/hz")), qPrintable(message));
    QVERIFY(pb::replay_to_json(other.replayPanel()->replay()) == written);  // kept
    QVERIFY(
        !other.replayPanel()->openReplayFile(dir.filePath(QStringLiteral("none.json"))).isEmpty());

    // A .csv gets the traces (one row per frame, what the plots show), not JSON.
    const QString csv = dir.filePath(QStringLiteral("trace.csv"));
    QCOMPARE(replay->exportReplay(csv), QString());
    QFile traces(csv);
    QVERIFY(traces.open(QIODevice::ReadOnly));
    const QList<QByteArray> lines = traces.readAll().split('\n');
    QVERIFY(lines.front().startsWith("t_s,pallet_tilt_deg,item_displacement_cm"));
    QCOMPARE(lines.size() - 2,
             static_cast<int>(replay->replay().frames.size()));  // header, last \n

    // Home and End go to the replay's start and end.
    replay->goToEndAction()->trigger();
    QCOMPARE(replay->player()->time(), replay->player()->endTime());
    replay->goToStartAction()->trigger();
    QCOMPARE(replay->player()->time(), replay->player()->startTime());
  }

  // Every control a person can use says what it does when hovered (buttons, boxes, dials,
  // sliders, the fields), in the docks and the central panels alike.
  void everyControlHasATooltip() {
    MainWindow window;
    window.show();
    QVERIFY(QTest::qWaitForWindowExposed(&window));
    QStringList silent;
    const auto check = [&](QWidget* w, const QString& what) {
      if (!w->isVisibleTo(&window) || !w->isEnabled() || !w->toolTip().isEmpty()) return;
      if (auto* b = qobject_cast<QAbstractButton*>(w)) {
        if (auto* tb = qobject_cast<QToolButton*>(b);
            tb && tb->defaultAction() && !tb->defaultAction()->toolTip().isEmpty())
          return;
      }
      // A part of a compound control that carries the tooltip (a spin box's line edit, ...).
      for (QWidget* p = w->parentWidget(); p != nullptr && p != &window; p = p->parentWidget()) {
        if ((qobject_cast<QAbstractSpinBox*>(p) || qobject_cast<QComboBox*>(p)) &&
            !p->toolTip().isEmpty())
          return;
      }
      silent << QStringLiteral("%1 '%2' (%3)")
                    .arg(what, w->objectName(),
                         qobject_cast<QAbstractButton*>(w)
                             ? qobject_cast<QAbstractButton*>(w)->text()
                             : QString::fromLatin1(w->metaObject()->className()));
    };
    for (auto* w : window.findChildren<QAbstractButton*>()) {
      if (qobject_cast<QTabBar*>(w->parentWidget()) || w->inherits("QDockWidgetTitleButton") ||
          w->parentWidget()->inherits("QScrollBar"))
        continue;  // Qt's own: the tab bar's scroll arrows, a dock's float and close buttons
      check(w, QStringLiteral("button"));
    }
    for (auto* w : window.findChildren<QComboBox*>()) check(w, QStringLiteral("combo box"));
    for (auto* w : window.findChildren<QAbstractSpinBox*>()) check(w, QStringLiteral("spin box"));
    for (auto* w : window.findChildren<QAbstractSlider*>()) {
      if (!qobject_cast<QScrollBar*>(w)) check(w, QStringLiteral("slider or dial"));
    }
    for (auto* w : window.findChildren<QLineEdit*>()) check(w, QStringLiteral("field"));
    QVERIFY2(silent.isEmpty(), qPrintable(silent.join(QStringLiteral(" | "))));
  }

  // The closed-form estimate shows at once, marked provisional; the analysis replaces it.
  void theAnswerIsProvisionalUntilTheAnalysisArrives() {
    MainWindow window;
    QVERIFY(window.loadScenario(QStringLiteral("top-heavy-surprise")));
    QSignalSpy finished(&window, &MainWindow::dispatchFinished);
    window.dispatch(pb::load_scenario("top-heavy-surprise")->suggested_profile, true);
    QVERIFY(window.resultsPanel()->isProvisional());
    QVERIFY(window.resultsPanel()->limitsText().contains(QStringLiteral("Provisional")));
    // Each simulated limit replaces its estimate as its search ends, before the analysis does.
    QSignalSpy found(window.service(), &pb::ui::AnalysisService::axisFound);
    QVERIFY(found.wait(60000));
    if (window.resultsPanel()->isProvisional()) {
      QVERIFY2(
          window.resultsPanel()->limitsText().contains(QStringLiteral("of 3 limits simulated")),
          qPrintable(window.resultsPanel()->limitsText()));
    }
    QVERIFY(!finished.isEmpty() || finished.wait(60000));
    QVERIFY(!window.resultsPanel()->isProvisional());
    QVERIFY(!window.resultsPanel()->limitsText().contains(QStringLiteral("Provisional")));
    QVERIFY(window.resultsPanel()->limitsText().contains(QStringLiteral("simulations")));
  }

  void menusOfferReplayFilesAndShortcuts() {
    MainWindow window;
    QStringList titles;
    for (QAction* a : window.menuBar()->actions()) titles << a->text();
    QVERIFY2(titles.contains(QStringLiteral("&Replay")), qPrintable(titles.join(QLatin1Char(','))));
    QStringList file;
    for (QAction* a : window.menuBar()->actions().first()->menu()->actions()) file << a->text();
    QVERIFY2(file.contains(QStringLiteral("Open &Replay\u2026")),
             qPrintable(file.join(QLatin1Char(','))));
    QVERIFY(file.contains(QStringLiteral("&Export Replay\u2026")));
    QCOMPARE(window.replayPanel()->playAction()->shortcut(), QKeySequence(Qt::Key_Space));
    QCOMPARE(window.replayPanel()->stepBackAction()->shortcut(), QKeySequence(Qt::Key_Left));
    QCOMPARE(window.replayPanel()->stepForwardAction()->shortcut(), QKeySequence(Qt::Key_Right));
    QCOMPARE(window.replayPanel()->goToStartAction()->shortcut(), QKeySequence(Qt::Key_Home));
    QCOMPARE(window.replayPanel()->goToEndAction()->shortcut(), QKeySequence(Qt::Key_End));
  }
};

QTEST_MAIN(TestMainWindow)
#include "tst_main_window.moc"
