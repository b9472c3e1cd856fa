// SPDX-License-Identifier: MIT
// The dial game's rules, headless: zones against the limit, the score (fraction of the solver's
// limit dared; "dialed in" from 85 %), and the envelope hidden until the replay has ended.
#include <QtTest>

#include "ui/models/dial_game.hpp"

using namespace pb;
using namespace pb::ui;

namespace {

SafetyResult envelope(double speed, double accel) {
  SafetyResult r;
  r.max_speed_mps = speed;
  r.max_accel_mps2 = accel;
  r.dominant_failure_mode = FailureMode::top_item_slide;
  return r;
}

ConveyorProfile dialled(double speed, double accel) {
  ConveyorProfile p;
  p.target_speed_mps = speed;
  p.accel_mps2 = accel;
  return p;
}

}  // namespace

class TestDialGame : public QObject {
  Q_OBJECT

 private slots:
  void zones() {
    QCOMPARE(dial_zone(0.5, 2.0), DialZone::safe);
    QCOMPARE(dial_zone(1.69, 2.0), DialZone::safe);
    QCOMPARE(dial_zone(1.70, 2.0), DialZone::marginal);  // 85 % exactly
    QCOMPARE(dial_zone(2.0, 2.0), DialZone::marginal);   // the limit itself was found safe
    QCOMPARE(dial_zone(2.01, 2.0), DialZone::failing);
    QCOMPARE(dial_zone(0.1, 0.0), DialZone::failing);  // a reject: nothing is safe
  }

  void scoreIsTheSmallerFractionDared() {
    const DialScore s =
        score_dispatch(dialled(1.0, 3.0), true, FailureMode::no_failure, envelope(2.0, 4.0));
    QCOMPARE(s.speed_fraction, 0.5);
    QCOMPARE(s.accel_fraction, 0.75);
    QCOMPARE(s.fraction, 0.5);
    QCOMPARE(s.points, 50);
    QCOMPARE(s.grade, 'C');
    QCOMPARE(s.verdict, DialScore::Verdict::cautious);
  }

  void dialedInFrom85Percent_data() {
    QTest::addColumn<double>("speed");
    QTest::addColumn<int>("verdict");
    QTest::addColumn<int>("points");
    QTest::addColumn<char>("grade");
    // Limits 2.0 m/s and 4.0 m/s^2; the acceleration is dialled at 100 %.
    QTest::newRow("84 %") << 1.68 << int(DialScore::Verdict::cautious) << 84 << 'B';
    QTest::newRow("85 %") << 1.70 << int(DialScore::Verdict::dialed_in) << 85 << 'A';
    QTest::newRow("94 %") << 1.88 << int(DialScore::Verdict::dialed_in) << 94 << 'A';
    QTest::newRow("95 %") << 1.90 << int(DialScore::Verdict::dialed_in) << 95 << 'S';
    QTest::newRow("100 %") << 2.00 << int(DialScore::Verdict::dialed_in) << 100 << 'S';
    // Beyond the speed limit but at the start-up limit: 100 % dared, no more.
    QTest::newRow("110 % speed") << 2.20 << int(DialScore::Verdict::dialed_in) << 100 << 'S';
    QTest::newRow("59 %") << 1.18 << int(DialScore::Verdict::cautious) << 59 << 'C';
    QTest::newRow("60 %") << 1.20 << int(DialScore::Verdict::cautious) << 60 << 'B';
  }
  void dialedInFrom85Percent() {
    QFETCH(double, speed);
    QFETCH(int, verdict);
    QFETCH(int, points);
    QFETCH(char, grade);
    const DialScore s =
        score_dispatch(dialled(speed, 4.0), true, FailureMode::no_failure, envelope(2.0, 4.0));
    QCOMPARE(int(s.verdict), verdict);
    QCOMPARE(s.points, points);
    QCOMPARE(s.grade, grade);
    QVERIFY(s.fraction >= 0.0 && s.fraction <= 1.0);
  }

  void survivingBeyondBothLimitsIsLuck() {
    const DialScore s =
        score_dispatch(dialled(2.2, 4.4), true, FailureMode::no_failure, envelope(2.0, 4.0));
    QCOMPARE(s.verdict, DialScore::Verdict::beyond_limit);
    QCOMPARE(s.fraction, 1.0);
    QCOMPARE(s.points, 100);
  }

