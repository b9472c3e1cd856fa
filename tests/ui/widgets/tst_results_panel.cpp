// SPDX-License-Identifier: MIT
// The results panel: the grade and limits in words, "Reject and re-wrap" when nothing is safe, the
// reason sentence, the last dispatch explained, the dialled point passed to the heatmap.
#include <QDir>
#include <QtTest>

#include "core/analysis/explain.hpp"
#include "core/inputs/scenario.hpp"
#include "ui/widgets/failure_map_view.hpp"
#include "ui/widgets/results_panel.hpp"

using namespace pb;
using namespace pb::ui;

namespace {

SafetyResult okResult() {
  SafetyResult r;
  r.max_speed_mps = 1.85;
  r.max_accel_mps2 = 3.4;
  r.max_decel_mps2 = 2.9;
  r.max_lateral_g = 0.21;
  r.dominant_failure_mode = FailureMode::top_item_slide;
  r.speed_governed_by = SpeedGovernor::estop;
  r.margin_pct = 42.0;
  r.sims_run = 17;
  r.reason = "Start-up to 3.4 m/s^2 (then top_item_slide).";
  return r;
}

}  // namespace

class TestResultsPanel : public QObject {
  Q_OBJECT

 private slots:
  void gradeAndLimitsInWords() {
    ResultsPanel panel;
    QVERIFY(panel.gradeText().contains(QStringLiteral("No analysis yet")));
    panel.setResult(okResult());
    QVERIFY(panel.gradeText().contains(QStringLiteral("Faster than the table")));
    QVERIFY(panel.gradeText().contains(QStringLiteral(">A<")));
    QVERIFY(panel.limitsText().contains(QStringLiteral("1.85 m/s")));
    QVERIFY(panel.limitsText().contains(QStringLiteral("3.40 m/s²")));
    QVERIFY(panel.limitsText().contains(QStringLiteral("set by the line's e-stop")));
    QVERIFY(panel.limitsText().contains(QStringLiteral("an item slides off")));
    QVERIFY(panel.limitsText().contains(QStringLiteral("17 simulations")));
    QCOMPARE(panel.reasonText(), QStringLiteral("Start-up to 3.4 m/s^2 (then top_item_slide)."));
  }

  // A load that cannot stand: a build defect, no limit and no speed anywhere on the panel.
  // The provisional estimate is replaced limit by limit as each search ends: the simulated ones in
  // bold, the others marked as the estimate; the speed waits for the analysis, which ends it.
  // A limit is never shown above itself, and the load sliding as one is said so.
  void limitsAreFlooredAndSayHowTheSlideWent() {
    ResultsPanel panel;
    SafetyResult r = okResult();
    r.max_accel_mps2 = 1.168;
    r.max_lateral_g = 0.2265;
    r.dominant_slide = SlideKind::load_as_one;
    panel.setResult(r);
    QVERIFY2(panel.limitsText().contains(QStringLiteral("start-up up to <b>1.16 m/s²</b>")),
             qPrintable(panel.limitsText()));
    QVERIFY(panel.limitsText().contains(QStringLiteral("curves up to <b>0.226 g</b>")));
    QVERIFY(panel.limitsText().contains(QStringLiteral("the load slides on its pallet")));
  }

  void provisionalLimitsAreReplacedOneByOne() {
    ResultsPanel panel;
    SafetyResult estimate = okResult();
    estimate.max_accel_mps2 = 3.2;
    estimate.max_lateral_g = 0.33;
    panel.setProvisional(estimate);
    QVERIFY(panel.isProvisional());
    QVERIFY2(panel.limitsText().contains(QStringLiteral("0 of 3 limits simulated")),
             qPrintable(panel.limitsText()));
    QVERIFY(panel.limitsText().contains(QStringLiteral("<i>\u22483.2 m/s\u00b2</i>")));
    AxisLimit curve;
    curve.limit = 0.25;
    curve.mode = FailureMode::top_item_slide;
    panel.setAxisFound(Axis::lateral, curve);
    QVERIFY(panel.isProvisional());
    QVERIFY2(panel.limitsText().contains(QStringLiteral("1 of 3 limits simulated")),
             qPrintable(panel.limitsText()));
    QVERIFY(panel.limitsText().contains(QStringLiteral("curves up to <b>0.25 g</b>")));
    QVERIFY(panel.limitsText().contains(QStringLiteral("<i>\u22483.2 m/s\u00b2</i>")));
    AxisLimit speed;
    speed.limit = 0.5;
    panel.setAxisFound(Axis::speed, speed);  // waits for the analysis
    QVERIFY(panel.limitsText().contains(QStringLiteral("1 of 3 limits simulated")));
    panel.setResult(okResult());  // the analysis
    QVERIFY(!panel.isProvisional());
    QVERIFY(!panel.limitsText().contains(QStringLiteral("Provisional")));
    panel.setAxisFound(Axis::accel, curve);  // late: ignored once the analysis is shown
    QVERIFY(!panel.limitsText().contains(QStringLiteral("Provisional")));
  }

