// SPDX-License-Identifier: MIT
// Grades and the one-sentence "why it failed": the numbers in the sentence are the mechanics
// (a/g against the pair's effective friction; the tipping ratio from the centre of mass).
#include "core/analysis/explain.hpp"

#include <QtTest>

#include <cmath>

#include "core/base/text.hpp"
#include "core/contract/pallet_metrics.hpp"
#include "tests/core/test_pallets.hpp"

using namespace pb;

namespace {

QString q(const std::string& s) {
  return QString::fromStdString(s);
}

/// Two cartons, one on the deck and one on top of it, frozen.
PalletConfig two_high(double temp_c = -22.0, WrapType wrap = WrapType::none) {
  PalletConfig c = test::pallet({test::carton(0.0, 0.0, 0.15), test::carton(0.0, 0.0, 0.35)}, wrap);
  c.env = Environment::frozen;
  c.body_temp_c = temp_c;
  return c;
}

ConveyorProfile startup(double accel) {
  ConveyorProfile p;
  p.shape = ProfileShape::accel_hold;
  p.accel_mps2 = accel;
  p.target_speed_mps = 1.0;
  return p;
}

FailureEvent failure(FailureMode mode, std::vector<int> items, double value = 0.051) {
  FailureEvent e;
  e.mode = mode;
  e.time_s = 0.412;
  e.value = value;
  e.items = std::move(items);
  return e;
}

}  // namespace

class ExplainTest : public QObject {
  Q_OBJECT

 private slots:
  void gradeFollowsTheTable() {
    SafetyResult r;
    r.max_speed_mps = 2.0;
    r.max_accel_mps2 = 5.0;
    QCOMPARE(grade(r).letter, 'A');
    r.max_accel_mps2 = 1.4;  // 1.4x the table's start-up: not yet 1.5x
    QCOMPARE(grade(r).letter, 'B');
    r.max_speed_mps = 1.0;
    r.max_accel_mps2 = 1.0;
    QCOMPARE(grade(r).letter, 'B');
    r.max_speed_mps = 0.8;
    QCOMPARE(grade(r).letter, 'C');
    QVERIFY(q(grade(r).advice).contains(QStringLiteral("0.80 m/s")));
    r.verdict = Verdict::reject;
    QCOMPARE(grade(r).letter, 'R');
    QCOMPARE(q(grade(r).label), QStringLiteral("Reject and re-wrap"));
  }

  void temperatureUsesATrueMinus() {
    QCOMPARE(q(format_temperature(-22.4)), QStringLiteral("\u221222 \u00b0C"));
    QCOMPARE(q(format_temperature(4.0)), QStringLiteral("4 \u00b0C"));
    QCOMPARE(q(format_temperature(-0.2)), QStringLiteral("0 \u00b0C"));
  }

  void peakDemandPerShape() {
    ConveyorProfile p = startup(2.5);
    QCOMPARE(peak_demand_mps2(p), 2.5);
    p.shape = ProfileShape::estop;
    p.decel_mps2 = 4.0;
    QCOMPARE(peak_demand_mps2(p), 4.0);
    p.shape = ProfileShape::curve;
    p.target_speed_mps = 1.5;
    p.curve_radius_m = 3.0;
    QCOMPARE(peak_demand_mps2(p), 1.5 * 1.5 / 3.0);
    p.shape = ProfileShape::constant;
    QCOMPARE(peak_demand_mps2(p), 0.0);
  }

  void topItemSlideNamesNeededAndAvailableFriction() {
    const PalletConfig c = two_high();
    const auto cf = FrictionModel::builtin().for_pallet(c);
    QVERIFY(cf.ok());
    const std::string s =
        explain_failure(c, startup(4.0), failure(FailureMode::top_item_slide, {1}));
    // 4.0 / 9.81 = 0.408: the start-up needs mu 0.41; the carton on a carton has its table value.
    QVERIFY2(q(s).startsWith(QStringLiteral("Top item 2 slid 5.1 cm")), s.c_str());
    QVERIFY2(q(s).contains(QStringLiteral("needs \u03bc 0.41")), s.c_str());
    QVERIFY2(q(s).contains(q(cf->item_item_key + " has " + fixed(cf->item_item.mu_s, 2))),
             s.c_str());
    QVERIFY2(q(s).contains(QStringLiteral("\u221222 \u00b0C")), s.c_str());
    QVERIFY(cf->item_item.mu_s < 0.41);  // the sentence is a real explanation, not a tautology
    QVERIFY2(!q(s).contains(QStringLiteral("friction alone would hold")), s.c_str());
  }

