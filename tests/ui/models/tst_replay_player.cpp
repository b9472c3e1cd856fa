// SPDX-License-Identifier: MIT
// The replay's clock and transport bar, headless: speeds, automatic slow motion around the
// failure (integrated exactly across its start), frame steps on the 30 Hz grid, clamping, the
// timeline's mapping and failure mark, and the controls' readout. The bar's PNG is an artifact.
#include <QComboBox>
#include <QDir>
#include <QSignalSpy>
#include <QTest>

#include "ui/models/replay_player.hpp"
#include "ui/replay/replay_controls.hpp"
#include "ui/widgets/timeline.hpp"

using pb::ui::ReplayControls;
using pb::ui::ReplayPlayer;
using pb::ui::Timeline;

namespace {

/// A replay of frames k / 30 for k = 0..60 (2 s) plus, if failed, a last frame at `end`.
pb::Replay replay(double end, bool failed) {
  pb::Replay r;
  for (int k = 0; k / 30.0 < end - 1e-9; ++k) {
    pb::ReplayFrame f;
    f.t = k / 30.0;
    r.frames.push_back(f);
  }
  pb::ReplayFrame last;
  last.t = end;
  r.frames.push_back(last);
  if (failed) {
    r.outcome = "failed";
    r.failure = pb::FailureEvent{pb::FailureMode::top_item_slide, end, 0.0, {0}, 0.0};
  }
  return r;
}

}  // namespace

class TestReplayPlayer : public QObject {
  Q_OBJECT

 private slots:
  void rateAroundTheFailure() {
    const std::optional<double> f = 1.0;
    QCOMPARE(ReplayPlayer::rateAt(0.49, 1.0, true, f), 1.0);
    QCOMPARE(ReplayPlayer::rateAt(0.5, 1.0, true, f), 0.25);
    QCOMPARE(ReplayPlayer::rateAt(2.5, 1.0, true, f), 0.25);  // the wreck, well after it
    QCOMPARE(ReplayPlayer::rateAt(2.51, 1.0, true, f), 1.0);
    QCOMPARE(ReplayPlayer::rateAt(0.8, 0.5, false, f), 0.5);            // switched off
    QCOMPARE(ReplayPlayer::rateAt(0.8, 0.5, true, std::nullopt), 0.5);  // nothing failed
    QCOMPARE(ReplayPlayer::rateAt(0.8, 0.25, true, f), 0.25);           // never faster than chosen
  }

  void advanceSlowsDownAtTheFailure() {
    ReplayPlayer player;
    player.setReplay(replay(1.3, true));
    QCOMPARE(player.failureTime(), std::optional<double>(1.3));
    QCOMPARE(player.time(), 0.0);
    // 0.5 s of wall time at 1x, then slow motion from 0.8 s: 0.3 s of replay took 0.3 s, the
    // remaining 0.2 s of wall time play 0.05 s.
    player.advance(0.5);
    QVERIFY(qAbs(player.time() - 0.5) < 1e-9);
    QVERIFY(!player.inSlowMotion());
    player.advance(0.5);
    QVERIFY2(qAbs(player.time() - 0.85) < 1e-9, qPrintable(QString::number(player.time())));
    QVERIFY(player.inSlowMotion());
    QCOMPARE(player.rate(), 0.25);
    player.setAutoSlowMotion(false);
    QCOMPARE(player.rate(), 1.0);
  }

  void speedsAndTheEnd() {
    ReplayPlayer player;
    player.setReplay(replay(2.0, false));
    QSignalSpy playing(&player, &ReplayPlayer::playingChanged);
    player.setSpeed(0.5);
    player.advance(1.0);
    QVERIFY(qAbs(player.time() - 0.5) < 1e-9);
    player.setSpeed(0.25);
    player.advance(1.0);
    QVERIFY(qAbs(player.time() - 0.75) < 1e-9);
    player.play();
    QVERIFY(player.isPlaying());
    player.advance(100.0);  // past the end: stops there, paused
    QCOMPARE(player.time(), 2.0);
    QVERIFY(!player.isPlaying());
    QCOMPARE(playing.count(), 2);
    player.play();  // from the end: starts over
    QCOMPARE(player.time(), 0.0);
    player.pause();
  }