  void buildDefectShowsNoLimits() {
    ResultsPanel panel;
    SafetyResult r;
    r.verdict = Verdict::reject;
    r.speed_governed_by = SpeedGovernor::build_defect;
    r.dominant_failure_mode = r.accel_mode = r.decel_mode = r.lateral_mode = r.speed_mode =
        FailureMode::cannot_stand;
    r.reason =
        "Reject, build defect: Item 7 (SKU-FD-003) cannot stand: with the belt standing "
        "still, item 7 moved 5.1 cm on the pallet within 0.40 s of being stacked.";
    panel.setResult(r);
    QVERIFY2(panel.gradeText().contains(QStringLiteral("Build defect: re-stack")),
             qPrintable(panel.gradeText()));
    QVERIFY(panel.limitsText().contains(QStringLiteral("Build defect")));
    QVERIFY(panel.limitsText().contains(QStringLiteral("no conveyor limit")));
    for (const QString& text : {panel.gradeText(), panel.limitsText()}) {
      QVERIFY2(!text.contains(QStringLiteral("m/s")), qPrintable(text));
    }
    QVERIFY(panel.reasonText().contains(QStringLiteral("Item 7 (SKU-FD-003) cannot stand")));
  }

  void rejectSaysRejectAndRewrap() {
    ResultsPanel panel;
    SafetyResult r = okResult();
    r.verdict = Verdict::reject;
    r.max_speed_mps = 0.0;
    r.dominant_failure_mode = FailureMode::load_shift;
    panel.setResult(r);
    QVERIFY(panel.gradeText().contains(QStringLiteral("Reject and re-wrap")));
    QVERIFY(panel.limitsText().contains(QStringLiteral("the load shifts inside")));
    QVERIFY(!panel.limitsText().contains(QStringLiteral("m/s")));
  }

  void dispatchIsExplained() {
    const auto s = load_scenario("tall-unwrapped-tower");
    QVERIFY(s.ok());
    Replay replay;
    replay.pallet = s->pallet;
    replay.profile = s->suggested_profile;
    replay.outcome = "failed";
    FailureEvent e;
    e.mode = FailureMode::pallet_slip;
    e.time_s = 0.5;
    e.value = 0.31;
    replay.failure = e;
    ResultsPanel panel;
    panel.setReplay(replay);
    const QString want = QString::fromStdString(explain_failure(replay.pallet, replay.profile, e));
    QVERIFY(panel.dispatchText().endsWith(want));
    QVERIFY(want.contains(QStringLiteral("needs \u03bc")));
    replay.outcome = "safe";
    replay.failure.reset();
    panel.setReplay(replay);
    QVERIFY(panel.dispatchText().contains(QStringLiteral("survived")));
  }

  void errorReplacesTheGrade() {
    ResultsPanel panel;
    panel.setResult(okResult());
    panel.showError(QStringLiteral("/items/3/dims_m/2: must be positive"));
    QVERIFY(panel.gradeText().contains(QStringLiteral("Could not analyse")));
    QVERIFY(panel.reasonText().contains(QStringLiteral("/items/3")));
    QVERIFY(panel.limitsText().isEmpty());
  }

  void heatmapGetsTheDialledPointAndScreenshot() {
    ResultsPanel panel;
    panel.resize(520, 640);
    panel.setResult(okResult());
    FailureMapView::Grid g;
    g.speeds_mps = {0.5, 1.0, 1.5, 2.0};
    g.accels_mps2 = {1.0, 2.0, 3.0, 4.0};
    for (double a : g.accels_mps2) {
      for (double v : g.speeds_mps) {
        const bool fails = a > 3.4 || (a > 2.5 && v > 1.85);
        g.cells.push_back({fails ? Outcome::failed : Outcome::safe,
                           fails ? FailureMode::top_item_slide : FailureMode::no_failure, false});
      }
    }
    panel.mapView()->setGrid(g);
    panel.setDialledPoint(1.5, 3.0);
    QCOMPARE(*panel.mapView()->dialledPoint(), QPointF(1.5, 3.0));
    QVERIFY(QDir().mkpath(QStringLiteral(PB_TEST_ARTIFACTS_DIR)));
    QVERIFY(panel.grab().save(QStringLiteral(PB_TEST_ARTIFACTS_DIR "/panel_results.png")));
    panel.clear();
    QVERIFY(!panel.mapView()->hasGrid());
  }
};

QTEST_MAIN(TestResultsPanel)
#include "tst_results_panel.moc"
