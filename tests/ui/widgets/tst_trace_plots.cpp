// SPDX-License-Identifier: MIT
// Trace plots: the curves are the detectors' measures over the replay (a synthetic replay with a
// known tilt and slip, and a real failing run whose last frame crosses the threshold the core's
// detector fired on), the threshold lines sit at the detector thresholds, the cursor follows.
#include <QApplication>
#include <QChart>
#include <QChartView>
#include <QDir>
#include <QGraphicsScene>
#include <QGraphicsSimpleTextItem>
#include <QGraphicsTextItem>
#include <QLineSeries>
#include <QMouseEvent>
#include <QSignalSpy>
#include <QValueAxis>
#include <QtTest>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/analysis/analyzer.hpp"
#include "core/inputs/scenario.hpp"
#include "ui/widgets/trace_plots.hpp"

using namespace pb;
using namespace pb::ui;

namespace {

/// Three frames: rest; the pallet tilted 4 deg about Y with the belt 10 cm ahead; tilted 10 deg.
Replay synthetic() {
  Replay r;
  r.pallet.items.push_back(Item{});
  for (int k = 0; k < 3; ++k) {
    ReplayFrame f;
    f.t = k * 0.5;
    const double deg = k == 0 ? 0.0 : (k == 1 ? 4.0 : 10.0);
    const double half = deg * std::numbers::pi / 360.0;
    f.pallet.quat = {std::cos(half), 0.0, std::sin(half), 0.0};
    f.belt_x = k == 1 ? 0.10 : 0.0;
    f.items.push_back(Pose{{0.0, 0.0, 0.25}, {1.0, 0.0, 0.0, 0.0}});
    r.frames.push_back(f);
  }
  return r;
}

}  // namespace

class TestTracePlots : public QObject {
  Q_OBJECT

 private slots:
  void measuresAreTheDetectorsOnTheFrames() {
    const auto curves = TracePlots::measure(synthetic(), DetectorThresholds{});
    const auto& tilt = curves[TracePlots::Tilt];
    QCOMPARE(tilt.value.size(), std::size_t{3});
    QVERIFY(std::abs(tilt.value[0]) < 1e-9);
    QVERIFY(std::abs(tilt.value[1] - 4.0) < 1e-6);
    QVERIFY(std::abs(tilt.value[2] - 10.0) < 1e-6);
    QCOMPARE(tilt.threshold, 8.0);
    // Slip: the belt ran 10 cm ahead of a pallet that stayed put.
    QVERIFY(std::abs(curves[TracePlots::Slip].value[1] - 10.0) < 1e-9);
    QCOMPARE(curves[TracePlots::Slip].threshold, 30.0);
    QCOMPARE(curves[TracePlots::ItemSlide].threshold, 5.0);
    QCOMPARE(curves[TracePlots::LoadShift].threshold, 2.0);
  }

  // The CSV export holds the same numbers as the curves, a row per frame.
  void csvIsTheCurves() {
    const pb::Replay replay = synthetic();
    const auto curves = TracePlots::measure(replay, DetectorThresholds{});
    const QList<QByteArray> lines = TracePlots::csv(replay).trimmed().split('\n');
    QCOMPARE(lines.size(), static_cast<int>(curves[0].t.size()) + 1);
    QCOMPARE(lines.front().split(',').size(), 9);
    for (std::size_t k = 0; k < curves[0].t.size(); ++k) {
      const QList<QByteArray> cells = lines[static_cast<int>(k) + 1].split(',');
      QCOMPARE(cells.size(), 9);
      QVERIFY(qAbs(cells[0].toDouble() - curves[0].t[k]) < 1e-9);
      for (int q = 0; q < TracePlots::kQuantities; ++q) {
        QVERIFY(qAbs(cells[q + 1].toDouble() - curves[std::size_t(q)].value[k]) < 1e-9);
        QVERIFY(qAbs(cells[q + 5].toDouble() - curves[std::size_t(q)].threshold) < 1e-9);
      }
    }
  }

