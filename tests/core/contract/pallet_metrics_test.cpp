// SPDX-License-Identifier: MIT
// Mass, centre of mass, height, yaw-aware overhang, footprint overlap and support fractions.
#include <QtTest>

#include <cmath>

#include "core/contract/pallet_metrics.hpp"
#include "tests/core/test_pallets.hpp"

using namespace pb;

namespace {

constexpr double kEps = 1e-12;

Item box(double x, double y, double z, double l, double w, double h, double yaw = 0.0,
         double kg = 10.0) {
  Item item;
  item.sku = "T";
  item.weight_kg = kg;
  item.dims_m = {l, w, h};
  item.position = {x, y, z};
  item.orientation_deg = yaw;
  return item;
}

PalletConfig pallet(std::vector<Item> items) {
  PalletConfig config;
  config.items = std::move(items);
  return config;
}

std::vector<Vec2> square(double cx, double cy, double side) {
  const double h = side / 2.0;
  return {{cx - h, cy - h}, {cx + h, cy - h}, {cx + h, cy + h}, {cx - h, cy + h}};
}

bool near(double a, double b) {
  return std::abs(a - b) <= kEps;
}

}  // namespace

class PalletMetricsTest : public QObject {
  Q_OBJECT

 private slots:
  void totalMassIsBasePlusItems() {
    QCOMPARE(total_mass_kg(pallet({})), 25.0);
    QCOMPARE(total_mass_kg(pallet({box(0, 0, 0.15, 0.4, 0.4, 0.2, 0, 10.0),
                                   box(0, 0, 0.35, 0.4, 0.4, 0.2, 0, 15.5)})),
             50.5);
  }

  void compositeComWeighsBaseAndItems() {
    QCOMPARE(composite_com_m(pallet({})), (Vec3{0.0, 0.0, 0.075}));
    // Base 25 kg at z 0.075; item 25 kg centred at (0.4, -0.2, 0.25).
    const Vec3 com = composite_com_m(pallet({box(0.4, -0.2, 0.15, 0.4, 0.4, 0.2, 0, 25.0)}));
    QVERIFY(near(com[0], 0.2));
    QVERIFY(near(com[1], -0.1));
    QVERIFY(near(com[2], (0.075 + 0.25) / 2.0));
  }

  void stackHeightIsTheHighestTopOrTheDeck() {
    QCOMPARE(stack_height_m(pallet({})), 0.15);
    QCOMPARE(
        stack_height_m(pallet({box(0, 0, 0.15, 0.4, 0.4, 0.2), box(0.5, 0, 0.15, 0.2, 0.2, 0.5),
                               box(0, 0, 0.35, 0.4, 0.4, 0.1)})),
        0.65);
  }

  void footprintIsCounterClockwiseAndYawed() {
    const auto flat = item_footprint(box(1.0, 2.0, 0, 0.4, 0.2, 0.1));
    QCOMPARE(flat[0], (Vec2{0.8, 1.9}));
    QCOMPARE(flat[1], (Vec2{1.2, 1.9}));
    QCOMPARE(flat[2], (Vec2{1.2, 2.1}));
    QCOMPARE(flat[3], (Vec2{0.8, 2.1}));
    // A quarter turn swaps the extents exactly.
    const auto turned = item_footprint(box(0.0, 0.0, 0, 0.4, 0.2, 0.1, 90.0));
    QCOMPARE(turned[0], (Vec2{0.1, -0.2}));
    QCOMPARE(turned[1], (Vec2{0.1, 0.2}));
    QCOMPARE(turned[2], (Vec2{-0.1, 0.2}));
    QCOMPARE(turned[3], (Vec2{-0.1, -0.2}));
    const auto back = item_footprint(box(0.0, 0.0, 0, 0.4, 0.2, 0.1, -180.0));
    QCOMPARE(back[0], (Vec2{0.2, 0.1}));
  }

  void overhangIsZeroInsideTheFootprint() {
    QCOMPARE(overhang_m(pallet({})), 0.0);
    QCOMPARE(overhang_m(pallet({box(0.0, 0.0, 0.15, 0.4, 0.4, 0.2)})), 0.0);
  }

  void overhangMeasuresTheFurthestReach() {
    // 0.5 + 0.2 - 0.6 along X; 0.35 + 0.1 - 0.4 along Y for the second item.
    const PalletConfig config =
        pallet({box(0.5, 0.0, 0.15, 0.4, 0.2, 0.2), box(0.0, 0.35, 0.15, 0.2, 0.2, 0.2)});
    QVERIFY(near(overhang_m(config), 0.1));
    QVERIFY(near(item_overhang_m(config.items[1], config.base_dims_m), 0.05));
    QVERIFY(near(item_overhang_m(box(-0.5, -0.35, 0.15, 0.4, 0.2, 0.2), {1.2, 0.8, 0.15}), 0.1));
  }

