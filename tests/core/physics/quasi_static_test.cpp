// SPDX-License-Identifier: MIT
#include "core/physics/quasi_static.hpp"

#include <QtTest>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>

#include "core/physics/step.hpp"
#include "tests/core/test_pallets.hpp"

using namespace pb;

namespace {

constexpr double g = kGravity;
constexpr double kMuBelt = 0.7, kMuDeck = 0.45, kMuItems = 0.35;

ContactFriction friction() {
  ContactFriction f;
  f.belt_pallet.mu_s = kMuBelt;
  f.item_pallet.mu_s = kMuDeck;
  f.item_item.mu_s = kMuItems;
  // Dynamic values differ so that using them instead would show.
  f.belt_pallet.mu_d = 0.5;
  f.item_pallet.mu_d = 0.3;
  f.item_item.mu_d = 0.2;
  return f;
}

using test::carton;
using test::pallet;

bool near(double a, double b) {
  return std::abs(a - b) <= 1e-12 * std::max(1.0, std::abs(b));
}

QByteArray text(const QuasiStaticLimit& l) {
  return QByteArray::fromStdString(l.what + " at " + std::to_string(l.accel_mps2));
}

// The one limit of `item` whose description contains `verb` ("slips", "tips"); fails otherwise.
QuasiStaticLimit find(const std::vector<QuasiStaticLimit>& limits, int item,
                      std::string_view verb) {
  const QuasiStaticLimit* found = nullptr;
  int matches = 0;
  for (const auto& l : limits) {
    if (l.item == item && l.what.find(verb) != std::string::npos) {
      found = &l;
      ++matches;
    }
  }
  if (matches != 1) {
    qWarning("%d limits of item %d %s", matches, item, std::string(verb).c_str());
    return {-1.0, FailureMode::no_failure, Mechanism::pallet_slip, "not found", -2};
  }
  return *found;
}

// g (b/2) / h for the whole load over the pallet's edge, from the composite COM worked out by
// hand: base 25 kg at half its height, centred.
double load_tip(const std::vector<std::array<double, 3>>& masses_x_z, double half_base) {
  double m = 25.0, mx = 0.0, mz = 25.0 * 0.075;
  for (const auto& [kg, x, z] : masses_x_z) {
    m += kg;
    mx += kg * x;
    mz += kg * z;
  }
  return g * (half_base - std::abs(mx / m)) / (mz / m);
}

}  // namespace

class QuasiStaticTest : public QObject {
  Q_OBJECT

 private slots:
  void palletSlipIsMuBeltG() {
    const auto b = quasi_static_bounds(pallet({carton(0.0, 0.0, 0.15)}), friction());
    for (const auto* list : {&b.along, &b.across}) {
      const QuasiStaticLimit& slip = list->at(0);
      QCOMPARE(slip.mode, FailureMode::pallet_slip);
      QCOMPARE(slip.item, -1);
      QVERIFY(near(slip.accel_mps2, kMuBelt * g));
      QCOMPARE(slip.what, std::string("the pallet slips on the belt (mu 0.70)"));
    }
  }

