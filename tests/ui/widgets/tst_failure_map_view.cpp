// SPDX-License-Identifier: MIT
// The failure-map heatmap: cells painted in their verdict's colour at their place (pixels), the
// non-monotone mark, the dialled point's ring, and an inconsistent grid refused with a message.
#include <QDir>
#include <QtTest>

#include "ui/widgets/failure_map_view.hpp"

using namespace pb;
using namespace pb::ui;
using Cell = FailureMapView::Cell;

namespace {

int distance(QColor a, QColor b) {
  return std::max({std::abs(a.red() - b.red()), std::abs(a.green() - b.green()),
                   std::abs(a.blue() - b.blue())});
}

/// 3 speeds x 2 accelerations.
FailureMapView::Grid grid() {
  FailureMapView::Grid g;
  g.speeds_mps = {0.5, 1.0, 1.5};
  g.accels_mps2 = {1.0, 2.0};
  g.cells = {
      {Outcome::safe, FailureMode::no_failure, false},        // (0.5, 1)
      {Outcome::safe, FailureMode::no_failure, false},        // (1.0, 1)
      {Outcome::failed, FailureMode::tip_over, false},        // (1.5, 1)
      {Outcome::safe, FailureMode::no_failure, true},         // (0.5, 2), non-monotone
      {Outcome::failed, FailureMode::top_item_slide, false},  // (1.0, 2)
      {Outcome::unstable, FailureMode::no_failure, false},    // (1.5, 2)
  };
  return g;
}

}  // namespace

class TestFailureMapView : public QObject {
  Q_OBJECT

 private slots:
  void coloursDifferByVerdictAndMode() {
    const QColor safe = FailureMapView::cellColor({Outcome::safe, FailureMode::no_failure, false});
    const QColor tip = FailureMapView::cellColor({Outcome::failed, FailureMode::tip_over, false});
    const QColor slide =
        FailureMapView::cellColor({Outcome::failed, FailureMode::top_item_slide, false});
    const QColor unstable =
        FailureMapView::cellColor({Outcome::unstable, FailureMode::no_failure, false});
    QVERIFY(distance(safe, tip) > 80);
    QVERIFY(distance(tip, slide) > 80);
    QVERIFY(distance(unstable, safe) > 80);
  }

  void cellsArePaintedWhereTheyBelong() {
    FailureMapView view;
    view.resize(420, 320);
    const FailureMapView::Grid g = grid();
    view.setGrid(g);
    QVERIFY(view.hasGrid());
    // The dialled point sits on the centre of the (1.0 m/s, 2.0 m/s^2) cell.
    view.setDialledPoint(1.0, 2.0);
    const QImage image = view.grab().toImage();
    for (int a = 0; a < 2; ++a) {
      for (int s = 0; s < 3; ++s) {
        const QRectF r = view.cellRect(s, a);
        QVERIFY(r.width() > 20 && r.height() > 20);
        // A point off the centre (the ring is there in one cell) but well inside the cell.
        const QPoint p = (r.center() + QPointF(r.width() * 0.3, r.height() * 0.3)).toPoint();
        const QColor want = FailureMapView::cellColor(g.cells[static_cast<std::size_t>(a * 3 + s)]);
        QVERIFY2(distance(image.pixelColor(p), want) < 10,
                 qPrintable(QStringLiteral("cell (%1, %2)").arg(s).arg(a)));
      }
    }
    // Higher accelerations are drawn higher up, higher speeds further right.
    QVERIFY(view.cellRect(0, 1).center().y() < view.cellRect(0, 0).center().y());
    QVERIFY(view.cellRect(2, 0).center().x() > view.cellRect(0, 0).center().x());
    // Non-monotone mark: black in the cell's top-left corner.
    const QRectF nm = view.cellRect(0, 1);
    QVERIFY(distance(image.pixelColor((nm.topLeft() + QPointF(3, 3)).toPoint()), Qt::black) < 30);
    const QRectF plain = view.cellRect(1, 0);
    QVERIFY(distance(image.pixelColor((plain.topLeft() + QPointF(3, 3)).toPoint()), Qt::black) >
            80);
    // The dialled ring: dark on its circle (radius 7), the cell's colour at its centre.
    const QPointF c = view.valuePoint(1.0, 2.0);
    QCOMPARE(c, view.cellRect(1, 1).center());
    QVERIFY(distance(image.pixelColor((c + QPointF(7, 0)).toPoint()), Qt::black) < 60);
    QVERIFY(distance(image.pixelColor(c.toPoint()), FailureMapView::cellColor(g.cells[4])) < 10);

    QVERIFY(QDir().mkpath(QStringLiteral(PB_TEST_ARTIFACTS_DIR)));
    QVERIFY(image.save(QStringLiteral(PB_TEST_ARTIFACTS_DIR "/panel_failure_map.png")));
  }