  void overhangAccountsForYaw() {
    // 0.6 x 0.2 at x = 0.5: 0.2 beyond the edge lengthwise, within it when turned 90 degrees.
    QVERIFY(near(overhang_m(pallet({box(0.5, 0.0, 0.15, 0.6, 0.2, 0.2)})), 0.2));
    QCOMPARE(overhang_m(pallet({box(0.5, 0.0, 0.15, 0.6, 0.2, 0.2, 90.0)})), 0.0);
    // A 0.4 m square touching the edge reaches 0.2 * (sqrt 2 - 1) further at 45 degrees.
    QCOMPARE(overhang_m(pallet({box(0.4, 0.0, 0.15, 0.4, 0.4, 0.2)})), 0.0);
    QVERIFY(near(overhang_m(pallet({box(0.4, 0.0, 0.15, 0.4, 0.4, 0.2, 45.0)})),
                 0.2 * (std::sqrt(2.0) - 1.0)));
  }

  void convexOverlapOfSquares() {
    QVERIFY(near(convex_overlap_area(square(0, 0, 1), square(0.5, 0, 1)), 0.5));
    QVERIFY(near(convex_overlap_area(square(0, 0, 1), square(0.5, 0.5, 1)), 0.25));
    QVERIFY(near(convex_overlap_area(square(0, 0, 1), square(0, 0, 0.5)), 0.25));
    QVERIFY(near(convex_overlap_area(square(0, 0, 0.5), square(0, 0, 1)), 0.25));
    QCOMPARE(convex_overlap_area(square(0, 0, 1), square(2, 0, 1)), 0.0);
    QCOMPARE(convex_overlap_area(square(0, 0, 1), square(1, 0, 1)), 0.0);  // touching edges
    QCOMPARE(convex_overlap_area({}, square(0, 0, 1)), 0.0);
  }

  void convexOverlapOfASquareAndItsDiamond() {
    // A unit square and the same square turned 45 degrees overlap in an octagon of 2(sqrt 2 - 1).
    const Item a = box(0, 0, 0, 1, 1, 1);
    const Item b = box(0, 0, 0, 1, 1, 1, 45.0);
    QVERIFY(near(footprint_overlap_area(a, b), 2.0 * (std::sqrt(2.0) - 1.0)));
    QVERIFY(near(footprint_overlap_area(b, a), 2.0 * (std::sqrt(2.0) - 1.0)));
  }

  void itemsOnTheDeckAreSupportedByItsRectangle() {
    const auto f = support_fractions(
        pallet({box(0.0, 0.0, 0.15, 0.4, 0.4, 0.2), box(0.6, 0.0, 0.1505, 0.4, 0.4, 0.2),
                box(0.0, 0.4, 0.15, 0.4, 0.4, 0.2, 90.0)}));
    QCOMPARE(f.size(), std::size_t{3});
    QCOMPARE(f[0], 1.0);
    QVERIFY(near(f[1], 0.5));  // half over the X edge, 0.5 mm gap within tolerance
    QVERIFY(near(f[2], 0.5));  // half over the Y edge
  }

  void brickItemOnOneCartonIsHalfSupported() {
    const auto f = support_fractions(
        pallet({box(-0.2, 0.0, 0.15, 0.4, 0.4, 0.2), box(0.0, 0.0, 0.35, 0.4, 0.4, 0.2)}));
    QCOMPARE(f[0], 1.0);
    QVERIFY(near(f[1], 0.5));
  }

  void brickItemOnTwoCartonsIsFullySupported() {
    const auto f = support_fractions(
        pallet({box(-0.2, 0.0, 0.15, 0.4, 0.4, 0.2), box(0.2, 0.0, 0.15, 0.4, 0.4, 0.2),
                box(0.0, 0.0, 0.35, 0.4, 0.4, 0.2)}));
    QVERIFY(near(f[2], 1.0));
  }

  void yawedItemOnACarton() {
    const auto f = support_fractions(
        pallet({box(0.0, 0.0, 0.15, 0.4, 0.4, 0.2), box(0.0, 0.0, 0.35, 0.4, 0.4, 0.2, 45.0)}));
    QVERIFY(near(f[1], 2.0 * (std::sqrt(2.0) - 1.0)));
  }

  void floatingItemIsUnsupported() {
    const auto f = support_fractions(
        pallet({box(0.0, 0.0, 0.15, 0.4, 0.4, 0.2), box(0.0, 0.0, 0.36, 0.4, 0.4, 0.2)}));
    QCOMPARE(f[1], 0.0);
    const auto loose = support_fractions(
        pallet({box(0.0, 0.0, 0.15, 0.4, 0.4, 0.2), box(0.0, 0.0, 0.36, 0.4, 0.4, 0.2)}), 0.02);
    QCOMPARE(loose[1], 1.0);
  }

