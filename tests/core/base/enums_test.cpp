// SPDX-License-Identifier: MIT
#include "core/base/enums.hpp"

#include <QtTest>

using namespace pb;

namespace {

static_assert(to_string(WrapType::banded) == "banded");
static_assert(enum_from_string<PalletType>("CHEP") == PalletType::chep);

// Every value of E in declaration order, each name unique, and each name read back to its value.
template <class E>
void check_round_trip() {
  const auto& names = EnumTable<E>::names;
  for (std::size_t i = 0; i < names.size(); ++i) {
    QCOMPARE(static_cast<std::size_t>(names[i].value), i);
    QCOMPARE(to_string(names[i].value), names[i].name);
    QCOMPARE(enum_from_string<E>(names[i].name), std::optional<E>(names[i].value));
    for (std::size_t j = i + 1; j < names.size(); ++j) QVERIFY(names[i].name != names[j].name);
  }
}

template <class E>
QString choices() {
  return QString::fromStdString(enum_choices<E>());
}

}  // namespace

class EnumsTest : public QObject {
  Q_OBJECT

 private slots:
  void everyNameRoundTrips() {
    check_round_trip<Fragility>();
    check_round_trip<WrapType>();
    check_round_trip<Environment>();
    check_round_trip<FailureMode>();
    check_round_trip<ProfileShape>();
    check_round_trip<PalletType>();
    check_round_trip<BeltSurface>();
    check_round_trip<LayerPattern>();
  }

  void tableSizes() {
    QCOMPARE(EnumTable<Fragility>::names.size(), std::size_t{3});
    QCOMPARE(EnumTable<WrapType>::names.size(), std::size_t{4});
    QCOMPARE(EnumTable<Environment>::names.size(), std::size_t{4});
    QCOMPARE(EnumTable<FailureMode>::names.size(), std::size_t{6});
    QCOMPARE(EnumTable<ProfileShape>::names.size(), std::size_t{6});
    QCOMPARE(EnumTable<PalletType>::names.size(), std::size_t{3});
    QCOMPARE(EnumTable<BeltSurface>::names.size(), std::size_t{2});
    QCOMPARE(EnumTable<LayerPattern>::names.size(), std::size_t{4});
  }

  void referenceNames() {
    QCOMPARE(to_string(PalletType::eur), std::string_view("EUR"));
    QCOMPARE(to_string(Environment::transitioning), std::string_view("transitioning"));
    QCOMPARE(to_string(FailureMode::top_item_slide), std::string_view("top_item_slide"));
    QCOMPARE(to_string(ProfileShape::ramp_decel), std::string_view("ramp_decel"));
  }

  void unknownNamesAreNullopt() {
    QCOMPARE(enum_from_string<Fragility>("glass"), std::optional<Fragility>());
    QCOMPARE(enum_from_string<PalletType>("eur"), std::optional<PalletType>());  // case-sensitive
    QCOMPARE(enum_from_string<WrapType>(""), std::optional<WrapType>());
    QCOMPARE(enum_from_string<BeltSurface>("rubber_belt "), std::optional<BeltSurface>());
    QCOMPARE(enum_from_string<Environment>("Frozen"), std::optional<Environment>());
  }

  void valueOutsideTheTableIsQuestionMark() {
    QCOMPARE(to_string(static_cast<WrapType>(42)), std::string_view("?"));
  }

  void choicesText() {
    QCOMPARE(choices<Fragility>(), QStringLiteral("rigid, semi_rigid or deformable"));
    QCOMPARE(choices<WrapType>(), QStringLiteral("none, shrink, stretch or banded"));
    QCOMPARE(choices<Environment>(),
             QStringLiteral("frozen, refrigerated, thawed or transitioning"));
    QCOMPARE(choices<FailureMode>(),
             QStringLiteral("no_failure, tip_over, top_item_slide, pallet_slip, load_shift or "
                            "cannot_stand"));
    QCOMPARE(choices<ProfileShape>(),
             QStringLiteral("accel_hold, constant, ramp_decel, estop, curve or eumos"));
    QCOMPARE(choices<PalletType>(), QStringLiteral("EUR, GMA or CHEP"));
    QCOMPARE(choices<BeltSurface>(), QStringLiteral("rubber_belt or steel_roller"));
    QCOMPARE(choices<LayerPattern>(), QStringLiteral("column, brick, pinwheel or irregular"));
  }
};

QTEST_APPLESS_MAIN(EnumsTest)
#include "enums_test.moc"
