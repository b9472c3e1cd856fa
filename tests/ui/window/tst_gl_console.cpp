// SPDX-License-Identifier: MIT
// The whole console, drawn for real (Xvfb + Mesa, 1400x900, device pixel ratio 1): each curated
// scenario dispatched with its suggested profile (a solve, not an envelope), the replay placed at
// its failure (or its end), and the frame checked where the replay pose puts things: the failing
// items in the highlight colour around their projected centres, the pallet in its wood colour,
// the trace plots holding one point per frame. The headless screenshot path (ScreenshotRunner,
// what `palletballet --screenshot` runs) writes its PNG. Every PNG is kept as an artifact.
#include <QDir>
#include <QDockWidget>
#include <QGraphicsSimpleTextItem>
#include <QGraphicsTextItem>
#include <QGraphicsView>
#include <QImage>
#include <QLabel>
#include <QSignalSpy>
#include <QTemporaryDir>
#include <QTest>
#include <QtCharts/QLineSeries>

#include "core/inputs/scenario.hpp"
#include "ui/models/replay_player.hpp"
#include "ui/replay/replay_panel.hpp"
#include "ui/replay/replay_view.hpp"
#include "ui/widgets/failure_map_view.hpp"
#include "ui/widgets/friction_chart.hpp"
#include "ui/widgets/trace_plots.hpp"
#include "ui/window/console_screenshot.hpp"
#include "ui/window/main_window.hpp"

using pb::ui::MainWindow;
using pb::ui::ReplayView;

namespace {

constexpr QSize kWindow(1400, 900);

QVector3D toQt(const pb::Vec3& v) {
  return QVector3D(static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2]));
}

// Text a person cannot read whole in the window as shown: a chart's text item Qt elided ("..."),
// and a one-line label whose text is wider than its box (measured with its font).
QStringList cutTexts(QWidget* root) {
  QStringList cut;
  for (QGraphicsView* view : root->findChildren<QGraphicsView*>()) {
    if (!view->isVisible() || view->scene() == nullptr) continue;
    for (QGraphicsItem* item : view->scene()->items()) {
      QString text;
      if (auto* t = dynamic_cast<QGraphicsTextItem*>(item)) text = t->toPlainText();
      if (auto* t = dynamic_cast<QGraphicsSimpleTextItem*>(item)) text = t->text();
      if (item->isVisible() &&
          (text.contains(QChar(0x2026)) || text.endsWith(QStringLiteral("..."))))
        cut << QStringLiteral("%1: '%2'")
                   .arg(QString::fromLatin1(view->metaObject()->className()), text);
    }
  }
  for (pb::ui::FailureMapView* map : root->findChildren<pb::ui::FailureMapView*>()) {
    if (!map->isVisible()) continue;
    for (const QString& text : map->cutTexts())
      cut << QStringLiteral("failure map: '%1'").arg(text);
  }
  for (QLabel* label : root->findChildren<QLabel*>()) {
    if (!label->isVisible() || label->wordWrap() || label->text().isEmpty() ||
        label->textFormat() == Qt::RichText || label->text().contains(QLatin1Char('<')) ||
        label->text().contains(QLatin1Char('\n')))
      continue;
    const int need = label->fontMetrics().horizontalAdvance(label->text());
    if (need > label->contentsRect().width() + 1) {
      cut << QStringLiteral("label %1 (%2 px for %3 px): '%4'")
                 .arg(label->objectName())
                 .arg(need)
                 .arg(label->contentsRect().width())
                 .arg(label->text());
    }
  }
  return cut;
}

int hueDistance(const QColor& a, const QColor& b) {
  const int d = std::abs(a.hsvHue() - b.hsvHue());
  return std::min(d, 360 - d);
}

// Runs a screenshot request to its end: the exit code it reports (-1: it never finished).
int finish(pb::ui::ScreenshotRunner& runner) {
  QSignalSpy done(&runner, &pb::ui::ScreenshotRunner::done);
  runner.start();
  if (!done.wait(60000)) return -1;
  return done.at(0).at(0).toInt();
}

QString artifact(const QString& name) {
  QDir().mkpath(QStringLiteral(PB_TEST_ARTIFACTS_DIR));
  return QStringLiteral(PB_TEST_ARTIFACTS_DIR "/") + name;
}

}  // namespace

class TestGlConsole : public QObject {
  Q_OBJECT

 private slots:
  void initTestCase() { QCOMPARE(ReplayView::probeOpenGl(), QString()); }

  void scenarioAtItsFailure_data() {
    QTest::addColumn<QString>("slug");
    for (const std::string& slug : pb::scenario_slugs()) {
      QTest::newRow(slug.c_str()) << QString::fromStdString(slug);
    }
  }