  void playsInRealTimeOnTheTimer() {
    ReplayPlayer player;
    player.setReplay(replay(2.0, false));
    player.play();
    QTRY_VERIFY_WITH_TIMEOUT(player.time() > 0.05, 5000);
    player.pause();
    const double t = player.time();
    QTest::qWait(50);
    QCOMPARE(player.time(), t);  // paused means paused
  }

  void stepsLandOnTheFrameGrid() {
    ReplayPlayer player;
    player.setReplay(replay(1.01, true));  // last frame 1.01 s, off the 30 Hz grid
    player.step(1);
    QCOMPARE(player.time(), 1.0 / 30.0);
    player.step(2);
    QCOMPARE(player.time(), 3.0 / 30.0);
    player.setTime(0.11);  // between frames 3 and 4
    player.step(-1);
    QCOMPARE(player.time(), 3.0 / 30.0);
    player.setTime(0.11);
    player.step(1);
    QCOMPARE(player.time(), 4.0 / 30.0);
    player.setTime(1.0);
    player.step(1);  // past the last grid frame: the last frame itself
    QCOMPARE(player.time(), 1.01);
    player.step(-1);
    QCOMPARE(player.time(), 1.0);
    player.setTime(0.0);
    player.step(-1);
    QCOMPARE(player.time(), 0.0);  // clamped
    player.setTime(-5.0);
    QCOMPARE(player.time(), 0.0);
    player.setTime(std::nan(""));
    QCOMPARE(player.time(), 0.0);
    player.play();
    player.step(1);
    QVERIFY(!player.isPlaying());  // stepping pauses
  }

  void timelineMapsTimeToPixels() {
    Timeline timeline;
    timeline.resize(216, 30);  // 200 px of bar between 8 px margins
    timeline.setRange(0.0, 2.0);
    QCOMPARE(timeline.xForTime(0.0), 8.0);
    QCOMPARE(timeline.xForTime(1.0), 108.0);
    QCOMPARE(timeline.xForTime(5.0), 208.0);
    QCOMPARE(timeline.timeForX(58.0), 0.5);
    QCOMPARE(timeline.timeForX(-10.0), 0.0);
    QSignalSpy seek(&timeline, &Timeline::seekRequested);
    QTest::mouseClick(&timeline, Qt::LeftButton, {}, QPoint(158, 15));
    QCOMPARE(seek.count(), 1);
    QCOMPARE(seek.at(0).at(0).toDouble(), 1.5);
  }

  void controlsShowTheFailureAndSlowMotion() {
    ReplayPlayer player;
    ReplayControls controls(&player);
    controls.resize(900, 90);
    QVERIFY(controls.readout().startsWith(QStringLiteral("No replay yet")));
    player.setReplay(replay(1.3, true));
    controls.refresh();
    QCOMPARE(controls.timeline()->failureTime(), std::optional<double>(1.3));
    QCOMPARE(controls.timeline()->end(), 1.3);
    player.setTime(1.0);
    QCOMPARE(controls.timeline()->time(), 1.0);
    QCOMPARE(controls.readout(), QStringLiteral("t = 1.000 s of 1.300 s \u00b7 failure at 1.300 s "
                                                "\u00b7 slow motion \u00bc\u00d7"));
    controls.speedBox()->setCurrentIndex(1);
    QCOMPARE(player.speed(), 0.5);
    player.setTime(0.2);
    QCOMPARE(
        controls.readout(),
        QStringLiteral("t = 0.200 s of 1.300 s \u00b7 failure at 1.300 s \u00b7 \u00bd\u00d7"));
    // The failure mark is red on the timeline, where its time maps.
    controls.show();
    const QImage image = controls.grab().toImage();
    QVERIFY(QDir().mkpath(QStringLiteral(PB_TEST_ARTIFACTS_DIR)));
    QVERIFY(image.save(QStringLiteral(PB_TEST_ARTIFACTS_DIR "/panel_replay_controls.png")));
    Timeline* t = controls.timeline();
    const QPoint mark = t->mapTo(&controls, QPoint(qRound(t->xForTime(1.3)), 4));
    QCOMPARE(image.pixelColor(mark * image.devicePixelRatio()), Timeline::failureColor());
  }
};

QTEST_MAIN(TestReplayPlayer)
#include "tst_replay_player.moc"
