// SPDX-License-Identifier: MIT
// PalletConfig's defaults are the reference system's, so a reference payload that omits a key
// means the same pallet here.
#include <QtTest>

#include "core/contract/pallet_config.hpp"

using namespace pb;

class PalletConfigTest : public QObject {
  Q_OBJECT

 private slots:
  void defaultsMatchTheReference() {
    const PalletConfig config;
    QCOMPARE(config.base_pallet_type, PalletType::eur);
    QCOMPARE(config.base_dims_m, (Vec3{1.2, 0.8, 0.15}));
    QCOMPARE(config.base_mass_kg, 25.0);
    QVERIFY(config.items.empty());
    QCOMPARE(config.wrap, WrapType::stretch);
    QCOMPARE(config.seconds_since_temp_change, 3600.0);
    QVERIFY(config.notes.empty());
    QCOMPARE(config.belt_surface, BeltSurface::rubber_belt);
  }

  void schemaVersionIsOne() { QCOMPARE(kSchemaVersion, 1); }

  void equalityComparesEveryField() {
    const PalletConfig a;
    PalletConfig b;
    QVERIFY(a == b);
    b.items.push_back(Item{});
    QVERIFY(a != b);
    b = a;
    b.belt_surface = BeltSurface::steel_roller;
    QVERIFY(a != b);
    b = a;
    b.notes = "x";
    QVERIFY(a != b);
  }

  void itemDerivedQuantities() {
    Item item;
    item.dims_m = {0.4, 0.3, 0.2};
    item.position = {0.1, -0.2, 0.15};
    QCOMPARE(item.center_of_mass(), (Vec3{0.1, -0.2, 0.25}));
    QCOMPARE(item.top_z(), 0.15 + 0.2);
  }
};

QTEST_APPLESS_MAIN(PalletConfigTest)
#include "pallet_config_test.moc"