  void scenarioAtItsFailure() {
    QFETCH(QString, slug);
    const auto scenario = pb::load_scenario(slug.toStdString());
    QVERIFY(scenario.ok());
    MainWindow window;
    window.resize(kWindow);
    window.show();
    QVERIFY(QTest::qWaitForWindowExposed(&window));
    QVERIFY(window.loadScenario(slug));
    // Before any dispatch the 3D view shows the loaded pallet as built, at rest.
    QVERIFY(window.replayPanel()->showsPreview());
    QTest::qWait(50);
    QVERIFY(window.replayPanel()->view()->grabFramebuffer().save(
        artifact(QStringLiteral("console_as_built_%1.png").arg(slug))));
    QSignalSpy finished(&window, &MainWindow::dispatchFinished);
    window.dispatch(scenario->suggested_profile, false);
    QVERIFY(finished.wait(60000));
    QVERIFY2(finished.at(0).at(0).toBool(), qPrintable(finished.at(0).at(1).toString()));

    pb::ui::ReplayPanel* panel = window.replayPanel();
    ReplayView* view = panel->view();
    QVERIFY(view != nullptr);
    const pb::Replay& replay = panel->replay();
    panel->player()->pause();
    const double t = replay.failure ? replay.failure->time_s : replay.frames.back().t;
    panel->player()->setTime(t);
    QCOMPARE(view->time(), t);
    QTest::qWait(50);
    const QImage frame = view->grabFramebuffer();
    QCOMPARE(frame.devicePixelRatio(), 1.0);
    QVERIFY(frame.save(artifact(QStringLiteral("console_replay_%1.png").arg(slug))));
    QVERIFY(window.grab().save(artifact(QStringLiteral("console_%1.png").arg(slug))));

    // The trace plots: one point per frame, their cursor at t.
    QCOMPARE(window.tracePlots()->series(pb::ui::TracePlots::Tilt)->count(),
             static_cast<int>(replay.frames.size()));
    QCOMPARE(window.tracePlots()->cursorTime(), t);

    // The pallet: the centre of its front (+X) face, which faces the iso camera, shaded wood.
    const pb::ReplayFrame& f = view->currentFrame();
    QCOMPARE(f.items.size(), replay.pallet.items.size());
    const pb::Vec3 front = pb::rotate(f.pallet.quat, {replay.pallet.base_dims_m[0] / 2.0, 0, 0});
    const QPointF palletFront = view->project(
        toQt({f.pallet.pos[0] + front[0], f.pallet.pos[1] + front[1], f.pallet.pos[2] + front[2]}));
    const QColor wood = frame.pixelColor(palletFront.toPoint());
    QVERIFY2(hueDistance(wood, QColor(176, 132, 84)) <= 6, qPrintable(wood.name()));

    // Every item's projected centre lies in the view; every highlighted pixel is near a failing
    // item; with a failure, the highlight is seen around the failing items' projected centres.
    if (!replay.failure) {
      qInfo("%s: no failure at the suggested profile", qPrintable(slug));
      return;
    }
    if (replay.failure->items.empty()) {  // the pallet itself slipped: no carton is to blame
      qInfo("%s: %s at %.3f s, no item failed", qPrintable(slug),
            pb::to_string(replay.failure->mode).data(), t);
      for (int y = 0; y < frame.height(); ++y) {
        for (int x = 0; x < frame.width(); ++x)
          QVERIFY(frame.pixelColor(x, y) != ReplayView::highlightColor());
      }
      return;
    }
    QRectF failingBox;
    for (int i : replay.failure->items) {
      const pb::Item& item = replay.pallet.items[i];
      const double r = std::max({item.dims_m[0], item.dims_m[1], item.dims_m[2]});
      for (int c = 0; c < 8; ++c) {
        const pb::Vec3 corner{f.items[i].pos[0] + ((c & 1) ? r : -r),
                              f.items[i].pos[1] + ((c & 2) ? r : -r),
                              f.items[i].pos[2] + ((c & 4) ? r : -r)};
        const QPointF p = view->project(toQt(corner));
        failingBox = failingBox.isNull() ? QRectF(p, QSizeF(1, 1))
                                         : failingBox.united(QRectF(p, QSizeF(1, 1)));
      }
    }
    int red = 0, stray = 0;
    for (int y = 0; y < frame.height(); ++y) {
      for (int x = 0; x < frame.width(); ++x) {
        if (frame.pixelColor(x, y) != ReplayView::highlightColor()) continue;
        ++red;
        if (!failingBox.contains(QPointF(x, y))) ++stray;
      }
    }
    qInfo("%s: %s at %.3f s, %d highlighted pixels", qPrintable(slug),
          pb::to_string(replay.failure->mode).data(), t, red);
    QVERIFY2(red >= 30, qPrintable(QStringLiteral("%1 highlighted pixels").arg(red)));
    QCOMPARE(stray, 0);
  }