  void seriesThresholdsAndCursor() {
    TracePlots plots;
    plots.setReplay(synthetic());
    for (int q = 0; q < TracePlots::kQuantities; ++q) {
      const auto quantity = static_cast<TracePlots::Quantity>(q);
      QCOMPARE(plots.chart(quantity)->series().size(), 3);
      QCOMPARE(plots.series(quantity)->count(), 3);
      QCOMPARE(plots.thresholdLine(quantity)->count(), 2);
    }
    QCOMPARE(plots.thresholdLine(TracePlots::Tilt)->at(0).y(), 8.0);
    QCOMPARE(plots.thresholdLine(TracePlots::Tilt)->at(1).x(), 1.0);
    QCOMPARE(plots.series(TracePlots::Tilt)->at(2).x(), 1.0);
    // The cursor starts at the beginning, follows, and is clamped to the replay.
    QCOMPARE(plots.cursorLine(TracePlots::Tilt)->at(0).x(), 0.0);
    plots.setCursorTime(0.6);
    for (int q = 0; q < TracePlots::kQuantities; ++q) {
      const QLineSeries* c = plots.cursorLine(static_cast<TracePlots::Quantity>(q));
      QCOMPARE(c->count(), 2);
      QCOMPARE(c->at(0).x(), 0.6);
      QCOMPARE(c->at(1).x(), 0.6);
      QVERIFY(c->at(1).y() > c->at(0).y());
    }
    plots.setCursorTime(7.0);
    QCOMPARE(plots.cursorTime(), 1.0);
    plots.clear();
    QCOMPARE(plots.series(TracePlots::Tilt)->count(), 0);
  }

  // The readout under the plots gives every quantity at the cursor, between frames linearly, with
  // its threshold; without a replay it says how to get one.
  void readoutIsEveryQuantityAtTheCursor() {
    TracePlots plots;
    QVERIFY(plots.readout().startsWith(QStringLiteral("No replay")));
    plots.setReplay(synthetic());
    plots.setCursorTime(0.25);  // halfway from rest to 4 deg and 10 cm of slip
    QVERIFY2(plots.readout().startsWith(QStringLiteral("At 0.250 s: tilt 2.00 deg (limit 8)")),
             qPrintable(plots.readout()));
    QVERIFY2(plots.readout().contains(QStringLiteral("slip 5.0 cm (limit 30)")),
             qPrintable(plots.readout()));
    QVERIFY2(plots.readout().contains(QStringLiteral("load shift 0.0 cm (limit 2)")),
             qPrintable(plots.readout()));
    plots.setCursorTime(1.0);
    QVERIFY2(plots.readout().startsWith(QStringLiteral("At 1.000 s: tilt 10.00 deg")),
             qPrintable(plots.readout()));
    QCOMPARE(TracePlots::valueAt(TracePlots::Curve{}, 0.5), 0.0);
    const TracePlots::Curve c{{0.0, 1.0}, {2.0, 4.0}, 0.0};
    QCOMPARE(TracePlots::valueAt(c, -1.0), 2.0);
    QCOMPARE(TracePlots::valueAt(c, 0.5), 3.0);
    QCOMPARE(TracePlots::valueAt(c, 9.0), 4.0);
  }