  // dims 0.4 (own x) x 0.3 x 0.5 m: the COM is 0.25 m above the deck.
  void singleCartonSlipsAndTips_data() {
    QTest::addColumn<double>("yaw");
    QTest::addColumn<double>("x");
    QTest::addColumn<double>("half_along");
    QTest::addColumn<double>("half_across");
    QTest::newRow("yaw 0") << 0.0 << 0.0 << 0.2 << 0.15;
    QTest::newRow("yaw 0, off centre") << 0.0 << 0.3 << 0.2 << 0.15;
    QTest::newRow("yaw 90") << 90.0 << 0.0 << 0.15 << 0.2;
    QTest::newRow("yaw -90") << -90.0 << 0.0 << 0.15 << 0.2;
    QTest::newRow("yaw 180") << 180.0 << 0.0 << 0.2 << 0.15;
    // A yawed footprint tips about the edge its centre's line of action crosses first, nearer
    // than its bounding box (0.248 m along X at 30 deg): 0.2 / cos 30 along, 0.15 / cos 30 across.
    QTest::newRow("yaw 30") << 30.0 << 0.0 << 0.2 / std::cos(std::numbers::pi / 6.0)
                            << 0.15 / std::cos(std::numbers::pi / 6.0);
    QTest::newRow("yaw 60") << 60.0 << 0.0 << 0.15 / std::cos(std::numbers::pi / 6.0)
                            << 0.2 / std::cos(std::numbers::pi / 6.0);
  }
  void singleCartonSlipsAndTips() {
    QFETCH(double, yaw);
    QFETCH(double, x);
    QFETCH(double, half_along);
    QFETCH(double, half_across);
    const auto b =
        quasi_static_bounds(pallet({carton(x, 0.0, 0.15, {0.4, 0.3, 0.5}, 10.0, yaw)}), friction());
    QCOMPARE(b.along.size(), std::size_t{4});  // pallet slip, load tip, item slip, item tip
    QCOMPARE(b.across.size(), std::size_t{4});
    for (const auto* list : {&b.along, &b.across}) {
      const QuasiStaticLimit slip = find(*list, 0, "slips");
      QCOMPARE(slip.mode, FailureMode::top_item_slide);
      QVERIFY2(near(slip.accel_mps2, kMuDeck * g), text(slip));
      QCOMPARE(slip.what, std::string("item 0 slips on the deck (mu 0.45)"));
    }
    const QuasiStaticLimit along = find(b.along, 0, "tips");
    const QuasiStaticLimit across = find(b.across, 0, "tips");
    QCOMPARE(along.what, std::string("the stack from item 0 up tips over its edge"));
    QCOMPARE(along.mode, FailureMode::top_item_slide);
    QVERIFY2(near(along.accel_mps2, g * half_along / 0.25), text(along));
    QVERIFY2(near(across.accel_mps2, g * half_across / 0.25), text(across));
    // The whole load over the pallet's edge.
    const QuasiStaticLimit load_along = find(b.along, -1, "tips");
    QCOMPARE(load_along.mode, FailureMode::tip_over);
    QVERIFY2(near(load_along.accel_mps2, load_tip({{10.0, x, 0.4}}, 0.6)), text(load_along));
    QVERIFY(near(find(b.across, -1, "tips").accel_mps2, load_tip({{10.0, 0.0, 0.4}}, 0.4)));
  }

  void weakestIsTheLowest() {
    // 0.4 wide, 1.2 tall: tips along at g 0.2 / 0.6 = 3.27, below its slip (4.41).
    const auto b =
        quasi_static_bounds(pallet({carton(0.0, 0.0, 0.15, {0.4, 0.3, 1.2})}), friction());
    QVERIFY(near(b.weakest_along().accel_mps2, g * 0.2 / 0.6));
    QCOMPARE(b.weakest_along().item, 0);
    QVERIFY(near(b.weakest_across().accel_mps2, g * 0.15 / 0.6));
    QCOMPARE(QuasiStaticBounds{}.weakest_along().mode, FailureMode::no_failure);
    QCOMPARE(QuasiStaticBounds{}.weakest_along().accel_mps2, 0.0);
  }

  // Bottom 10 kg, top 5 kg, both 0.4 x 0.3 x 0.2: the bottom item's sub-stack has its COM at
  // (10 * 0.25 + 5 * 0.45) / 15 = 0.3167 m, 0.1667 m above its bottom.
  void columnTipsAboutTheCombinedCom() {
    const auto b = quasi_static_bounds(
        pallet({carton(0.0, 0.0, 0.15), carton(0.0, 0.0, 0.35, {0.4, 0.3, 0.2}, 5.0)}), friction());
    QCOMPARE(b.along.size(), std::size_t{6});
    const double h = (10.0 * 0.25 + 5.0 * 0.45) / 15.0 - 0.15;
    QVERIFY(near(find(b.along, 0, "tips").accel_mps2, g * 0.2 / h));
    QVERIFY(near(find(b.across, 0, "tips").accel_mps2, g * 0.15 / h));
    QVERIFY(near(find(b.along, 1, "tips").accel_mps2, g * 0.2 / 0.1));
    const QuasiStaticLimit top_slip = find(b.along, 1, "slips");
    QVERIFY(near(top_slip.accel_mps2, kMuItems * g));
    QCOMPARE(top_slip.what, std::string("item 1 slips on the item below (mu 0.35)"));
    QVERIFY(near(find(b.along, 0, "slips").accel_mps2, kMuDeck * g));
  }