  void headlessScreenshotOfTheReplayView() {
    QTemporaryDir dir;
    pb::ui::ConsoleRequest request;
    const QString out = dir.filePath(QStringLiteral("shot.png"));
    QCOMPARE(pb::ui::ConsoleRequest::parse(QStringLiteral("tall-unwrapped-tower"), {}, {}, out,
                                           QStringLiteral("failure"), QStringLiteral("800x600"),
                                           QStringLiteral("replay"), request),
             QString());
    MainWindow window;
    pb::ui::ScreenshotRunner runner(&window, request);
    QCOMPARE(finish(runner), 0);
    const QImage image(out);
    QVERIFY(!image.isNull());
    QCOMPARE(runner.capturedTime(), *window.replayPanel()->player()->failureTime());
    QVERIFY(image.save(artifact(QStringLiteral("screenshot_replay_tall-unwrapped-tower.png"))));
    int red = 0;
    for (int y = 0; y < image.height(); ++y) {
      for (int x = 0; x < image.width(); ++x)
        red += image.pixelColor(x, y) == ReplayView::highlightColor();
    }
    QVERIFY(red >= 30);
  }

  // --size is honoured exactly, for the window (its panels scroll when they need more) and for the
  // replay view alone; each screenshot is kept as an artifact.
  void screenshotsHaveTheSizeAsked_data() {
    QTest::addColumn<QString>("size");
    QTest::addColumn<QString>("view");
    for (const char* size : {"1024x768", "1280x800", "1920x1080"}) {
      for (const char* view : {"window", "replay"}) {
        QTest::addRow("%s %s", size, view)
            << QString::fromLatin1(size) << QString::fromLatin1(view);
      }
    }
  }
  void screenshotsHaveTheSizeAsked() {
    QFETCH(QString, size);
    QFETCH(QString, view);
    pb::ui::ConsoleRequest request;
    const QString out = artifact(QStringLiteral("screenshot_%1_%2.png").arg(view, size));
    // The dairy slab: the window's screenshot waits for its analysis, which takes 40 ms here.
    QCOMPARE(pb::ui::ConsoleRequest::parse(QStringLiteral("stable-dairy-slab"), {}, {}, out,
                                           QStringLiteral("end"), size, view, request),
             QString());
    MainWindow window;
    pb::ui::ScreenshotRunner runner(&window, request);
    QCOMPARE(finish(runner), 0);
    const QImage image(out);
    QCOMPARE(image.size(), request.size);
    if (view == QStringLiteral("window")) {
      QStringList cut = cutTexts(&window);
      // And the friction chart, which shares its dock's place with the results: brought forward.
      for (QWidget* w = window.frictionChart(); w != nullptr; w = w->parentWidget()) {
        if (auto* dock = qobject_cast<QDockWidget*>(w)) {
          dock->raise();
          break;
        }
      }
      QTest::qWait(50);
      QVERIFY(window.frictionChart()->isVisible());
      cut << cutTexts(window.frictionChart());
      QVERIFY2(cut.isEmpty(), qPrintable(cut.join(QStringLiteral(" | "))));
    }
  }

  void badArgumentsNameTheOption() {
    pb::ui::ConsoleRequest r;
    const auto parse = [&](const QString& slug, const QString& speed, const QString& at,
                           const QString& size, const QString& view) {
      return pb::ui::ConsoleRequest::parse(slug, speed, {}, QStringLiteral("x.png"), at, size, view,
                                           r);
    };
    const QString ok = QStringLiteral("tall-unwrapped-tower");
    const QString failure = QStringLiteral("failure"), size = QStringLiteral("800x600"),
                  window = QStringLiteral("window");
    QVERIFY(parse(QStringLiteral("nope"), {}, failure, size, window)
                .startsWith(QStringLiteral("--scenario:")));
    QVERIFY(parse(ok, QStringLiteral("fast"), failure, size, window)
                .startsWith(QStringLiteral("--profile-speed:")));
    QVERIFY(parse(ok, QStringLiteral("9"), failure, size, window)
                .startsWith(QStringLiteral("--profile-speed:")));
    // One range: the dials', the search's and the map's (it was 5 m/s here, 3 on the dial, 2 in
    // the search).
    QCOMPARE(parse(ok, QStringLiteral("2.5"), failure, size, window),
             QStringLiteral("--profile-speed: 2.5 m/s is outside the analysed range; give 0.1 to 2 "
                            "m/s (the dials, the search and the failure map share it)"));
    QVERIFY(pb::ui::ConsoleRequest::parse(ok, {}, QStringLiteral("6"), QStringLiteral("x.png"),
                                          failure, size, window, r)
                .startsWith(QStringLiteral("--profile-accel: 6 m/s^2 is outside the analysed "
                                           "range; give 0.1 to 5 m/s^2")));
    QVERIFY(
        parse(ok, {}, QStringLiteral("soon"), size, window).startsWith(QStringLiteral("--at:")));
    QVERIFY(parse(ok, {}, failure, QStringLiteral("10x10"), window)
                .startsWith(QStringLiteral("--size:")));
    QVERIFY(parse(ok, {}, failure, size, QStringLiteral("dials"))
                .startsWith(QStringLiteral("--screenshot-view:")));
    QCOMPARE(parse(ok, QStringLiteral("1.5"), QStringLiteral("0.4"), size, window), QString());
    QCOMPARE(r.profile.target_speed_mps, 1.5);
    QCOMPARE(r.at, pb::ui::ConsoleRequest::At::time);
    QCOMPARE(r.atTime, 0.4);
  }
};

QTEST_MAIN(TestGlConsole)
#include "tst_gl_console.moc"