  // A click on a plot, and a drag along it, ask for the time under the mouse; outside the
  // replay's range, its nearest end.
  void clickingAPlotAsksForItsTime() {
    TracePlots plots;
    plots.resize(900, 600);
    plots.setReplay(synthetic());
    plots.show();
    QVERIFY(QTest::qWaitForWindowExposed(&plots));
    QSignalSpy asked(&plots, &TracePlots::timeRequested);
    for (const auto q : {TracePlots::Tilt, TracePlots::Slip}) {
      QChartView* view = plots.view(q);
      const auto at = [&](double t) {
        const QPointF scene = plots.chart(q)->mapToScene(
            plots.chart(q)->mapToPosition(QPointF(t, 0.5), plots.series(q)));
        return view->mapFromScene(scene);
      };
      QTest::mouseClick(view->viewport(), Qt::LeftButton, {}, at(0.75));
      QCOMPARE(asked.size(), 1);
      QVERIFY2(std::abs(asked.takeFirst()[0].toDouble() - 0.75) < 0.01,
               "the click's time is the one under the mouse");
      QTest::mousePress(view->viewport(), Qt::LeftButton, {}, at(0.2));
      QMouseEvent move(QEvent::MouseMove, at(0.4), view->viewport()->mapToGlobal(at(0.4)),
                       Qt::NoButton, Qt::LeftButton, Qt::NoModifier);
      QApplication::sendEvent(view->viewport(), &move);
      QTest::mouseRelease(view->viewport(), Qt::LeftButton, {}, at(0.4));
      QCOMPARE(asked.size(), 2);
      QVERIFY(std::abs(asked[0][0].toDouble() - 0.2) < 0.01);
      QVERIFY(std::abs(asked[1][0].toDouble() - 0.4) < 0.01);
      asked.clear();
      QTest::mouseClick(view->viewport(), Qt::LeftButton, {}, at(5.0));
      QCOMPARE(asked.size(), 1);
      QCOMPARE(asked.takeFirst()[0].toDouble(), 1.0);
    }
  }

  // No label of any plot is elided ("...") at the sizes the console gives the plots, from a
  // 1024x768 window up; the tower's replay has the widest numbers (to 300 cm).
  void noLabelIsElided_data() {
    QTest::addColumn<QSize>("size");
    QTest::newRow("1024x768 console") << QSize(500, 300);
    QTest::newRow("1280x800 console") << QSize(700, 330);
    QTest::newRow("1920x1080 console") << QSize(1100, 370);
  }
  void noLabelIsElided() {
    QFETCH(QSize, size);
    const auto scenario = load_scenario("tall-unwrapped-tower");
    Analyzer analyzer;
    const auto solve = analyzer.solve(scenario->pallet, scenario->suggested_profile);
    QVERIFY(solve.ok());
    TracePlots plots;
    plots.resize(size);
    plots.show();
    QVERIFY(QTest::qWaitForWindowExposed(&plots));
    plots.setReplay(solve->replay);
    QTest::qWait(50);
    QStringList elided;
    for (int q = 0; q < TracePlots::kQuantities; ++q) {
      QGraphicsScene* scene = plots.chart(TracePlots::Quantity(q))->scene();
      for (QGraphicsItem* item : scene->items()) {
        QString text;
        if (auto* t = dynamic_cast<QGraphicsTextItem*>(item)) text = t->toPlainText();
        if (auto* t = dynamic_cast<QGraphicsSimpleTextItem*>(item)) text = t->text();
        if (item->isVisible() &&
            (text.contains(QChar(0x2026)) || text.endsWith(QStringLiteral("..."))))
          elided << QStringLiteral("plot %1: '%2'").arg(q).arg(text);
      }
    }
    QVERIFY2(elided.isEmpty(), qPrintable(elided.join(QStringLiteral(" | "))));
    // Time is labelled at a round interval (1, 2 or 5 x 10^k s) from zero, at least three labels
    // across the run (Qt's default five ticks put them at quarters of the run: 0.29, 0.59, ...).
    for (int q = 0; q < TracePlots::kQuantities; ++q) {
      for (QAbstractAxis* axis : plots.chart(TracePlots::Quantity(q))->axes(Qt::Horizontal)) {
        const auto* x = static_cast<QValueAxis*>(axis);
        QCOMPARE(x->tickType(), QValueAxis::TicksDynamic);
        QCOMPARE(x->tickAnchor(), 0.0);
        const double mantissa =
            x->tickInterval() / std::pow(10.0, std::floor(std::log10(x->tickInterval())));
        QVERIFY2(std::abs(mantissa - 1.0) < 1e-9 || std::abs(mantissa - 2.0) < 1e-9 ||
                     std::abs(mantissa - 5.0) < 1e-9,
                 qPrintable(QString::number(x->tickInterval())));
        QVERIFY((x->max() - x->min()) / x->tickInterval() >= 2.0);
      }
    }
  }

