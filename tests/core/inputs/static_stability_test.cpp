// SPDX-License-Identifier: MIT
// Can the load stand: margins and load paths against closed-form statics (a carton on the deck, on
// an offset carton, the harmonic stack whose sub-stacks overhang, a carton bridging two), the
// suggested correction, and validate()'s rule with its pointer and sentence.
#include <QtTest>

#include <cmath>

#include "core/inputs/static_stability.hpp"
#include "core/inputs/validation.hpp"
#include "tests/core/test_pallets.hpp"

using namespace pb;
using test::carton;

namespace {

constexpr double kDeck = 0.15;  // the default EUR deck top
constexpr double kH = 0.2;      // the test carton's height

QString describe(const Diagnostics& diagnostics) {
  QStringList out;
  for (const auto& d : diagnostics) out << QString::fromStdString(to_string(d));
  return out.join('\n');
}

Diagnostics errors(const PalletConfig& config) {
  return errors_of(validate(config));
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace

class StaticStabilityTest : public QObject {
  Q_OBJECT

 private slots:
  // On the deck the region is the footprint: the margin is half the narrower side.
  void onTheDeckTheMarginIsHalfTheWidth() {
    const auto s = standing(test::pallet({carton(0.1, -0.05, kDeck)}));
    QCOMPARE(s.size(), std::size_t{1});
    QVERIFY(s[0].on_deck);
    QVERIFY(s[0].supports.empty());
    QCOMPARE(s[0].load_kg, 10.0);
    QVERIFY(std::abs(s[0].margin_m - 0.15) < 1e-12);
  }

  // Overhanging the deck's edge: the deck's edge bounds the region.
  void theDeckEdgeBoundsTheRegion() {
    // The carton's centre 0.55 m from the centre of a 1.2 m deck: 5 cm inside its edge.
    const auto s = standing(test::pallet({carton(0.55, 0.0, kDeck)}));
    QVERIFY(std::abs(s[0].margin_m - 0.05) < 1e-12);
  }

  // A carton offset by dx on one of the same size: the region ends at the lower carton's edge,
  // L/2 - dx from the centre of mass (outside when dx > L/2).
  void anOffsetCartonStandsByHalfItsLengthLessTheOffset_data() {
    QTest::addColumn<double>("dx");
    QTest::newRow("centred") << 0.0;
    QTest::newRow("5 cm") << 0.05;
    QTest::newRow("on the edge") << 0.2;
    QTest::newRow("5 cm out") << 0.25;
  }
  void anOffsetCartonStandsByHalfItsLengthLessTheOffset() {
    QFETCH(double, dx);
    const auto s = standing(test::pallet({carton(0.0, 0.0, kDeck), carton(dx, 0.0, kDeck + kH)}));
    QCOMPARE(s[1].supports, std::vector<std::size_t>{0});
    const double expected = dx < 0.2 - 0.15 ? 0.15 : 0.2 - dx;  // the width binds when centred
    QVERIFY2(std::abs(s[1].margin_m - expected) < 1e-9,
             qPrintable(QString("margin %1, expected %2").arg(s[1].margin_m).arg(expected)));
    // The lower carton bears both weights where the upper one's resultant acts.
    QCOMPARE(s[0].load_kg, 20.0);
    const double resultant = dx / 2.0;  // the upper load passes down whole, wherever it acts
    if (dx <= 0.2) QVERIFY(std::abs(s[0].load_point[0] - resultant) < 1e-9);
  }

  // Three cartons on a base, each offset 0.16 m (0.4 L) from the one below: every carton is over
  // the one under it, but the sub-stacks are not. Carton 3 stands (0.52 - 0.48 = +0.04); cartons
  // 2 and 3 act at 0.40, 4 cm beyond carton 1's end (-0.04): carton 2 tips there, over the edge at
  // 0.36, so carton 1 bears 10 kg at 0.16 and 20 kg at 0.36: 0.2933, 93 mm beyond the base's end.
  void subStacksAreJudgedWithWhatTheyCarry() {
    const auto config =
        test::pallet({carton(0.0, 0.0, kDeck), carton(0.16, 0.0, kDeck + kH),
                      carton(0.32, 0.0, kDeck + 2 * kH), carton(0.48, 0.0, kDeck + 3 * kH)});
    const auto s = standing(config);
    QVERIFY(std::abs(s[1].margin_m + (0.16 + 2 * 0.36) / 3.0 - 0.2) < 1e-9);
    QVERIFY(std::abs(s[2].margin_m + 0.04) < 1e-9);
    QVERIFY(std::abs(s[3].margin_m - 0.04) < 1e-9);
    QCOMPARE(s[1].load_kg, 30.0);
    QCOMPARE(carried_items(config, 1), (std::vector<std::size_t>{2, 3}));
    QVERIFY(!stands(config, 0.01));

    // validate(): each carton that cannot carry its load, at its position, naming what it carries.
    const Diagnostics found = errors(config);
    QVERIFY2(found.size() == 2, qPrintable(describe(found)));
    QCOMPARE(found[0].pointer, std::string("/items/1/position"));
    QCOMPARE(found[1].pointer, std::string("/items/2/position"));
    const std::string& m = found[0].message;
    QVERIFY2(contains(m,
                      "item 1 (test) cannot stand: the centre of mass of it and the 2 items it "
                      "carries is 93 mm outside the edge of what it rests on (item 0)"),
             m.c_str());
    QVERIFY2(contains(m, "move item 1 (test) and the 2 items it carries "), m.c_str());
    QVERIFY2(contains(m, "towards -x"), m.c_str());
  }

  // A carton across two: the union of the patches is its whole footprint and its resultant is at
  // its centroid, so the pressure is uniform and each support takes its share of the area.
  void aBridgingCartonSharesItsWeightByArea() {
    const auto config =
        test::pallet({carton(-0.2, 0.0, kDeck), carton(0.2, 0.0, kDeck),
                      carton(-0.1, 0.0, kDeck + kH, {0.4, 0.3, 0.2}, 40.0)});  // 3/4 on item 0
    const auto s = standing(config);
    QCOMPARE(s[2].supports, (std::vector<std::size_t>{0, 1}));
    QVERIFY(std::abs(s[0].load_kg - (10.0 + 30.0)) < 1e-9);
    QVERIFY(std::abs(s[1].load_kg - (10.0 + 10.0)) < 1e-9);
    // Item 1 takes the 10 kg at the centre of its patch (x from 0 to 0.1).
    QVERIFY(std::abs(s[1].load_point[0] - (10.0 * 0.2 + 10.0 * 0.05) / 20.0) < 1e-9);
    QVERIFY(stands(config, 0.01));
    QVERIFY2(errors(config).empty(), qPrintable(describe(errors(config))));
  }

  // Lifted supports: a carton whose load acts far to one side of its two patches. A linear
  // pressure over the union (x from -0.35 to 0.05, the load at -0.24: eccentric by 0.09, beyond
  // the kern's L/6) would pull on the small patch over item 1: it is lifted, item 0 takes all.
  void aSupportTheLoadWouldPullOnIsLifted() {
    PalletConfig config = test::pallet({carton(-0.2, 0.0, kDeck), carton(0.2, 0.0, kDeck),
                                        carton(-0.15, 0.0, kDeck + kH),
                                        carton(-0.25, 0.0, kDeck + 2 * kH, {0.2, 0.3, 0.2}, 90.0)});
    const auto s = standing(config);
    QCOMPARE(s[2].supports, (std::vector<std::size_t>{0, 1}));
    QVERIFY(std::abs(s[2].load_point[0] + 0.24) < 1e-9);
    QVERIFY(std::abs(s[1].load_kg - 10.0) < 1e-9);
    QVERIFY(std::abs(s[0].load_kg - 110.0) < 1e-9);
    QVERIFY(std::abs(s[0].load_point[0] - (10.0 * -0.2 + 100.0 * -0.24) / 110.0) < 1e-9);
    // With a lighter top (30 kg, eccentric by 0.075) both patches still push: nothing lost.
    config.items[3].weight_kg = 30.0;
    const auto light = standing(config);
    QVERIFY(light[1].load_kg > 10.0);
    QVERIFY(std::abs(light[0].load_kg + light[1].load_kg - 60.0) < 1e-9);
  }

  // The suggested shift, applied to the carton and what it carries, makes it stand (to the mm).
  void theCorrectionMakesItStand_data() {
    QTest::addColumn<double>("dx");
    QTest::addColumn<double>("dy");
    QTest::newRow("+x, out") << 0.25 << 0.0;
    QTest::newRow("-x, on the edge") << -0.2 << 0.0;
    QTest::newRow("+y, just in") << 0.0 << 0.145;
    QTest::newRow("diagonal") << 0.23 << 0.16;
  }
  void theCorrectionMakesItStand() {
    QFETCH(double, dx);
    QFETCH(double, dy);
    PalletConfig config = test::pallet(
        {carton(0.0, 0.0, kDeck), carton(dx, dy, kDeck + kH), carton(dx, dy, kDeck + 2 * kH)});
    const auto s = standing(config);
    QVERIFY(s[1].margin_m < 0.01);
    const auto shift = standing_correction(config, s, 1, 0.01);
    QVERIFY(shift.has_value());
    for (std::size_t i : {std::size_t{1}, std::size_t{2}}) {
      config.items[i].position[0] += (*shift)[0];
      config.items[i].position[1] += (*shift)[1];
    }
    const auto after = standing(config);
    QVERIFY2(after[1].margin_m >= 0.01 - 1e-9, qPrintable(QString::number(after[1].margin_m)));
    // The smallest such shift: a millimetre less does not do.
    const double length = std::hypot((*shift)[0], (*shift)[1]);
    QVERIFY(after[1].margin_m < 0.01 + 0.0015);
    QVERIFY(length > 0.0);
    QVERIFY2(errors(config).empty(), qPrintable(describe(errors(config))));
  }

  // Stable but precarious: centred on a smaller carton, it stands (no error) and the low-support
  // warning stays.
  void precariousButStandingIsAWarning() {
    const auto config = test::pallet(
        {carton(0.0, 0.0, kDeck, {0.2, 0.2, 0.2}), carton(0.0, 0.0, kDeck + kH, {0.4, 0.3, 0.2})});
    Diagnostics all;
    for (const Diagnostic& d : validate(config)) {
      if (d.pointer.rfind("/items/1", 0) == 0 && d.pointer != "/items/1/sku") all.push_back(d);
    }
    QVERIFY2(all.size() == 1, qPrintable(describe(all)));
    QCOMPARE(all[0].severity, Severity::warning);
    QCOMPARE(all[0].pointer, std::string("/items/1"));
    QVERIFY(contains(all[0].message, "rests on only 33 %"));
  }

  // The margin is the rule's: 9 mm inside is an error, 10 mm is not.
  void theMarginIsTheRule() {
    auto offset = [](double dx) {
      return test::pallet({carton(0.0, 0.0, kDeck), carton(dx, 0.0, kDeck + kH)});
    };
    QVERIFY(errors(offset(0.19)).empty());  // 10 mm inside
    const Diagnostics nine = errors(offset(0.191));
    QVERIFY2(nine.size() == 1, qPrintable(describe(nine)));
    QVERIFY(contains(nine[0].message,
                     "is 9 mm inside the edge of what it rests on (item 0) and "
                     "must be at least 10 mm inside; move item 1 (test) 1 mm "
                     "towards -x"));
    ValidationLimits off;
    off.check_standing = false;
    QVERIFY(errors_of(validate(offset(0.3), off)).empty());
  }

  // Yawed cartons: the patches are the clipped polygons, not boxes.
  void yawedCartonsUseTheirFootprints() {
    // A 0.4 x 0.4 carton turned 45 degrees on a 0.4 x 0.4 carton: its corners overhang, the
    // octagonal patch has its centroid at the centre: margin = 0.2 (the square's half-width).
    const auto config = test::pallet({carton(0.0, 0.0, kDeck, {0.4, 0.4, 0.2}),
                                      carton(0.0, 0.0, kDeck + kH, {0.4, 0.4, 0.2}, 10.0, 45.0)});
    const auto s = standing(config);
    QVERIFY(std::abs(s[1].margin_m - 0.2) < 1e-9);
  }
};

QTEST_APPLESS_MAIN(StaticStabilityTest)
#include "static_stability_test.moc"
