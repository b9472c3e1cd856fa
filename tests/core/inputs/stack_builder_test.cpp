// SPDX-License-Identifier: MIT
#include "core/inputs/stack_builder.hpp"

#include <QtTest>
#include <set>

#include "core/contract/pallet_metrics.hpp"
#include "core/inputs/validation.hpp"

namespace {

const pb::Catalog& catalog() {
  return pb::Catalog::builtin();
}

// The six stacks of the reference's two frozen-meat scenarios.
std::vector<pb::StackSpec> frozen_meat_stacks() {
  std::vector<pb::StackSpec> stacks;
  for (int row = 0; row < 2; ++row) {
    for (int col = 0; col < 3; ++col) stacks.push_back({"SKU-FM-001", row, col, 4});
  }
  return stacks;
}

// The built pallet; a refusal is printed and yields a pallet without an id, which the callers'
// checks then fail on.
pb::PalletConfig build(const std::vector<pb::StackSpec>& stacks,
                       const pb::StackBuildOptions& options = {}) {
  auto result = pb::build_from_stacks(stacks, options, catalog());
  if (!result) {
    for (const auto& d : result.diagnostics) qWarning("%s", pb::to_string(d).c_str());
    pb::PalletConfig refused;
    refused.pallet_id.clear();
    return refused;
  }
  return *result;
}

pb::Diagnostics errors(const std::vector<pb::StackSpec>& stacks,
                       const pb::StackBuildOptions& options = {}) {
  auto result = pb::build_from_stacks(stacks, options, catalog());
  if (result.ok()) return {};
  return result.diagnostics;
}

void verify_valid(const pb::PalletConfig& config) {
  QVERIFY(!config.pallet_id.empty());
  const auto diags = pb::validate(config);
  for (const auto& d : diags) {
    if (d.severity == pb::Severity::error) qWarning("%s", pb::to_string(d).c_str());
  }
  QVERIFY(!pb::has_errors(diags));
}

double items_mass(const pb::PalletConfig& config) {
  return pb::total_mass_kg(config) - config.base_mass_kg;
}

}  // namespace

class StackBuilderTest : public QObject {
  Q_OBJECT

 private slots:
  void gridForDividesWithoutLosingAColumn() {
    const pb::Vec3 eur{1.2, 0.8, 0.15};
    QCOMPARE(pb::grid_for(frozen_meat_stacks(), eur, catalog()), (pb::GridShape{2, 3}));
    // 0.8 / 0.4 and 1.2 / 0.4 are both a hair under a whole number in binary.
    const std::vector<pb::StackSpec> cheese{{"SKU-FD-001", 0, 0, 1}};
    QCOMPARE(pb::grid_for(cheese, eur, catalog()), (pb::GridShape{2, 3}));
    // The largest length and the largest width may come from different SKUs.
    const std::vector<pb::StackSpec> mixed{{"SKU-FS-003", 0, 0, 1}, {"SKU-FD-001", 0, 1, 1}};
    QCOMPARE(pb::grid_for(mixed, eur, catalog()), (pb::GridShape{2, 2}));
  }

  void gridForDefaultsAndAtLeastOne() {
    const pb::Vec3 eur{1.2, 0.8, 0.15};
    QCOMPARE(pb::grid_for({}, eur, catalog()), (pb::GridShape{2, 3}));
    const std::vector<pb::StackSpec> unknown{{"NOPE", 0, 0, 1}};
    QCOMPARE(pb::grid_for(unknown, eur, catalog()), (pb::GridShape{2, 3}));
    const std::vector<pb::StackSpec> milk{{"SKU-FD-004", 0, 0, 1}};
    QCOMPARE(pb::grid_for(milk, pb::Vec3{0.3, 0.2, 0.15}, catalog()), (pb::GridShape{1, 1}));
  }