  void aRealFailureCrossesItsThresholdAtTheEnd() {
    const auto scenario = load_scenario("tall-unwrapped-tower");
    QVERIFY(scenario.ok());
    Analyzer analyzer;
    const auto solve = analyzer.solve(scenario->pallet, scenario->suggested_profile);
    QVERIFY(solve.ok());
    const Replay& replay = solve->replay;
    QCOMPARE(QString::fromStdString(replay.outcome), QStringLiteral("failed"));
    const FailureEvent& event = *replay.failure;
    const auto curves = TracePlots::measure(replay, DetectorThresholds{});
    TracePlots::Quantity q = TracePlots::Tilt;
    double scale = 1.0;
    switch (event.mode) {
      case FailureMode::tip_over:
        break;
      case FailureMode::top_item_slide:
        q = TracePlots::ItemSlide, scale = 100.0;
        break;
      case FailureMode::load_shift:
        q = TracePlots::LoadShift, scale = 100.0;
        break;
      case FailureMode::pallet_slip:
        q = TracePlots::Slip, scale = 100.0;
        break;
      case FailureMode::no_failure:
      case FailureMode::cannot_stand:
        QFAIL("a failed replay without a conveyor mode");
    }
    const auto& c = curves[q];
    // The frame at the failure's instant is the moment the detector fired: over the threshold,
    // with its value (the replay rounds positions to 0.01 mm, hence the tolerance) ...
    std::size_t fired = 0;
    while (fired < replay.frames.size() && replay.frames[fired].t != event.time_s) ++fired;
    QVERIFY(fired < c.value.size());
    QVERIFY(c.value[fired] > c.threshold);
    QVERIFY2(std::abs(c.value[fired] - scale * event.value) < 0.01 * scale * event.value + 0.01,
             qPrintable(QStringLiteral("%1 vs %2").arg(c.value[fired]).arg(scale * event.value)));
    // ... below it before (the detector fires at the first crossing), and the wreck after it.
    for (std::size_t i = 0; i < fired; ++i) QVERIFY(c.value[i] <= c.threshold + 1e-6);
    QVERIFY(fired + 1 < c.value.size());

    TracePlots plots;
    plots.resize(800, 520);
    plots.setReplay(replay);
    plots.setCursorTime(event.time_s);
    // The wreck after the failure (the carton falls off and stays behind: metres) does not set the
    // scale: the threshold stays in view with room above it, the curve leaves the top, and the
    // readout says how far it went.
    const double peak = *std::max_element(c.value.begin(), c.value.end());
    QVERIFY2(peak > 20.0 * c.threshold, qPrintable(QString::number(peak)));
    const auto* y = static_cast<QValueAxis*>(plots.chart(q)->axes(Qt::Vertical).first());
    QVERIFY(y->max() >= 1.25 * c.threshold);
    QVERIFY2(y->max() <= 10.0 * c.threshold, qPrintable(QString::number(y->max())));
    const QString unit = q == TracePlots::Tilt ? QStringLiteral(" deg") : QStringLiteral(" cm");
    QVERIFY2(plots.readout().contains(QStringLiteral("Off scale: ")) &&
                 plots.readout().contains(QStringLiteral("up to ") + QString::number(peak, 'f', 0) +
                                          unit),
             qPrintable(plots.readout()));
    QVERIFY(QDir().mkpath(QStringLiteral(PB_TEST_ARTIFACTS_DIR)));
    QVERIFY(plots.grab().save(QStringLiteral(PB_TEST_ARTIFACTS_DIR "/panel_trace_plots.png")));
  }
};

QTEST_MAIN(TestTracePlots)
#include "tst_trace_plots.moc"
