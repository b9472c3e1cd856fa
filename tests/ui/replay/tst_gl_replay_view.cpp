// SPDX-License-Identifier: MIT
// The replay view, drawn for real (Xvfb + Mesa): at the failure time of the tall unwrapped tower
// the failing item is red where its replay pose puts it, the other items and the pallet have their
// own colours there, and far from the load is background. The screenshot is kept as an artifact.
#include <QDir>
#include <QImage>
#include <QTest>
#include <cmath>

#include "core/analysis/analyzer.hpp"
#include "core/inputs/scenario.hpp"
#include "ui/replay/replay_view.hpp"
#include "ui/widgets/sku_color.hpp"

using pb::ui::ReplayView;

namespace {

constexpr QSize kSize(800, 600);

QVector3D toQt(const pb::Vec3& v) {
  return QVector3D(static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2]));
}

/// Hue distance in degrees (0..180).
int hueDistance(const QColor& a, const QColor& b) {
  const int d = std::abs(a.hsvHue() - b.hsvHue());
  return std::min(d, 360 - d);
}

QString describe(const QColor& c) {
  return QStringLiteral("rgb(%1, %2, %3)").arg(c.red()).arg(c.green()).arg(c.blue());
}

}  // namespace

class TestGlReplayView : public QObject {
  Q_OBJECT

 private:
  pb::Replay _replay;

  /// The shaded colour at a pixel must be `base` scaled by a Lambert term: same hue, not darker
  /// than the shader's ambient floor.
  static void verifyShadeOf(const QImage& image, QPointF at, const QColor& base) {
    const QColor seen = image.pixelColor(at.toPoint());
    QVERIFY2(seen != ReplayView::backgroundColor(), qPrintable(describe(seen)));
    QVERIFY2(hueDistance(seen, base) <= 6,
             qPrintable(describe(seen) + QStringLiteral(" vs ") + describe(base)));
    QVERIFY2(seen.value() >= base.value() / 2 && seen.value() <= base.value() + 1,
             qPrintable(describe(seen) + QStringLiteral(" vs ") + describe(base)));
  }

 private slots:
  void initTestCase() {
    auto scenario = pb::load_scenario("tall-unwrapped-tower");
    QVERIFY(scenario.ok());
    pb::Analyzer analyzer;
    auto solve = analyzer.solve(scenario->pallet, scenario->suggested_profile);
    QVERIFY(solve.ok());
    _replay = solve->replay;
    QCOMPARE(_replay.outcome, std::string("failed"));
    QVERIFY(_replay.failure.has_value());
    QCOMPARE(_replay.failure->mode, pb::FailureMode::top_item_slide);
    QCOMPARE(_replay.failure->items, std::vector<int>{7});
  }

  void openGlIsAvailableUnderXvfb() { QCOMPARE(ReplayView::probeOpenGl(), QString()); }

  void interpolatesBetweenFrames() {
    QVERIFY(_replay.frames.size() > 3);
    const pb::ReplayFrame& a = _replay.frames[2];
    const pb::ReplayFrame& b = _replay.frames[3];
    const pb::ReplayFrame mid = ReplayView::frameAt(_replay, (a.t + b.t) / 2.0);
    QCOMPARE(mid.belt_x, (a.belt_x + b.belt_x) / 2.0);
    QCOMPARE(mid.items.size(), a.items.size());
    const pb::Pose expected = pb::interpolate(a.items[7], b.items[7], 0.5);
    for (int k = 0; k < 3; ++k) QVERIFY(std::abs(mid.items[7].pos[k] - expected.pos[k]) < 1e-12);
    for (int k = 0; k < 4; ++k) QVERIFY(std::abs(mid.items[7].quat[k] - expected.quat[k]) < 1e-12);
    QVERIFY(mid.items[7] != a.items[7]);  // the item moves between these frames
    QCOMPARE(ReplayView::frameAt(_replay, -1.0), _replay.frames.front());
    QCOMPARE(ReplayView::frameAt(_replay, 99.0), _replay.frames.back());
  }