  void aSlideBelowTheFrictionLimitSaysFrictionWasNotTheCause() {
    const PalletConfig c = two_high();
    const std::string s =
        explain_failure(c, startup(0.5), failure(FailureMode::top_item_slide, {1}));
    QVERIFY2(q(s).contains(QStringLiteral("friction alone would hold")), s.c_str());
  }

  // In a curve an item off the centre line rides at its own radius (turning_frame.hpp): two cartons
  // 0.3 m outboard on a 1 m left curve at 0.30 g feel 1.3 times it, 0.39 g, which is what their
  // friction is measured against; on the centre line the sentence is the centre line's.
  void aCurveNamesTheDemandWhereTheItemRides() {
    PalletConfig c = two_high();
    for (Item& item : c.items) item.position[1] = -0.3;
    ConveyorProfile p;
    p.shape = ProfileShape::curve;
    p.curve_radius_m = 1.0;
    p.target_speed_mps = std::sqrt(0.30 * 9.81 * 1.0);
    const std::string s = explain_failure(c, p, failure(FailureMode::top_item_slide, {1}));
    QVERIFY2(q(s).contains(QStringLiteral(
                 "the curve's 0.30 g (0.39 g where it rides: the curve turns the load) needs "
                 "μ 0.39")),
             s.c_str());
    const std::string centred =
        explain_failure(two_high(), p, failure(FailureMode::top_item_slide, {1}));
    QVERIFY2(q(centred).contains(QStringLiteral("the curve's 0.30 g needs μ 0.30")),
             centred.c_str());
  }

  // A carton that moved its 5 cm by turning over an edge (detectors.hpp: item_tipped) is said to
  // have tipped, with its own tipping onset (b/2)/h; the same carton that slid flat, to have slid.
  void anItemThatTippedIsSaidToTip() {
    PalletConfig c = test::pallet({test::carton(0.0, 0.0, 0.15, {0.2, 0.2, 1.0}, 20.0)});
    FailureEvent tipped = failure(FailureMode::top_item_slide, {0}, 0.0502);
    tipped.item_tilt_deg = 5.6;
    const std::string s = explain_failure(c, startup(2.5), tipped);
    QVERIFY2(q(s).startsWith(QStringLiteral("Top item 1 tipped over (0.41 s), turning 5.6 deg")),
             s.c_str());
    QVERIFY2(q(s).contains(QStringLiteral("0.25 g is more than the 0.20 g its footprint holds")),
             s.c_str());
    QVERIFY2(q(s).endsWith(QStringLiteral("restack it lower or wider.")), s.c_str());
    FailureEvent slid = tipped;
    slid.item_tilt_deg = 0.4;
    const std::string f = explain_failure(c, startup(2.5), slid);
    QVERIFY2(q(f).startsWith(QStringLiteral("Top item 1 slid 5.0 cm")), f.c_str());
  }

  // Every carton moved with it (load_slid_as_one): the load left a pallet that held, so the deck
  // pair is to blame, and what holds a load to its pallet is the remedy, not a restack.
  void aLoadThatSlidAsOneBlamesTheDeckPair() {
    const PalletConfig c = two_high();
    const auto cf = FrictionModel::builtin().for_pallet(c);
    FailureEvent e = failure(FailureMode::top_item_slide, {1}, 0.056);
    e.least_item_move_m = 0.055;
    const std::string s = explain_failure(c, startup(4.0), e);
    QVERIFY2(q(s).startsWith(QStringLiteral("The whole load slid 5.6 cm on its pallet (0.41 s): "
                                            "the start-up's 0.41 g needs μ 0.41, ")),
             s.c_str());
    QVERIFY2(q(s).contains(q(cf->item_pallet_key + " has " + fixed(cf->item_pallet.mu_s, 2))),
             s.c_str());
    QCOMPARE(q(s).contains(QStringLiteral("so the load goes first")),
             cf->item_pallet.mu_s < cf->belt_pallet.mu_s);
    QVERIFY2(q(s).endsWith(
                 QStringLiteral("wrap the load to its pallet or lay an anti-slip sheet under it.")),
             s.c_str());
    // The top carton alone moved that far: its own pair is named, as before.
    e.least_item_move_m = 0.01;
    QVERIFY(q(explain_failure(c, startup(4.0), e)).startsWith(QStringLiteral("Top item 2 slid")));
  }