  void frozenMeatPlacesAllTwentyFourCartons() {
    const auto config = build(frozen_meat_stacks());
    QCOMPARE(config.items.size(), std::size_t{24});
    QCOMPARE(items_mass(config), 24 * 10.5);
    QCOMPARE(items_mass(config), 252.0);
    std::set<double> xs, ys, zs;
    for (const auto& item : config.items) {
      xs.insert(item.position[0]);
      ys.insert(item.position[1]);
      zs.insert(item.position[2]);
    }
    QCOMPARE(xs.size(), std::size_t{3});
    QCOMPARE(ys.size(), std::size_t{2});
    QCOMPARE(zs.size(), std::size_t{4});
    QCOMPARE(pb::overhang_m(config), 0.0);
    verify_valid(config);
  }

  void cellCentreFormulaIsExact() {
    const auto config = build(frozen_meat_stacks());
    // Stack 5 is row 1, col 2; its cartons are items 20..23, bottom to top.
    for (std::size_t k = 0; k < 4; ++k) {
      const pb::Item& item = config.items[20 + k];
      QVERIFY(item.position[0] == -1.2 / 2.0 + (2 + 0.5) * (1.2 / 3));
      QVERIFY(item.position[1] == -0.8 / 2.0 + (1 + 0.5) * (0.8 / 2));
      QCOMPARE(item.orientation_deg, 0.0);
    }
    QVERIFY(config.items[20].position[2] == 0.15);
    QVERIFY(config.items[21].position[2] == 0.15 + 0.2);
    QVERIFY(config.items[23].position[2] == 0.15 + 0.2 + 0.2 + 0.2);
    QCOMPARE(config.items[0].position, (pb::Vec3{-0.4, -0.2, 0.15}));
  }

  void itemsCarryTheCatalogEntry() {
    const auto config = build({{"SKU-FD-002", 0, 1, 1}});
    const pb::Item& item = config.items.front();
    QCOMPARE(item.sku, std::string("SKU-FD-002"));
    QCOMPARE(item.weight_kg, 6.0);
    QCOMPARE(item.dims_m, (pb::Vec3{0.35, 0.25, 0.12}));
    QCOMPARE(item.fragility, pb::Fragility::rigid);
  }

  void optionsReachThePallet() {
    pb::StackBuildOptions options;
    options.pallet_id = "frozen-meat-sprint";
    options.base_pallet_type = pb::PalletType::gma;
    options.wrap = pb::WrapType::none;
    options.env = pb::Environment::frozen;
    options.body_temp_c = -25.0;
    options.seconds_since_temp_change = 120.0;
    options.belt_surface = pb::BeltSurface::steel_roller;
    const auto config = build(frozen_meat_stacks(), options);
    QCOMPARE(config.pallet_id, std::string("frozen-meat-sprint"));
    QCOMPARE(config.base_pallet_type, pb::PalletType::gma);
    QCOMPARE(config.base_dims_m, (pb::Vec3{1.219, 1.016, 0.14}));
    QCOMPARE(config.base_mass_kg, 17.0);
    QCOMPARE(config.wrap, pb::WrapType::none);
    QCOMPARE(config.env, pb::Environment::frozen);
    QCOMPARE(config.body_temp_c, -25.0);
    QCOMPARE(config.seconds_since_temp_change, 120.0);
    QCOMPARE(config.belt_surface, pb::BeltSurface::steel_roller);
    QVERIFY(config.items.front().position[2] == 0.14);
    options.base_dims_m = pb::Vec3{1.2, 0.8, 0.12};
    options.base_mass_kg = 22.0;
    const auto custom = build(frozen_meat_stacks(), options);
    QCOMPARE(custom.base_dims_m, (pb::Vec3{1.2, 0.8, 0.12}));
    QCOMPARE(custom.base_mass_kg, 22.0);
  }

