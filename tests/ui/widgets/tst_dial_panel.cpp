// SPDX-License-Identifier: MIT
// The dial panel: dials and spin boxes stay in sync, Dispatch emits the dialled profile, the
// envelope stays hidden until the replay ends, then it is painted on the dials (pixels checked).
#include <QDir>
#include <QDoubleSpinBox>
#include <QPushButton>
#include <QSignalSpy>
#include <QtTest>

#include "core/inputs/scenario.hpp"
#include "ui/widgets/dial_panel.hpp"

using namespace pb;
using namespace pb::ui;

namespace {

SafetyResult envelope() {
  SafetyResult r;
  r.max_speed_mps = 1.5;
  r.max_accel_mps2 = 3.0;
  r.dominant_failure_mode = FailureMode::top_item_slide;
  return r;
}

/// Colour distance (max channel difference).
int distance(QColor a, QColor b) {
  return std::max({std::abs(a.red() - b.red()), std::abs(a.green() - b.green()),
                   std::abs(a.blue() - b.blue())});
}

QColor pixelAt(const QImage& image, QPointF p) {
  return image.pixelColor(p.toPoint());
}

}  // namespace

class TestDialPanel : public QObject {
  Q_OBJECT

 private slots:
  void dialAndSpinStayInSync() {
    DialPanel panel;
    QSignalSpy changed(&panel, &DialPanel::dialsChanged);
    panel.speedDial()->setValue(150);  // 1.50 m/s
    QCOMPARE(panel.speedSpin()->value(), 1.5);
    QCOMPARE(panel.speed(), 1.5);
    QCOMPARE(changed.count(), 1);
    QCOMPARE(changed.last().at(0).toDouble(), 1.5);
    panel.accelSpin()->setValue(2.75);
    QCOMPARE(panel.accelDial()->value(), 275);
    QCOMPARE(panel.accel(), 2.75);
    QCOMPARE(changed.count(), 2);
    QCOMPARE(changed.last().at(1).toDouble(), 2.75);
    panel.setSpeed(99.0);  // clamped to the dial's range
    QCOMPARE(panel.speed(), 2.0);
    QCOMPARE(panel.speedDial()->value(), 200);
  }

  void dispatchEmitsTheDialledProfile() {
    DialPanel panel;
    panel.setSpeed(1.2);
    panel.setAccel(2.4);
    QSignalSpy spy(&panel, &DialPanel::dispatchRequested);
    panel.dispatchButton()->click();
    QCOMPARE(spy.count(), 1);
    const auto p = spy.first().at(0).value<ConveyorProfile>();
    QCOMPARE(p.shape, ProfileShape::accel_hold);
    QCOMPARE(p.target_speed_mps, 1.2);
    QCOMPARE(p.accel_mps2, 2.4);
    QCOMPARE(p.duration_s, 1.2 / 2.4 + 2.0);
    QVERIFY(validate_profile(p).empty());
  }

  void envelopeHiddenUntilReplayEndsThenPainted() {
    DialPanel panel;
    panel.resize(420, 420);
    panel.setSpeed(1.35);
    panel.setAccel(2.7);
    QSignalSpy revealed(&panel, &DialPanel::scoreRevealed);
    panel.dispatch();
    panel.setEnvelope(envelope());
    panel.setOutcome(true, FailureMode::no_failure);
    QVERIFY(!panel.speedDial()->limit());
    QVERIFY(panel.statusText().contains(QStringLiteral("revealed when the replay ends")));
    QCOMPARE(revealed.count(), 0);

    // Hidden: no arc colours at the arcs' positions.
    EnvelopeDial* dial = panel.speedDial();
    QImage before = dial->grab().toImage();
    const QColor safe = EnvelopeDial::zoneColor(DialZone::safe);
    const QColor failing = EnvelopeDial::zoneColor(DialZone::failing);
    QVERIFY(distance(pixelAt(before, dial->arcPoint(0.5)), safe) > 40);

    panel.replayFinished();
    QCOMPARE(revealed.count(), 1);
    const auto score = revealed.first().at(0).value<DialScore>();
    QCOMPARE(score.points, 90);  // 1.35 / 1.5 and 2.7 / 3.0
    QCOMPARE(score.verdict, DialScore::Verdict::dialed_in);
    QVERIFY(panel.statusText().contains(QStringLiteral("Dialed in")));
    QCOMPARE(*panel.speedDial()->limit(), 1.5);
    QCOMPARE(*panel.accelDial()->limit(), 3.0);

    const QImage after = dial->grab().toImage();

    // Speed dial (0.1-2 m/s, limit 1.5): 0.5 is safe, 1.4 marginal (>= 1.275), 1.8 failing.
    QVERIFY(distance(pixelAt(after, dial->arcPoint(0.5)), safe) < 40);
    QVERIFY(distance(pixelAt(after, dial->arcPoint(1.4)),
                     EnvelopeDial::zoneColor(DialZone::marginal)) < 40);
    QVERIFY(distance(pixelAt(after, dial->arcPoint(1.8)), failing) < 40);
    const QImage accel = panel.accelDial()->grab().toImage();
    QVERIFY(distance(pixelAt(accel, panel.accelDial()->arcPoint(3.5)), failing) < 40);

    QVERIFY(QDir().mkpath(QStringLiteral(PB_TEST_ARTIFACTS_DIR)));
    QVERIFY(panel.grab().save(QStringLiteral(PB_TEST_ARTIFACTS_DIR "/panel_dials.png")));

    panel.resetRound();
    QVERIFY(!panel.speedDial()->limit());
  }

  // One range: the dials span the search's (the limits speak about every point they can dial),
  // and every curated scenario's suggested profile can be dialled exactly.
  void theDialsSpanTheAnalysedRange() {
    const pb::SearchConfig range;
    DialPanel panel(range);
    QCOMPARE(panel.speedDial()->minPhysical(), range.speed_min_mps);
    QCOMPARE(panel.speedDial()->maxPhysical(), range.speed_max_mps);
    QCOMPARE(panel.accelDial()->maxPhysical(), range.accel_max_mps2);
    QCOMPARE(panel.speedSpin()->maximum(), range.speed_max_mps);
    QCOMPARE(panel.accelSpin()->minimum(), range.accel_min_mps2);
    panel.setAccel(0.0);
    QCOMPARE(panel.accel(), range.accel_min_mps2);
    for (const pb::Scenario& s : pb::all_scenarios()) {
      panel.setSpeed(s.suggested_profile.target_speed_mps);
      panel.setAccel(s.suggested_profile.accel_mps2);
      QVERIFY2(panel.speed() == s.suggested_profile.target_speed_mps &&
                   panel.accel() == s.suggested_profile.accel_mps2,
               s.slug.c_str());
    }
    // Another range re-ranges the dials (e.g. a line that runs to 3 m/s).
    pb::SearchConfig faster;
    faster.speed_max_mps = 3.0;
    DialPanel wide(faster);
    wide.setSpeed(99.0);
    QCOMPARE(wide.speed(), 3.0);
    QCOMPARE(wide.speedDial()->value(), 300);
  }

  void crashedRoundSaysSo() {
    DialPanel panel;
    panel.dispatch();
    panel.setOutcome(false, FailureMode::tip_over);
    panel.replayFinished();
    QVERIFY(!panel.game().revealed());  // the envelope has not arrived
    panel.setEnvelope(envelope());
    QVERIFY(panel.game().revealed());
    QVERIFY(panel.statusText().contains(QStringLiteral("The dispatch failed")));
  }
};

QTEST_MAIN(TestDialPanel)
#include "tst_dial_panel.moc"