  void bottomItemUsesTheDeckPair() {
    const PalletConfig c = two_high();
    const auto cf = FrictionModel::builtin().for_pallet(c);
    const std::string s =
        explain_failure(c, startup(4.0), failure(FailureMode::top_item_slide, {0}));
    QVERIFY2(q(s).startsWith(QStringLiteral("Item 1 slid")), s.c_str());
    QVERIFY2(q(s).contains(q(cf->item_pallet_key + " has " + fixed(cf->item_pallet.mu_s, 2))),
             s.c_str());
  }

  void wrappedLoadBlamesTheWrap() {
    const PalletConfig c = two_high(-22.0, WrapType::stretch);
    const std::string s =
        explain_failure(c, startup(4.0), failure(FailureMode::top_item_slide, {1}));
    QVERIFY2(q(s).contains(QStringLiteral("stretch wrap holds")), s.c_str());
  }

  void tipOverQuotesTheTippingRatio() {
    // A tall narrow column: the loaded pallet's tipping ratio (L/2 - |x|) / h_com is what tips.
    PalletConfig c = test::pallet({test::carton(0.0, 0.0, 0.15, {0.4, 0.3, 1.6}, 200.0)});
    const Vec3 com = composite_com_m(c);
    const double ratio = (c.base_dims_m[0] / 2.0 - std::abs(com[0])) / com[2];
    const std::string s = explain_failure(c, startup(6.0), failure(FailureMode::tip_over, {}, 8.2));
    QVERIFY2(q(s).startsWith(QStringLiteral("The load tipped over")), s.c_str());
    QVERIFY2(q(s).contains(QStringLiteral("0.61 g")), s.c_str());  // 6.0 / 9.81
    QVERIFY2(q(s).contains(q(fixed(ratio, 2) + " g")), s.c_str());
  }

  void palletSlipUsesTheBeltPair() {
    const PalletConfig c = two_high();
    const auto cf = FrictionModel::builtin().for_pallet(c);
    ConveyorProfile stop = startup(1.0);
    stop.shape = ProfileShape::estop;
    stop.decel_mps2 = 5.0;
    const std::string s = explain_failure(c, stop, failure(FailureMode::pallet_slip, {}, 0.31));
    QVERIFY2(q(s).contains(QStringLiteral("the stop's 0.51 g needs \u03bc 0.51")), s.c_str());
    QVERIFY2(q(s).contains(q(cf->belt_pallet_key + " has " + fixed(cf->belt_pallet.mu_s, 2))),
             s.c_str());
  }

  void frostMeltPenaltyIsNamed() {
    PalletConfig c = two_high(2.0);
    c.env = Environment::transitioning;
    c.seconds_since_temp_change = 60.0;
    const auto cf = FrictionModel::builtin().for_pallet(c);
    QVERIFY(cf->belt_pallet.penalty < 1.0);
    const std::string s = explain_failure(c, startup(4.0), failure(FailureMode::pallet_slip, {}));
    QVERIFY2(q(s).contains(QStringLiteral("frost-melt film")), s.c_str());
  }

  void loadShiftNamesThePair() {
    const std::string s =
        explain_failure(two_high(), startup(3.0), failure(FailureMode::load_shift, {0, 1}, 0.021));
    QVERIFY2(q(s).contains(QStringLiteral("items 1 and 2 moved 2.1 cm apart")), s.c_str());
    QVERIFY2(q(s).contains(QStringLiteral("interlocked")), s.c_str());
  }

  void unknownPairFallsBackToTheDetectorsWords() {
    PalletConfig c = two_high();
    c.base_pallet_type = PalletType::chep;
    c.belt_surface = BeltSurface::steel_roller;
    if (FrictionModel::builtin().for_pallet(c).ok()) QSKIP("the table now has plastic on steel");
    const FailureEvent e = failure(FailureMode::pallet_slip, {}, 0.31);
    QCOMPARE(q(explain_failure(c, startup(4.0), e)), q(describe(e)));
  }
};

QTEST_APPLESS_MAIN(ExplainTest)
#include "explain_test.moc"
