// SPDX-License-Identifier: MIT
#include "core/contract/pallet_type.hpp"

#include <QtTest>

using namespace pb;

class PalletTypeTest : public QObject {
  Q_OBJECT

 private slots:
  void eurIsTheReferencePallet() {
    const PalletTypeSpec& s = pallet_type_spec(PalletType::eur);
    QCOMPARE(s.type, PalletType::eur);
    QCOMPARE(s.dims_m, (Vec3{1.2, 0.8, 0.15}));
    QCOMPARE(s.mass_kg, 25.0);
    QCOMPARE(s.surface, std::string_view("wood_pallet"));
    QCOMPARE(s.rated_load_kg, 1500.0);
  }

  void gmaIsFortyEightByForty() {
    const PalletTypeSpec& s = pallet_type_spec(PalletType::gma);
    QCOMPARE(s.type, PalletType::gma);
    QCOMPARE(s.dims_m, (Vec3{1.219, 1.016, 0.14}));
    QCOMPARE(s.mass_kg, 17.0);
    QCOMPARE(s.surface, std::string_view("wood_pallet"));
    QCOMPARE(s.rated_load_kg, 1270.0);
  }

  void chepIsPlastic() {
    const PalletTypeSpec& s = pallet_type_spec(PalletType::chep);
    QCOMPARE(s.type, PalletType::chep);
    QCOMPARE(s.dims_m, (Vec3{1.2, 0.8, 0.15}));
    QCOMPARE(s.mass_kg, 20.0);
    QCOMPARE(s.surface, std::string_view("plastic_pallet"));
    QCOMPARE(s.rated_load_kg, 1250.0);
  }

  void everyTypeHasItsOwnSpec() {
    for (const auto& entry : EnumTable<PalletType>::names) {
      QCOMPARE(pallet_type_spec(entry.value).type, entry.value);
      // The reference caps loads at 1,200 kg; every rating sits above that.
      QVERIFY(pallet_type_spec(entry.value).rated_load_kg > 1200.0);
    }
  }
};

QTEST_APPLESS_MAIN(PalletTypeTest)
#include "pallet_type_test.moc"