  void curatedScenariosBuildAndValidate() {
    // The reference's seed scenarios (reference/data/seed_scenarios.json).
    const auto slab = build({{"SKU-FD-001", 0, 0, 2},
                             {"SKU-FD-001", 0, 1, 2},
                             {"SKU-FD-001", 1, 0, 2},
                             {"SKU-FD-001", 1, 1, 2}});
    QCOMPARE(slab.items.size(), std::size_t{8});
    QCOMPARE(items_mass(slab), 200.0);
    verify_valid(slab);

    const auto tower = build({{"SKU-FD-002", 0, 1, 8}});
    QCOMPARE(tower.items.size(), std::size_t{8});
    QVERIFY(tower.items.back().position[0] == -0.6 + 1.5 * (1.2 / 3));
    QVERIFY(tower.items.back().position[1] == -0.4 + 0.5 * (0.8 / 3));
    QCOMPARE(pb::stack_height_m(tower), 0.15 + 8 * 0.12);
    verify_valid(tower);

    const auto top_heavy = build({{"SKU-MS-003", 0, 1, 6}});
    QCOMPARE(top_heavy.items.size(), std::size_t{6});
    QVERIFY(top_heavy.items.front().position[0] == -0.6 + 1.5 * (1.2 / 2));
    QVERIFY(top_heavy.items.front().position[1] == 0.0);
    verify_valid(top_heavy);

    const auto asymmetric = build({{"SKU-FD-001", 0, 0, 1}, {"SKU-MS-003", 0, 1, 5}});
    QCOMPARE(asymmetric.items.size(), std::size_t{6});
    QCOMPARE(items_mass(asymmetric), 25.0 + 5 * 35.0);
    verify_valid(asymmetric);
  }

  void stacksNamingOneCellStandOnEachOther() {
    const auto config = build({{"SKU-FD-001", 0, 0, 1},
                               {"SKU-FD-002", 0, 0, 2},
                               {"SKU-FD-001", 1, 2, 1},
                               {"SKU-FD-001", 0, 0, 1}});
    QCOMPARE(config.items.size(), std::size_t{5});
    QVERIFY(config.items[0].position[2] == 0.15);
    QVERIFY(config.items[1].position[2] == 0.15 + 0.15);
    QVERIFY(config.items[2].position[2] == 0.15 + 0.15 + 0.12);
    QVERIFY(config.items[3].position[2] == 0.15);  // another cell starts at the deck
    QVERIFY(config.items[4].position[2] == 0.15 + 0.15 + 0.12 + 0.12);
    for (std::size_t i : {1u, 2u, 4u}) {
      QCOMPARE(config.items[i].position[0], config.items[0].position[0]);
      QCOMPARE(config.items[i].position[1], config.items[0].position[1]);
    }
    verify_valid(config);
  }

  void emptyStacksGiveAnEmptyPallet() {
    const auto config = build({});
    QVERIFY(config.items.empty());
    verify_valid(config);
  }

  void unknownSkuPointsAtTheStack() {
    const auto d = errors({{"SKU-FM-001", 0, 0, 1}, {"SKU-XX-999", 0, 1, 1}});
    QCOMPARE(d.size(), std::size_t{1});
    QCOMPARE(d[0].pointer, std::string("/stacks/1/sku"));
    QCOMPARE(d[0].message, std::string("unknown SKU 'SKU-XX-999'; use a SKU from the catalog "
                                       "(palletballet-cli catalog)"));
  }

  void cellOutsideTheGridSaysWhy() {
    const auto d =
        errors({{"SKU-FM-001", 0, 3, 1}, {"SKU-FM-001", 2, 0, 1}, {"SKU-FM-001", -1, -1, 1}});
    QCOMPARE(d.size(), std::size_t{4});
    QCOMPARE(d[0].pointer, std::string("/stacks/0/col"));
    QCOMPARE(d[0].message, std::string("col 3 is outside the 3-column grid sized for SKU-FM-001 "
                                       "(0.40 m long) on a 1.20 m deck; use col 0..2"));
    QCOMPARE(d[1].pointer, std::string("/stacks/1/row"));
    QCOMPARE(d[1].message, std::string("row 2 is outside the 2-row grid sized for SKU-FM-001 "
                                       "(0.30 m wide) on a 0.80 m deck; use row 0..1"));
    QCOMPARE(d[2].pointer, std::string("/stacks/2/row"));
    QCOMPARE(d[3].pointer, std::string("/stacks/2/col"));
  }

  void cellOutsideAnExplicitGrid() {
    pb::StackBuildOptions options;
    options.grid = pb::GridShape{1, 2};
    const auto d = errors({{"SKU-FM-001", 0, 2, 1}}, options);
    QCOMPARE(d.size(), std::size_t{1});
    QCOMPARE(d[0].pointer, std::string("/stacks/0/col"));
    QCOMPARE(d[0].message,
             std::string("col 2 is outside the 2-column grid set in /grid; use col 0..1"));
  }