  void supportIsClampedToOne() {
    // Two identical cartons under one (an invalid layout) do not give 200 %.
    const auto f = support_fractions(
        pallet({box(0.0, 0.0, 0.15, 0.4, 0.4, 0.2), box(0.0, 0.0, 0.15, 0.4, 0.4, 0.2),
                box(0.0, 0.0, 0.35, 0.4, 0.4, 0.2)}));
    QCOMPARE(f[2], 1.0);
  }

  // Every item has a twin at (-x, y, z) of the same size, mass and SKU; an item on the plane is
  // its own twin; a turned item's footprint counts, not its yaw.
  void mirrorSymmetryAlongTheBelt() {
    using test::carton;
    QVERIFY(mirror_symmetric_along(test::pallet({})));
    QVERIFY(mirror_symmetric_along(test::pallet({carton(0, 0.1, 0.15)})));
    QVERIFY(mirror_symmetric_along(
        test::pallet({carton(-0.3, 0, 0.15), carton(0.3, 0, 0.15), carton(0, 0, 0.35)})));
    QVERIFY(mirror_symmetric_along(test::pallet({carton(-0.3, 0, 0.15, {0.4, 0.3, 0.2}, 10.0, 90.0),
                                                 carton(0.3, 0, 0.15, {0.3, 0.4, 0.2})})));
    QVERIFY(!mirror_symmetric_along(test::pallet({carton(0.1, 0, 0.15)})));
    QVERIFY(!mirror_symmetric_along(
        test::pallet({carton(-0.3, 0, 0.15), carton(0.3, 0, 0.15, {0.4, 0.3, 0.2}, 11.0)})));
    QVERIFY(!mirror_symmetric_along(
        test::pallet({carton(-0.3, 0, 0.15), carton(0.3, 0, 0.15, {0.4, 0.3, 0.25})})));
    QVERIFY(
        !mirror_symmetric_along(test::pallet({carton(0, 0, 0.15, {0.4, 0.3, 0.2}, 10.0, 30.0)})));
    // Across the belt: twins at (x, -y, z).
    QVERIFY(mirror_symmetric_across(
        test::pallet({carton(0.1, -0.2, 0.15), carton(0.1, 0.2, 0.15), carton(0.3, 0, 0.15)})));
    QVERIFY(!mirror_symmetric_across(test::pallet({carton(0, -0.267, 0.15)})));
    QVERIFY(mirror_symmetric_across(test::pallet({carton(0.2, 0, 0.15)})));
    // Two cartons on one side cannot share the one twin on the other.
    QVERIFY(!mirror_symmetric_along(
        test::pallet({carton(-0.3, 0, 0.15), carton(-0.3, 0, 0.35), carton(0.3, 0, 0.15)})));
  }

  // The sweep finds exactly the pairs whose footprint bounds come within the margin, as checking
  // every pair does: a grid, a brick layer, yawed items, touching edges and a non-finite item.
  void footprintNeighboursAreEveryPairThatCanMeet() {
    std::vector<Item> items;
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 5; ++c)
        items.push_back(box(0.4 * c - 0.8, 0.3 * r - 0.45, 0.144, 0.4, 0.3, 0.2));
    }
    for (int c = 0; c < 4; ++c)
      items.push_back(box(0.4 * c - 0.6, 0.0, 0.344, 0.4, 0.3, 0.2, 30.0 * c));
    items.push_back(box(0.7, 0.9, 0.144, 0.2, 0.2, 0.2));
    items.push_back(box(std::nan(""), 0.0, 0.144, 0.2, 0.2, 0.2));
    const PalletConfig config = pallet(items);
    for (const double margin : {0.0, 0.01, 0.5}) {
      const auto neighbours = footprint_neighbours(config, margin);
      QCOMPARE(neighbours.size(), items.size());
      for (std::size_t i = 0; i < items.size(); ++i) {
        std::vector<std::size_t> expected;
        for (std::size_t j = 0; j < items.size(); ++j) {
          if (j == i) continue;
          auto bounds = [](const Item& it) {
            std::array<double, 4> b{1e300, -1e300, 1e300, -1e300};
            for (const Vec2& v : item_footprint(it)) {
              b = {std::min(b[0], v[0]), std::max(b[1], v[0]), std::min(b[2], v[1]),
                   std::max(b[3], v[1])};
            }
            return b;
          };
          const auto a = bounds(items[i]);
          const auto b = bounds(items[j]);
          if (!std::isfinite(items[i].position[0]) || !std::isfinite(items[j].position[0]))
            continue;
          if (b[0] <= a[1] + margin && a[0] <= b[1] + margin && b[2] <= a[3] + margin &&
              a[2] <= b[3] + margin) {
            expected.push_back(j);
          }
        }
        QCOMPARE(neighbours[i], expected);
      }
    }
    // A layer side by side: each inner carton of the grid touches its eight neighbours' bounds.
    QCOMPARE(footprint_neighbours(config)[6].size(), std::size_t{8 + 2});
  }
};

QTEST_APPLESS_MAIN(PalletMetricsTest)
#include "pallet_metrics_test.moc"