  void dialledPointBetweenCellsInterpolates() {
    FailureMapView view;
    view.resize(420, 320);
    view.setGrid(grid());
    const QPointF a = view.valuePoint(0.5, 1.0), b = view.valuePoint(1.0, 1.0);
    const QPointF mid = view.valuePoint(0.75, 1.0);
    QCOMPARE(mid.x(), (a.x() + b.x()) / 2.0);
    // Far outside the grid: clamped onto the plot, never off the widget.
    const QPointF far = view.valuePoint(10.0, 50.0);
    QVERIFY(view.rect().contains(far.toPoint()));
  }

  void coreMapIsShownWithItsNonMonotoneCells() {
    // A 2 x 2 map whose (fast, hard) cell is safe while the (slow, hard) one fails: the core's
    // summary flags it, and the view paints it in safe green with the black mark.
    FailureMap map;
    map.speeds_mps = {1.0, 2.0};
    map.accels_mps2 = {1.0, 2.0};
    map.cells.resize(4);
    map.at(0, 1).outcome = Outcome::failed;
    map.at(0, 1).mode = FailureMode::pallet_slip;
    map.line_cells.resize(2);
    summarise_map(map);
    QVERIFY(map.at(1, 1).non_monotone);
    FailureMapView view;
    view.resize(300, 260);
    view.setMap(map);
    QVERIFY(view.hasGrid());
    QCOMPARE(view.grid().cells.size(), std::size_t{4});
    QVERIFY(view.grid().cells[3].non_monotone);
    const QImage image = view.grab().toImage();
    const QRectF slow = view.cellRect(0, 1), fast = view.cellRect(1, 1);
    QVERIFY(distance(image.pixelColor(slow.center().toPoint()),
                     FailureMapView::cellColor(
                         {Outcome::failed, FailureMode::pallet_slip, false})) < 10);
    QVERIFY(distance(image.pixelColor((fast.topLeft() + QPointF(3, 3)).toPoint()), Qt::black) < 30);
  }

  // Every text is drawn whole: at the smallest size the view asks for, the legend (five entries
  // here) wraps into rows and nothing is cut; in a box too small for its labels, what does not
  // fit is named (the check that the console's screenshot test relies on can fail).
  void noTextIsCut() {
    FailureMapView view;
    view.setGrid(grid());
    view.resize(view.minimumSizeHint());
    QVERIFY(!view.grab().isNull());
    QVERIFY2(view.cutTexts().isEmpty(), qPrintable(view.cutTexts().join(QStringLiteral(" | "))));
    view.resize(160, 150);
    QVERIFY(!view.grab().isNull());
    QVERIFY(!view.cutTexts().isEmpty());
  }

  void inconsistentGridIsRefused() {
    FailureMapView view;
    FailureMapView::Grid g = grid();
    g.cells.pop_back();
    view.setGrid(g);
    QVERIFY(!view.hasGrid());
    QVERIFY(view.cellRect(0, 0).isEmpty());
    view.resize(300, 200);
    QVERIFY(!view.grab().isNull());  // paints the message, no crash
  }
};

QTEST_MAIN(TestFailureMapView)
#include "tst_failure_map_view.moc"