  // The top item 10 cm forward of the bottom one: the sub-stack's COM is 5 * 0.1 / 15 m forward,
  // so its lever along X shrinks; across nothing changes.
  void offsetLoadShortensTheLever() {
    const auto b = quasi_static_bounds(
        pallet({carton(0.0, 0.0, 0.15), carton(0.1, 0.0, 0.35, {0.4, 0.3, 0.2}, 5.0)}), friction());
    const double h = (10.0 * 0.25 + 5.0 * 0.45) / 15.0 - 0.15;
    QVERIFY(near(find(b.along, 0, "tips").accel_mps2, g * (0.2 - 5.0 * 0.1 / 15.0) / h));
    QVERIFY(near(find(b.across, 0, "tips").accel_mps2, g * 0.15 / h));
  }

  // A heavy item overhanging a narrow one puts the COM beyond its edge: it tips at rest (0).
  void comBeyondTheEdgeTipsAtZero() {
    const auto b = quasi_static_bounds(pallet({carton(0.0, 0.0, 0.15, {0.2, 0.3, 0.2}, 1.0),
                                               carton(0.15, 0.0, 0.35, {0.4, 0.3, 0.2}, 30.0)}),
                                       friction());
    QCOMPARE(find(b.along, 0, "tips").accel_mps2, 0.0);
    QVERIFY(find(b.across, 0, "tips").accel_mps2 > 0.0);
  }

  void wrappedLoadsHaveNoItemMechanisms() {
    for (const WrapType wrap : {WrapType::shrink, WrapType::stretch, WrapType::banded}) {
      const auto b = quasi_static_bounds(
          pallet({carton(0.0, 0.0, 0.15), carton(0.0, 0.0, 0.35, {0.4, 0.3, 0.2}, 5.0)}, wrap),
          friction());
      QCOMPARE(b.along.size(), std::size_t{2});
      QCOMPARE(b.across.size(), std::size_t{2});
      for (const auto* list : {&b.along, &b.across}) {
        for (const auto& l : *list) QCOMPARE(l.item, -1);
      }
      QCOMPARE(b.along[0].mode, FailureMode::pallet_slip);
      QCOMPARE(b.along[1].mode, FailureMode::tip_over);
    }
  }

  // A brick: item 2 bridges items 0 and 1 (resting on both). It is held by item 1 when item 0
  // tips, so item 0 goes over alone (g 0.2 / 0.1); a carton on item 2 alone goes with item 2.
  // Counting the bridge into item 0's sub-stack put its centre of mass over item 1 and the onset
  // near zero (48 bricked dairy cases: 0.19 m/s^2 for a load that stands to 3.1).
  void aBridgingItemIsHeldByItsOtherSupport() {
    const auto b = quasi_static_bounds(pallet({carton(-0.2, 0.0, 0.15), carton(0.2, 0.0, 0.15),
                                               carton(0.0, 0.0, 0.35), carton(0.0, 0.0, 0.55)}),
                                       friction());
    QVERIFY2(near(find(b.along, 0, "tips").accel_mps2, 2.0 * g), text(find(b.along, 0, "tips")));
    QVERIFY(near(find(b.along, 1, "tips").accel_mps2, 2.0 * g));
    QVERIFY(near(find(b.along, 2, "tips").accel_mps2, g * 0.2 / 0.2));  // items 2 and 3 together
  }

