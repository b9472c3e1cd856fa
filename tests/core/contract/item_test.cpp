// SPDX-License-Identifier: MIT
#include "core/contract/item.hpp"

#include <QtTest>

using namespace pb;

class ItemTest : public QObject {
  Q_OBJECT

 private slots:
  void defaultsAreTheReferenceCarton() {
    const Item item;
    QCOMPARE(item.weight_kg, 10.0);
    QCOMPARE(item.dims_m, (Vec3{0.4, 0.3, 0.2}));
    QCOMPARE(item.position, (Vec3{0.0, 0.0, 0.15}));
    QCOMPARE(item.fragility, Fragility::rigid);
  }

  void centerOfMassIsHalfTheHeightAboveTheBottomFace() {
    Item item;
    item.position = {0.25, -0.1, 0.35};
    item.dims_m = {0.5, 0.3, 0.24};
    item.orientation_deg = 90.0;  // yaw does not move the centre
    QCOMPARE(item.center_of_mass(), (Vec3{0.25, -0.1, 0.47}));
  }

  void topZIsBottomPlusHeight() {
    Item item;
    item.position = {0.0, 0.0, 0.35};
    item.dims_m = {0.4, 0.3, 0.2};
    QCOMPARE(item.top_z(), 0.55);
    item.position[2] = 0.15;
    QCOMPARE(item.top_z(), 0.35);
  }

  void equalityComparesEveryField() {
    Item a;
    Item b;
    QVERIFY(a == b);
    b.sku = "SKU-FM-001";
    QVERIFY(!(a == b));
    b = a;
    b.orientation_deg = 1.0;
    QVERIFY(!(a == b));
  }
};

QTEST_APPLESS_MAIN(ItemTest)
#include "item_test.moc"