  void drawsTheFailure() {
    ReplayView view;
    view.resize(kSize);
    view.setReplay(_replay);
    view.setPreset(pb::ui::CameraPreset::iso);
    view.setTime(_replay.failure->time_s);
    view.show();
    QVERIFY(QTest::qWaitForWindowExposed(&view));
    const QImage image = view.grabFramebuffer();
    QVERIFY2(view.glProblem().isEmpty(), qPrintable(view.glProblem()));
    QCOMPARE(image.size(), kSize);  // device pixel ratio 1

    QVERIFY(QDir().mkpath(QStringLiteral(PB_TEST_ARTIFACTS_DIR)));
    const QString path = QStringLiteral(PB_TEST_ARTIFACTS_DIR "/replay_tall-unwrapped-tower.png");
    QVERIFY(image.save(path));
    qInfo("screenshot: %s", qPrintable(path));

    const pb::ReplayFrame& frame = view.currentFrame();
    QCOMPARE(frame.t, _replay.failure->time_s);
    // The failing (top) item: the highlight, unlit, at the projected centre of its top face (its
    // centre proper lies behind the outline of its nearest vertical edge in this view).
    const pb::Pose& top = frame.items[7];
    const pb::Vec3 up = pb::rotate(top.quat, {0.0, 0.0, _replay.pallet.items[7].dims_m[2] / 2.0});
    const QPointF failing =
        view.project(toQt({top.pos[0] + up[0], top.pos[1] + up[1], top.pos[2] + up[2]}));
    QCOMPARE(image.pixelColor(failing.toPoint()), ReplayView::highlightColor());
    // A non-failing item: its SKU colour, shaded.
    const QColor sku = pb::ui::skuColor(_replay.pallet.items[3].sku);
    verifyShadeOf(image, view.project(toQt(frame.items[3].pos)), sku);
    QVERIFY(image.pixelColor(view.project(toQt(frame.items[3].pos)).toPoint()) !=
            ReplayView::highlightColor());
    // The pallet: the centre of its front (+X) face, which faces the iso camera.
    const double half = _replay.pallet.base_dims_m[0] / 2.0;
    const pb::Vec3 front = pb::rotate(frame.pallet.quat, {half, 0.0, 0.0});
    const QPointF palletFront =
        view.project(toQt({frame.pallet.pos[0] + front[0], frame.pallet.pos[1] + front[1],
                           frame.pallet.pos[2] + front[2]}));
    verifyShadeOf(image, palletFront, QColor(176, 132, 84));
    // Far from the load, above the horizon of the grid: background.
    QCOMPARE(image.pixelColor(8, 8), ReplayView::backgroundColor());
  }

  // Cartons of one SKU stacked in a column read as separate boxes: the edge where one carton's
  // front face meets the next one's is drawn dark (edgeColor), the faces around it in their shade.
  void everyCartonShowsItsEdges() {
    ReplayView view;
    view.resize(kSize);
    view.setReplay(_replay);
    view.setPreset(pb::ui::CameraPreset::iso);
    view.setTime(_replay.frames.front().t);  // at rest: the column stands straight
    view.show();
    QVERIFY(QTest::qWaitForWindowExposed(&view));
    const QImage image = view.grabFramebuffer();
    QVERIFY2(view.glProblem().isEmpty(), qPrintable(view.glProblem()));
    const QString path = QStringLiteral(PB_TEST_ARTIFACTS_DIR "/replay_edges_at_rest.png");
    QVERIFY(QDir().mkpath(QStringLiteral(PB_TEST_ARTIFACTS_DIR)) && image.save(path));
    qInfo("screenshot: %s", qPrintable(path));
    const pb::ReplayFrame& frame = view.currentFrame();
    for (int i : {2, 3}) {
      const pb::Item& item = _replay.pallet.items[std::size_t(i)];
      const pb::Item& above = _replay.pallet.items[std::size_t(i) + 1];
      QCOMPARE(above.sku, item.sku);  // one SKU: without edges, one block
      const pb::Pose& p = frame.items[std::size_t(i)];
      auto onFront = [&](double z) {  // a point on the item's front (+X) face, z from its centre
        const pb::Vec3 v = pb::rotate(p.quat, {item.dims_m[0] / 2.0, 0.0, z});
        return view.project(toQt({p.pos[0] + v[0], p.pos[1] + v[1], p.pos[2] + v[2]}));
      };
      const QColor face = image.pixelColor(onFront(0.0).toPoint());
      verifyShadeOf(image, onFront(0.0), pb::ui::skuColor(item.sku));
      // The darkest pixel within 2 px of the projected top edge is far darker than the face (a
      // line 1 px wide lands within a pixel of where it projects, blended where it covers part).
      const QPoint edge = onFront(item.dims_m[2] / 2.0).toPoint();
      int darkest = 255;
      for (int dy = -2; dy <= 2; ++dy) {
        darkest = std::min(darkest, image.pixelColor(edge + QPoint(0, dy)).value());
      }
      QVERIFY2(darkest <= face.value() * 6 / 10,
               qPrintable(QStringLiteral("item %1: darkest %2 near its top edge, face %3")
                              .arg(i)
                              .arg(darkest)
                              .arg(describe(face))));
    }
  }