  // Side by side on the deck: neither carries the other, each tips alone (g 0.2 / 0.1).
  void neighboursAreNotCarried() {
    const auto b =
        quasi_static_bounds(pallet({carton(-0.2, 0.0, 0.15), carton(0.2, 0.0, 0.15)}), friction());
    QVERIFY(near(find(b.along, 0, "tips").accel_mps2, 2.0 * g));
    QVERIFY(near(find(b.along, 1, "tips").accel_mps2, 2.0 * g));
  }

  // Regression: item 2 sits on item 1 at exactly item 0's top height, its footprint sharing only
  // the edge x = 0 with item 0's. Item 0 does not carry it; item 1 does (equal masses: the COM is
  // 0.2 m above item 1's bottom).
  void footprintsSharingAnEdgeAreNotASupport() {
    const auto b = quasi_static_bounds(
        pallet({carton(-0.2, 0.0, 0.15), carton(0.2, 0.0, 0.15), carton(0.2, 0.0, 0.35)}),
        friction());
    QVERIFY2(near(find(b.along, 0, "tips").accel_mps2, 2.0 * g), text(find(b.along, 0, "tips")));
    QVERIFY(near(find(b.across, 0, "tips").accel_mps2, g * 0.15 / 0.1));
    QVERIFY(near(find(b.along, 1, "tips").accel_mps2, g * 0.2 / 0.2));
  }
  // breakaway_slide_m against the friction law it states, integrated step by step (1 us): the
  // load lags at a - onset on its static cone until it has slipped the break-loose distance, then
  // at a - sliding until the push ends, then catches up at sliding. Coulomb's slide (breaking loose
  // at once) is the longest; below the onset nothing moves; the stop speed inverts the slide.
  void theBreakawaySlideIsItsFrictionLawIntegrated() {
    const double onset = 0.4 * g, sliding = 0.3 * g;
    auto integrated = [&](double a, double push_s, double break_loose_m) {
      const double dt = 1e-6;
      double slip = 0.0, lag = 0.0, t = 0.0;
      bool loose = break_loose_m <= 0.0;
      while (t < push_s || lag > 0.0) {
        const double friction = loose ? sliding : onset;
        const double rate = t < push_s ? a - friction : -friction;
        lag = std::max(0.0, lag + rate * dt);
        slip += lag * dt;
        if (slip >= break_loose_m) loose = true;
        t += dt;
      }
      return slip;
    };
    for (const double a : {4.5, 5.0, 7.0}) {
      for (const double push : {0.02, 0.3, 1.5}) {
        const double expected = integrated(a, push, kBreakLooseM);
        const double closed = breakaway_slide_m(onset, sliding, a, push, kBreakLooseM);
        QVERIFY2(std::abs(closed - expected) <= 1e-3 * expected + 1e-6,
                 qPrintable(
                     QString("a %1, %2 s: %3 vs %4 m").arg(a).arg(push).arg(closed).arg(expected)));
        const double coulomb = breakaway_slide_m(onset, sliding, a, push, 0.0);
        QVERIFY(std::abs(coulomb - integrated(a, push, 0.0)) <= 1e-3 * coulomb + 1e-6);
        QVERIFY(coulomb > closed);
      }
    }
    QCOMPARE(breakaway_slide_m(onset, sliding, onset, 1.0, kBreakLooseM), 0.0);
    QCOMPARE(breakaway_slide_m(onset, 0.0, 5.0, 1.0, kBreakLooseM), 1e9);
    const double v = breakaway_slide_speed_mps(onset, sliding, 5.0, 0.3, kBreakLooseM);
    QVERIFY(std::abs(breakaway_slide_m(onset, sliding, 5.0, v / 5.0, kBreakLooseM) - 0.3) < 1e-9);
    QCOMPARE(breakaway_slide_speed_mps(onset, sliding, onset, 0.3, kBreakLooseM), 1e9);
  }
};

QTEST_APPLESS_MAIN(QuasiStaticTest)
#include "quasi_static_test.moc"
