// SPDX-License-Identifier: MIT
// Every validation rule: its pointer, its severity, and that one bad number gives one finding.
#include <QtTest>

#include <cmath>
#include <limits>

#include "core/inputs/validation.hpp"
#include "tests/core/test_pallets.hpp"

using namespace pb;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A 25 kg, 0.40 x 0.40 x 0.15 m cheese case (SKU-FD-001) with its bottom centre at (x, y, z).
Item cheese(double x, double y, double z, double yaw = 0.0) {
  Item item;
  item.sku = "SKU-FD-001";
  item.weight_kg = 25.0;
  item.dims_m = {0.4, 0.4, 0.15};
  item.position = {x, y, z};
  item.orientation_deg = yaw;
  return item;
}

// Two cases side by side with a 2 mm gap (items 0 and 1), a third on item 0 (item 2).
PalletConfig valid() {
  PalletConfig config;
  config.pallet_id = "P-1";
  config.items = {cheese(-0.201, 0.0, 0.15), cheese(0.201, 0.0, 0.15), cheese(-0.201, 0.0, 0.30)};
  return config;
}

QString describe(const Diagnostics& diagnostics) {
  QStringList out;
  for (const auto& d : diagnostics) out << QString::fromStdString(to_string(d));
  return out.join('\n');
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace

// Asserts exactly one finding, at `ptr` with severity `sev`; leaves it in `only` for more checks.
#define EXPECT_ONE(diagnostics, ptr, sev)                              \
  do {                                                                 \
    const Diagnostics found_ = (diagnostics);                          \
    QVERIFY2(found_.size() == 1, qPrintable(describe(found_)));        \
    QCOMPARE(QString::fromStdString(found_[0].pointer), QString(ptr)); \
    QCOMPARE(found_[0].severity, sev);                                 \
    only = found_[0];                                                  \
  } while (false)

class ValidationTest : public QObject {
  Q_OBJECT

  Diagnostic only;

 private slots:
  void validPalletHasNoFindings() {
    const Diagnostics found = validate(valid());
    QVERIFY2(found.empty(), qPrintable(describe(found)));
    // An empty pallet is valid (its limits are the base's), with a warning that says so.
    EXPECT_ONE(validate(PalletConfig{}), "/items", Severity::warning);
    QVERIFY(only.message.find("no items") != std::string::npos);
  }

  void emptyPalletId() {
    PalletConfig config = valid();
    config.pallet_id.clear();
    EXPECT_ONE(validate(config), "/pallet_id", Severity::error);
  }

  void baseDimsRanges_data() {
    QTest::addColumn<int>("axis");
    QTest::addColumn<double>("value");
    QTest::newRow("length zero") << 0 << 0.0;
    QTest::newRow("length above 3 m") << 0 << 3.01;
    QTest::newRow("width negative") << 1 << -0.8;
    QTest::newRow("width NaN") << 1 << kNaN;
    QTest::newRow("height above 0.5 m") << 2 << 0.51;
    QTest::newRow("height infinite") << 2 << std::numeric_limits<double>::infinity();
  }
  void baseDimsRanges() {
    QFETCH(int, axis);
    QFETCH(double, value);
    PalletConfig config = valid();
    config.base_dims_m[static_cast<std::size_t>(axis)] = value;
    EXPECT_ONE(validate(config), "/base_dims_m/" + QString::number(axis), Severity::error);
  }

  void baseDimsFarFromTheTypeAreAWarning() {
    PalletConfig config = valid();
    config.base_dims_m = {1.2, 0.86, 0.15};
    EXPECT_ONE(validate(config), "/base_dims_m", Severity::warning);
    QVERIFY(contains(only.message, "EUR"));
    config.base_dims_m = {1.2, 0.84, 0.15};  // within 5 cm
    QVERIFY(validate(config).empty());
    config.base_pallet_type = PalletType::gma;  // 1.219 x 1.016: 17.6 cm wider
    config.base_dims_m = {1.2, 0.8, 0.15};
    EXPECT_ONE(validate(config), "/base_dims_m", Severity::warning);
  }

  void baseMass() {
    PalletConfig config = valid();
    for (double bad : {0.0, 100.5, kNaN}) {
      config.base_mass_kg = bad;
      EXPECT_ONE(validate(config), "/base_mass_kg", Severity::error);
    }
    config.base_mass_kg = 100.0;
    QVERIFY(validate(config).empty());
  }

  void bodyTemperature() {
    PalletConfig config = valid();
    for (double bad : {-40.5, 40.5, kNaN}) {
      config.body_temp_c = bad;
      EXPECT_ONE(validate(config), "/body_temp_c", Severity::error);
    }
    config.env = Environment::frozen;
    config.body_temp_c = -40.0;
    QVERIFY(validate(config).empty());
  }

  // The friction follows body_temp_c; an env that disagrees with it (a frozen load at +20 degC) is
  // a sign that one of them is wrong: a warning at /body_temp_c naming both.
  void envAndTemperatureThatDisagreeAreWarned() {
    PalletConfig config = valid();
    struct Case {
      Environment env;
      double temp_c;
      bool warned;
    };
    for (const Case& c :
         {Case{Environment::frozen, 20.0, true}, Case{Environment::frozen, -4.0, true},
          Case{Environment::frozen, -18.0, false}, Case{Environment::refrigerated, -20.0, true},
          Case{Environment::refrigerated, 12.0, true}, Case{Environment::refrigerated, 2.0, false},
          Case{Environment::thawed, -30.0, true}, Case{Environment::thawed, 18.0, false},
          Case{Environment::transitioning, -30.0, false},
          Case{Environment::transitioning, 30.0, false}}) {
      config.env = c.env;
      config.body_temp_c = c.temp_c;
      const Diagnostics d = validate(config);
      if (!c.warned) {
        QVERIFY2(d.empty(), qPrintable(describe(d)));
        continue;
      }
      EXPECT_ONE(d, "/body_temp_c", Severity::warning);
      QVERIFY2(
          d[0].message.find("env '" + std::string(to_string(c.env)) + "'") != std::string::npos,
          d[0].message.c_str());
    }
  }

  void secondsSinceTemperatureChange() {
    PalletConfig config = valid();
    for (double bad : {-1.0, std::numeric_limits<double>::infinity()}) {
      config.seconds_since_temp_change = bad;
      EXPECT_ONE(validate(config), "/seconds_since_temp_change", Severity::error);
      // An open-ended range is a bound, not "[0.00, 1.79769e+308]".
      QVERIFY2(only.message.ends_with("set it to a number >= 0 s"), only.message.c_str());
    }
    config.seconds_since_temp_change = 0.0;
    QVERIFY(validate(config).empty());
  }

  void emptySku() {
    PalletConfig config = valid();
    config.items[1].sku.clear();
    EXPECT_ONE(validate(config), "/items/1/sku", Severity::error);
  }

  void unknownSku() {
    PalletConfig config = valid();
    config.items[1].sku = "SKU-XX-999";
    EXPECT_ONE(validate(config), "/items/1/sku", Severity::warning);
    QVERIFY(contains(only.message, "'SKU-XX-999'"));
    ValidationLimits strict;
    strict.require_known_skus = true;
    EXPECT_ONE(validate(config, strict), "/items/1/sku", Severity::error);
  }

  void customCatalog() {
    const auto catalog = Catalog::from_csv(
        "sku,name,weight_kg,length_m,width_m,height_m,fragility,category,default_env\n"
        "SKU-FD-001,Cheese,25.0,0.40,0.40,0.15,rigid,fresh_dairy,refrigerated\n");
    QVERIFY(catalog.ok());
    QVERIFY(validate(valid(), {}, &*catalog).empty());
    const auto other = Catalog::from_csv(
        "sku,name,weight_kg,length_m,width_m,height_m,fragility,category,default_env\n"
        "SKU-X,X,1.0,0.1,0.1,0.1,rigid,dry_goods,thawed\n");
    QCOMPARE(validate(valid(), {}, &*other).size(), std::size_t{3});
  }

  void itemWeight() {
    PalletConfig config = valid();
    for (double bad : {0.0, 500.5, kNaN}) {
      config.items[1].weight_kg = bad;
      EXPECT_ONE(validate(config), "/items/1/weight_kg", Severity::error);
    }
  }

  void itemDims_data() {
    QTest::addColumn<int>("axis");
    QTest::addColumn<double>("value");
    QTest::newRow("length zero") << 0 << 0.0;
    QTest::newRow("width negative") << 1 << -0.4;
    QTest::newRow("height above 3 m") << 2 << 3.5;
    QTest::newRow("height NaN") << 2 << kNaN;
  }
  void itemDims() {
    QFETCH(int, axis);
    QFETCH(double, value);
    PalletConfig config = valid();
    // Item 0 carries item 2: one bad number still gives one finding, not a floating cascade.
    config.items[0].dims_m[static_cast<std::size_t>(axis)] = value;
    EXPECT_ONE(validate(config), "/items/0/dims_m/" + QString::number(axis), Severity::error);
  }

  void itemPositionMustBeFinite() {
    PalletConfig config = valid();
    config.items[0].position[1] = kNaN;
    EXPECT_ONE(validate(config), "/items/0/position/1", Severity::error);
    // Far off any pallet: a unit slip, refused at the coordinate, not reported as reaching
    // "inf mm" beyond the deck.
    config.items[0].position[1] = 1e308;
    EXPECT_ONE(validate(config), "/items/0/position/1", Severity::error);
    QVERIFY2(contains(only.message, "1e+308 m"), only.message.c_str());
  }

  void itemOrientation() {
    PalletConfig config = valid();
    config.items[1].orientation_deg = 180.5;
    EXPECT_ONE(validate(config), "/items/1/orientation_deg", Severity::error);
    config.items[1].orientation_deg = -180.0;
    QVERIFY(validate(config).empty());
  }

  void weightDiffersFromCatalog() {
    PalletConfig config = valid();
    config.items[1].weight_kg = 25.3;  // 1.2 %
    EXPECT_ONE(validate(config), "/items/1/weight_kg", Severity::warning);
    config.items[1].weight_kg = 25.2;  // 0.8 %
    QVERIFY(validate(config).empty());
  }

  void dimsDifferFromCatalog() {
    PalletConfig config = valid();
    config.items[2].dims_m = {0.42, 0.42, 0.15};
    EXPECT_ONE(validate(config), "/items/2/dims_m", Severity::warning);
    // Length and width swapped describe the same carton.
    Item beef;
    beef.sku = "SKU-FM-001";
    beef.weight_kg = 10.5;
    beef.dims_m = {0.30, 0.40, 0.20};
    beef.position = {0.0, 0.0, 0.15};
    PalletConfig single;
    single.items = {beef};
    QVERIFY(validate(single).empty());
  }

  void itemBelowTheDeck() {
    PalletConfig config = valid();
    config.items[1].position[2] = 0.148;
    EXPECT_ONE(validate(config), "/items/1/position/2", Severity::error);
    QVERIFY(contains(only.message, "raise it to z = 0.150 m"));
    config.items[1].position[2] = 0.1495;  // within the 1 mm tolerance
    QVERIFY(validate(config).empty());
  }

  void interpenetratingItems() {
    PalletConfig config = valid();
    config.items.push_back(cheese(0.48, 0.0, 0.15));  // into item 1 by 121 mm along X
    EXPECT_ONE(validate(config), "/items/3", Severity::error);
    QVERIFY2(contains(only.message, "item 3 (SKU-FD-001) and item 1 (SKU-FD-001)"),
             only.message.c_str());
    QVERIFY2(contains(only.message, "121.0 mm"), only.message.c_str());
  }

  void interpenetrationWithinToleranceIsAllowed() {
    PalletConfig config = valid();
    config.items[1].position[0] = 0.1985;  // 0.5 mm into item 0
    QVERIFY(validate(config).empty());
    config.items[1].position[0] = 0.198;  // exactly 1 mm, a hair more in doubles: allowed
    QVERIFY2(validate(config).empty(), qPrintable(describe(validate(config))));
    config.items[1].position[0] = 0.197;  // 2 mm into item 0
    EXPECT_ONE(validate(config), "/items/1", Severity::error);
    QVERIFY(contains(only.message, "2.0 mm"));
  }

  void interpenetrationIsYawAware() {
    // Two 0.4 m cases turned 45 degrees, diagonal neighbours: their axis-aligned boxes overlap
    // by 28 cm, but the cases themselves are 5 mm apart.
    const double offset = (0.4 + 0.005) / std::sqrt(2.0);
    PalletConfig config;
    config.items = {cheese(-offset / 2, -offset / 2, 0.15, 45.0),
                    cheese(offset / 2, offset / 2, 0.15, 45.0)};
    QVERIFY2(validate(config).empty(), qPrintable(describe(validate(config))));
    const double close = (0.4 - 0.01) / std::sqrt(2.0);
    config.items = {cheese(-close / 2, -close / 2, 0.15, 45.0),
                    cheese(close / 2, close / 2, 0.15, 45.0)};
    EXPECT_ONE(validate(config), "/items/1", Severity::error);
    QVERIFY2(contains(only.message, "10.0 mm"), only.message.c_str());
  }

  void eachPairIsReportedOnce() {
    PalletConfig config = valid();
    config.items.push_back(cheese(0.201, 0.0, 0.15));  // exactly where item 1 is
    config.items.push_back(cheese(0.201, 0.0, 0.15));  // and again
    const Diagnostics found = validate(config);
    QCOMPARE(found.size(), std::size_t{3});  // (1, 3), (1, 4), (3, 4)
    QCOMPARE(found[0].pointer, std::string("/items/3"));
    QCOMPARE(found[1].pointer, std::string("/items/4"));
    QCOMPARE(found[2].pointer, std::string("/items/4"));
    QVERIFY(contains(found[1].message, "and item 1 "));
    QVERIFY(contains(found[2].message, "and item 3 "));
  }

  void floatingItem() {
    PalletConfig config = valid();
    config.items[2].position[2] = 0.32;
    EXPECT_ONE(validate(config), "/items/2/position/2", Severity::error);
    QVERIFY2(contains(only.message, "lower it to z = 0.300 m"), only.message.c_str());
    config.items[2].position[2] = 0.3008;  // within the 1 mm tolerance
    QVERIFY(validate(config).empty());
    config.items[2].position[2] = 0.301;  // exactly 1 mm, a hair more in doubles: allowed
    QVERIFY2(validate(config).empty(), qPrintable(describe(validate(config))));
    config.items[2].position[2] = 0.3011;
    EXPECT_ONE(validate(config), "/items/2/position/2", Severity::error);
    QVERIFY2(contains(only.message, "floats 1.1 mm"), only.message.c_str());
  }

  void floatingOverTheDeck() {
    PalletConfig config = valid();
    for (Item& item : config.items) item.position[1] = -0.2;
    config.items.push_back(cheese(0.0, 0.201, 0.2));  // 1 mm beside them, over the bare deck
    EXPECT_ONE(validate(config), "/items/3/position/2", Severity::error);
    QVERIFY2(contains(only.message, "lower it to z = 0.150 m"), only.message.c_str());
  }

  void lowSupport() {
    PalletConfig config = valid();
    config.items[2].position[0] = -0.461;  // 0.14 of its 0.40 m over item 0
    // Its centre of mass is 6 cm beyond item 0's end: it cannot stand (an error, not the warning).
    EXPECT_ONE(validate(config), "/items/2/position", Severity::error);
    QVERIFY2(contains(only.message, "cannot stand: its centre of mass is 60 mm outside"),
             only.message.c_str());
    // Without the standing rule only the low support is left: a warning.
    ValidationLimits no_standing;
    no_standing.check_standing = false;
    EXPECT_ONE(validate(config, no_standing), "/items/2", Severity::warning);
    QVERIFY2(contains(only.message, "35 %"), only.message.c_str());
    ValidationLimits lenient = no_standing;
    lenient.low_support_warning = 0.3;
    QVERIFY(validate(config, lenient).empty());
  }

  // An item thinner than twice the margin cannot stand on that side anywhere: it is told to lie
  // flat, not to be re-stacked centred (an 18 mm board, centred on the deck, was).
  void aBoardOnItsEdgeIsToldToLieFlat() {
    PalletConfig config;
    Item board = cheese(0.0, 0.0, 0.15);
    board.dims_m = {0.018, 1.0, 0.6};
    board.weight_kg = 8.0;
    config.items = {board};
    const Diagnostics errors = errors_of(validate(config));
    QCOMPARE(errors.size(), std::size_t{1});
    QCOMPARE(errors[0].pointer, std::string("/items/0/position"));
    QVERIFY2(contains(errors[0].message, "18 mm thick") &&
                 contains(errors[0].message, "lay it flat") &&
                 !contains(errors[0].message, "re-stack"),
             errors[0].message.c_str());
    config.items[0].dims_m = {1.0, 0.6, 0.018};  // flat: stands
    QVERIFY(!has_errors(validate(config)));
  }

  void overhang() {
    PalletConfig config = valid();
    config.items[1].position[0] = 0.52;  // reaches 0.72 m: 12 cm over the 0.60 m edge
    EXPECT_ONE(validate(config), "/items/1/position", Severity::error);
    QVERIFY2(contains(only.message, "120 mm"), only.message.c_str());
    config.items[1].position[0] = 0.49;  // 9 cm
    QVERIFY(validate(config).empty());
  }

  void overhangIsYawAware() {
    PalletConfig config = valid();
    config.items[1].position[0] = 0.45;  // 5 cm over; turned 45 degrees, 13.3 cm
    QVERIFY(validate(config).empty());
    config.items[1].orientation_deg = 45.0;
    EXPECT_ONE(validate(config), "/items/1/position", Severity::error);
  }

  void everyOverhangingItemIsReported() {
    PalletConfig config = valid();
    config.items[0].position[1] = -0.31;
    config.items[2].position[1] = -0.31;
    const Diagnostics found = validate(config);
    QCOMPARE(found.size(), std::size_t{2});
    QCOMPARE(found[0].pointer, std::string("/items/0/position"));
    QCOMPARE(found[1].pointer, std::string("/items/2/position"));
  }

  // An item denser than lead or lighter than 1 kg/m^3 is a unit slip: an error at its weight that
  // names the density and what to check. A dairy case (10 kg, 12 litres) is fine.
  void impossibleDensityIsRefused() {
    PalletConfig config = valid();
    QVERIFY(!has_errors(validate(config)));
    config.items[0].weight_kg = 400.0;
    Diagnostics errors = errors_of(validate(config));
    QVERIFY(!errors.empty());
    QCOMPARE(errors[0].pointer, std::string("/items/0/weight_kg"));
    QVERIFY2(contains(errors[0].message, "denser than lead"), errors[0].message.c_str());
    config.items[0].weight_kg = 1e-6;
    errors = errors_of(validate(config));
    QVERIFY(!errors.empty());
    QVERIFY2(contains(errors[0].message, "lighter than air"), errors[0].message.c_str());
  }

  // A base far lighter than its load is beyond what the simulation holds (refused at
  // /base_mass_kg); merely light for its type, a warning.
  void baseTooLightForItsLoad() {
    PalletConfig config = valid();
    const double heaviest =
        std::max_element(config.items.begin(), config.items.end(),
                         [](const Item& a, const Item& b) { return a.weight_kg < b.weight_kg; })
            ->weight_kg;
    config.base_mass_kg = heaviest / 150.0;
    Diagnostics errors = errors_of(validate(config));
    QCOMPARE(errors.size(), std::size_t{1});
    QCOMPARE(errors[0].pointer, std::string("/base_mass_kg"));
    QVERIFY2(contains(errors[0].message, "150 times as heavy"), errors[0].message.c_str());
    QVERIFY2(contains(errors[0].message, "weighs about 25 kg"), errors[0].message.c_str());
    config.base_mass_kg = 5.0;
    const Diagnostics light = validate(config);
    QVERIFY(!has_errors(light));
    QVERIFY(std::any_of(light.begin(), light.end(), [](const Diagnostic& d) {
      return d.pointer == "/base_mass_kg" && d.severity == Severity::warning;
    }));
    config.base_mass_kg = 25.0;
    for (const Diagnostic& d : validate(config)) QVERIFY(d.pointer != "/base_mass_kg");
  }

  // An item carrying one more than 100 times its weight is refused at its weight (a 0.5 kg plate
  // under a 500 kg block answered a start-up limit of 0.9 m/s^2 where the pallet slips at 4.7);
  // at 100 times, or a light item on a heavy one, it is not.
  void anItemCarryingFarMoreThanItsWeight() {
    PalletConfig config = valid();  // item 2 (25 kg) rests on item 0
    config.items[0].weight_kg = 0.2;
    Diagnostics errors = errors_of(validate(config));
    QCOMPARE(errors.size(), std::size_t{1});
    QCOMPARE(errors[0].pointer, std::string("/items/0/weight_kg"));
    QVERIFY2(contains(errors[0].message, "carries item 2"), errors[0].message.c_str());
    QVERIFY2(contains(errors[0].message, "125 times as heavy"), errors[0].message.c_str());
    config.items[0].weight_kg = 0.25;
    QVERIFY(!has_errors(validate(config)));
    config.items[0].weight_kg = 25.0;
    config.items[2].weight_kg = 0.2;
    QVERIFY(!has_errors(validate(config)));
  }

  void grossMassAboveTheCap() {
    PalletConfig config = valid();
    for (Item& item : config.items) item.weight_kg = 400.0;  // 1225 kg with the base
    ValidationLimits limits;
    limits.max_density_kg_m3 =
        1e9;  // 400 kg in these boxes is denser than lead: the mass cap alone
    const Diagnostics errors = errors_of(validate(config, limits));
    QCOMPARE(errors.size(), std::size_t{1});
    QCOMPARE(errors[0].pointer, std::string("/items"));
    QVERIFY2(contains(errors[0].message, "1225.0 kg, above the 1200.0 kg"),
             errors[0].message.c_str());
  }

  void grossMassCapFollowsThePalletRating() {
    PalletConfig config = valid();
    config.base_pallet_type = PalletType::chep;  // 1250 kg + 20 kg tare
    for (Item& item : config.items) item.weight_kg = 400.0;
    ValidationLimits limits;
    limits.max_gross_mass_kg = 5000.0;
    limits.max_density_kg_m3 = 1e9;  // the rating alone (these boxes are too small for 400 kg)
    QVERIFY(!has_errors(validate(config, limits)));  // 1225 kg
    config.items[0].weight_kg = 450.0;               // 1275 kg
    const Diagnostics errors = errors_of(validate(config, limits));
    QCOMPARE(errors.size(), std::size_t{1});
    QCOMPARE(errors[0].pointer, std::string("/items"));
    QVERIFY(contains(errors[0].message, "1270.0 kg"));
  }

  void stackHeightReportsTheHighestItem() {
    PalletConfig config = valid();
    ValidationLimits limits;
    limits.max_stack_height_m = 0.40;  // the load's top is 0.45 m (item 2)
    EXPECT_ONE(validate(config, limits), "/items/2", Severity::error);
    QVERIFY(contains(only.message, "0.450 m"));
    // The highest item listed first.
    config.items = {cheese(-0.201, 0.0, 0.30), cheese(0.201, 0.0, 0.15), cheese(-0.201, 0.0, 0.15)};
    EXPECT_ONE(validate(config, limits), "/items/0", Severity::error);
  }

  void defaultStackHeightLimit() {
    PalletConfig config;
    config.pallet_id = "tower";
    for (int level = 0; level < 12; ++level)
      config.items.push_back(cheese(0, 0, 0.15 + 0.15 * level));
    EXPECT_ONE(validate(config), "/items/11", Severity::error);  // top at 1.95 m > 1.85 m
    config.items.pop_back();
    QVERIFY(validate(config).empty());  // 1.80 m
    // A column so tall its top cartons' positions are out of range: the height is its real top,
    // not the top of the last carton whose position was in range.
    config.items.clear();
    for (int level = 0; level < 80; ++level)
      config.items.push_back(cheese(0, 0, 0.15 + 0.15 * level));
    const Diagnostics errors = errors_of(validate(config));
    const auto height = std::find_if(errors.begin(), errors.end(), [](const Diagnostic& d) {
      return contains(d.message, "m high");
    });
    QVERIFY(height != errors.end());
    QCOMPARE(height->pointer, std::string("/items/79"));
    QVERIFY2(contains(height->message, "12.150 m high"), height->message.c_str());
  }

  void findingsComeInDocumentOrder() {
    PalletConfig config = valid();
    config.pallet_id.clear();
    config.body_temp_c = 50.0;
    config.items[1].weight_kg = -1.0;
    const Diagnostics found = validate(config);
    QStringList pointers;
    for (const auto& d : found) pointers << QString::fromStdString(d.pointer);
    QCOMPARE(pointers, (QStringList{"/pallet_id", "/body_temp_c", "/items/1/weight_kg"}));
  }

  // Too many items is refused first, with one error naming the limit (no pair checks: 20,000
  // items would otherwise keep the quadratic checks busy for minutes).
  void tooManyItemsIsRefusedFirst() {
    PalletConfig config;
    config.items.assign(20000, test::carton(0, 0, 0.15));
    const Diagnostics d = validate(config);
    QCOMPARE(d.size(), std::size_t{1});
    QCOMPARE(d[0].pointer, std::string("/items"));
    QCOMPARE(d[0].severity, Severity::error);
    QVERIFY(d[0].message.find("400") != std::string::npos);
    QVERIFY(!has_errors(validate(test::pallet({test::carton(0, 0, 0.15)}))));
  }

  // A curve turns the pallet about its centre: a radius no wider than the pallet's half-width
  // across the belt (0.4 m for an EUR pallet; an overhanging carton's reach where it is wider)
  // would turn it about a point under it, and is refused with the least radius it takes.
  void aCurveRadiusMustClearThePallet() {
    const PalletConfig eur = test::pallet({test::carton(0.0, 0.0, 0.15)});
    QVERIFY(validate_curve_radius(eur, 0.41, "/line/curve_radius_m").empty());
    const Diagnostics tight = validate_curve_radius(eur, 0.4, "/line/curve_radius_m");
    QCOMPARE(tight.size(), std::size_t{1});
    QCOMPARE(tight[0].pointer, std::string("/line/curve_radius_m"));
    QVERIFY(has_errors(tight));
    QVERIFY2(tight[0].message.find("more than 0.4 m") != std::string::npos,
             tight[0].message.c_str());
    // A 0.3 m wide carton centred 0.3 m off the centre line reaches 0.45 m.
    const PalletConfig over = test::pallet({test::carton(0.0, -0.3, 0.15)});
    const Diagnostics wide = validate_curve_radius(over, 0.42, "/profile/curve_radius_m");
    QCOMPARE(wide.size(), std::size_t{1});
    QVERIFY2(wide[0].message.find("more than 0.45 m") != std::string::npos,
             wide[0].message.c_str());
  }
};

QTEST_APPLESS_MAIN(ValidationTest)
#include "validation_test.moc"