  // Following the failing item centres it and closes in on it (it looks at least twice as big as
  // in the preset's view); following stops, the view steps back to where it was.
  void followKeepsTheFailingItemCentred() {
    ReplayView view;
    view.resize(kSize);
    view.setReplay(_replay);
    view.setTime(_replay.failure->time_s);
    const pb::Pose item = view.currentFrame().items[7];
    const double half = _replay.pallet.items[7].dims_m[2] / 2.0;
    const auto apparent = [&] {  // the projected length of the item's vertical axis
      const QPointF a = view.project(toQt({item.pos[0], item.pos[1], item.pos[2] - half}));
      const QPointF b = view.project(toQt({item.pos[0], item.pos[1], item.pos[2] + half}));
      return std::hypot(a.x() - b.x(), a.y() - b.y());
    };
    const double before = apparent();
    const float distance = view.camera().distance;
    view.setFollowFailure(true);
    const QPointF centre = view.project(toQt(view.currentFrame().items[7].pos));
    QVERIFY(std::abs(centre.x() - kSize.width() / 2.0) < 0.5);
    QVERIFY(std::abs(centre.y() - kSize.height() / 2.0) < 0.5);
    QVERIFY2(apparent() >= 2.0 * before,
             qPrintable(QStringLiteral("%1 px -> %2 px").arg(before).arg(apparent())));
    view.show();
    QVERIFY(QTest::qWaitForWindowExposed(&view));
    const QString path = QStringLiteral(PB_TEST_ARTIFACTS_DIR "/replay_follow_failure.png");
    QVERIFY(QDir().mkpath(QStringLiteral(PB_TEST_ARTIFACTS_DIR)) &&
            view.grabFramebuffer().save(path));
    qInfo("screenshot: %s", qPrintable(path));
    view.setFollowFailure(false);
    QCOMPARE(view.camera().distance, distance);
  }

  // The replay goes on after the failure (the wreck); the camera rides along with the pallet, so
  // at the end, metres down the belt, the pallet is where it was in the view at the start, and
  // drawn there. The end's picture is kept as an artifact.
  void theCameraRidesAlongToTheWreck() {
    ReplayView view;
    view.resize(kSize);
    view.setReplay(_replay);
    view.show();
    QVERIFY(QTest::qWaitForWindowExposed(&view));
    const QPointF start = view.project(toQt(view.currentFrame().pallet.pos));
    const pb::Vec3 startPos = view.currentFrame().pallet.pos;
    view.setTime(_replay.frames.back().t);
    QVERIFY(_replay.frames.back().t > _replay.failure->time_s + 0.25);
    const pb::Pose end = view.currentFrame().pallet;
    QVERIFY(std::hypot(end.pos[0] - startPos[0], end.pos[1] - startPos[1]) > 1.0);  // travelled
    const QPointF there = view.project(toQt({end.pos[0], end.pos[1], startPos[2]}));
    QVERIFY(std::abs(there.x() - start.x()) < 1.0 && std::abs(there.y() - start.y()) < 1.0);
    const QImage image = view.grabFramebuffer();
    const QPointF deck = view.project(toQt(end.pos));
    QVERIFY(image.pixelColor(deck.toPoint()) != ReplayView::backgroundColor());
    QVERIFY(QDir().mkpath(QStringLiteral(PB_TEST_ARTIFACTS_DIR)));
    QVERIFY(
        image.save(QStringLiteral(PB_TEST_ARTIFACTS_DIR "/replay_tall-unwrapped-tower_end.png")));
  }
};

QTEST_MAIN(TestGlReplayView)
#include "tst_gl_replay_view.moc"