  void heightOutOfRange() {
    const auto d =
        errors({{"SKU-FM-001", 0, 0, 0}, {"SKU-FM-001", 0, 1, 51}, {"SKU-FV-003", 0, 2, 50}});
    QCOMPARE(d.size(), std::size_t{2});
    QCOMPARE(d[0].pointer, std::string("/stacks/0/height"));
    QCOMPARE(d[0].message, std::string("height 0 is not a number of cartons; use 1..50"));
    QCOMPARE(d[1].pointer, std::string("/stacks/1/height"));
  }

  void everyErrorIsCollected() {
    const auto d = errors({{"NOPE", 5, 0, 0}, {"SKU-FM-001", 0, 9, 1}});
    QCOMPARE(d.size(), std::size_t{4});
    QCOMPARE(d[0].pointer, std::string("/stacks/0/sku"));
    QCOMPARE(d[1].pointer, std::string("/stacks/0/row"));
    QCOMPARE(d[2].pointer, std::string("/stacks/0/height"));
    QCOMPARE(d[3].pointer, std::string("/stacks/1/col"));
  }

  void explicitGridNeedsPositiveCounts() {
    pb::StackBuildOptions options;
    options.grid = pb::GridShape{0, -1};
    const auto d = errors({{"SKU-FM-001", 0, 0, 1}}, options);
    QCOMPARE(d.size(), std::size_t{2});
    QCOMPARE(d[0].pointer, std::string("/grid/rows"));
    QCOMPARE(d[0].message, std::string("the grid has 0 rows; give at least 1 row"));
    QCOMPARE(d[1].pointer, std::string("/grid/cols"));
  }

  void explicitGridCellsMustHoldTheItems() {
    pb::StackBuildOptions options;
    options.grid = pb::GridShape{3, 4};
    const auto d = errors({{"SKU-FM-001", 0, 0, 1}}, options);
    QCOMPARE(d.size(), std::size_t{2});
    QCOMPARE(d[0].pointer, std::string("/grid"));
    QCOMPARE(d[0].message,
             std::string("the 4-column grid makes cells 0.30 m long but SKU-FM-001 is 0.40 m "
                         "long, so neighbouring stacks would interpenetrate; use at most 3 "
                         "columns"));
    QCOMPARE(d[1].pointer, std::string("/grid"));
    QVERIFY(d[1].message.find("use at most 2 rows") != std::string::npos);
  }

  void explicitGridWithLargerCellsIsKept() {
    pb::StackBuildOptions options;
    options.grid = pb::GridShape{1, 2};
    const auto config = build({{"SKU-FM-001", 0, 0, 1}, {"SKU-FM-001", 0, 1, 1}}, options);
    QCOMPARE(config.items[0].position, (pb::Vec3{-0.6 + 0.5 * 0.6, 0.0, 0.15}));
    QCOMPARE(config.items[1].position, (pb::Vec3{-0.6 + 1.5 * 0.6, 0.0, 0.15}));
    verify_valid(config);
  }

  void physicalRulesPointAtTheStack() {
    // Six milk crates (0.30 m) reach 1.95 m, above the 1.85 m limit.
    const auto d = errors({{"SKU-FD-001", 0, 0, 1}, {"SKU-FD-004", 0, 1, 6}});
    QCOMPARE(d.size(), std::size_t{1});
    QCOMPARE(d[0].pointer, std::string("/stacks/1"));
    QVERIFY2(d[0].message.rfind("carton 5 (from the bottom, 0 first) of this stack: the load is "
                                "1.950 m high",
                                0) == 0,
             d[0].message.c_str());
  }

  void grossMassCapIsAnError() {
    std::vector<pb::StackSpec> stacks;
    for (int row = 0; row < 2; ++row) {
      for (int col = 0; col < 3; ++col) stacks.push_back({"SKU-FD-001", row, col, 9});
    }
    const auto d = errors(stacks);
    QCOMPARE(d.size(), std::size_t{1});
    QCOMPARE(d[0].pointer, std::string("/items"));
  }
};

QTEST_APPLESS_MAIN(StackBuilderTest)
#include "stack_builder_test.moc"