  void crashScoresNothing() {
    const DialScore s =
        score_dispatch(dialled(1.9, 3.9), false, FailureMode::tip_over, envelope(2.0, 4.0));
    QCOMPARE(s.verdict, DialScore::Verdict::crashed);
    QCOMPARE(s.points, 0);
    QCOMPARE(s.grade, 'F');
    QCOMPARE(s.failure_mode, FailureMode::tip_over);
    // Plain words for the operator: what failed, no identifier and no joke.
    QCOMPARE(s.headline, std::string("The dispatch failed: the load tips over"));
  }

  // A top_item_slide says how it went: the whole load sliding on its pallet is not an item
  // sliding off, and the round remembers it until the reveal.
  void crashSaysHowTheSlideWent() {
    const DialScore s = score_dispatch(dialled(1.9, 3.9), false, FailureMode::top_item_slide,
                                       envelope(2.0, 4.0), SlideKind::load_as_one);
    QCOMPARE(s.failure_slide, SlideKind::load_as_one);
    QCOMPARE(s.headline, std::string("The dispatch failed: the load slides on its pallet"));
    DialGame game;
    game.dispatch(dialled(1.0, 1.0));
    game.setOutcome(false, FailureMode::top_item_slide, SlideKind::item_tipped);
    game.replayFinished();
    game.setEnvelope(envelope(0.8, 0.9));
    QVERIFY(game.revealed());
    QCOMPARE(game.score()->headline, std::string("The dispatch failed: an item tips over"));
  }

  void rejectScoresNothingEvenWhenItSurvived() {
    SafetyResult r = envelope(0.0, 0.0);
    r.verdict = Verdict::reject;
    r.dominant_failure_mode = FailureMode::load_shift;
    const DialScore s = score_dispatch(dialled(0.3, 0.3), true, FailureMode::no_failure, r);
    QCOMPARE(s.verdict, DialScore::Verdict::reject);
    QCOMPARE(s.points, 0);
    QCOMPARE(s.failure_mode, FailureMode::load_shift);
  }

  void envelopeHiddenUntilReplayEnds() {
    DialGame game;
    QVERIFY(!game.dispatched());
    game.setEnvelope(envelope(2.0, 4.0));  // before a dispatch: ignored
    game.dispatch(dialled(1.8, 3.6));
    QVERIFY(game.dispatched());
    game.setEnvelope(envelope(2.0, 4.0));
    QVERIFY(!game.revealed());
    QVERIFY(!game.envelope());
    QVERIFY(!game.score());
    game.replayFinished();  // no outcome yet: a replay cannot have ended
    QVERIFY(!game.revealed());
    game.setOutcome(true);
    QVERIFY(!game.revealed());  // the replay is still playing
    game.replayFinished();
    QVERIFY(game.revealed());
    QCOMPARE(game.envelope()->max_speed_mps, 2.0);
    QCOMPARE(game.score()->points, 90);
    QCOMPARE(game.score()->verdict, DialScore::Verdict::dialed_in);
  }

  void envelopeArrivingLastStillReveals() {
    DialGame game;
    game.dispatch(dialled(1.0, 1.0));
    game.setOutcome(false, FailureMode::pallet_slip);
    game.replayFinished();
    QVERIFY(!game.revealed());
    game.setEnvelope(envelope(0.8, 0.9));
    QVERIFY(game.revealed());
    QCOMPARE(game.score()->verdict, DialScore::Verdict::crashed);
  }

  void aNewDispatchHidesTheOldRound() {
    DialGame game;
    game.dispatch(dialled(1.0, 1.0));
    game.setEnvelope(envelope(2.0, 4.0));
    game.setOutcome(true);
    game.replayFinished();
    QVERIFY(game.revealed());
    game.dispatch(dialled(1.5, 1.0));
    QVERIFY(!game.revealed());
    QVERIFY(!game.envelope());
  }
};

QTEST_APPLESS_MAIN(TestDialGame)
#include "tst_dial_game.moc"
