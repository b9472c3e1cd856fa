// SPDX-License-Identifier: MIT
#include "core/inputs/layer_layout.hpp"

#include <QtTest>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>

#include "core/base/rng.hpp"
#include "core/contract/pallet_metrics.hpp"
#include "core/inputs/static_stability.hpp"

namespace {

const pb::Catalog& catalog() {
  return pb::Catalog::builtin();
}

pb::ScannerInputs inputs(pb::LayerPattern pattern, int items_per_layer, int layers,
                         std::vector<std::string> skus) {
  pb::ScannerInputs in;
  in.pattern = pattern;
  in.items_per_layer = items_per_layer;
  in.layers = layers;
  in.skus = std::move(skus);
  return in;
}

// The built pallet; a refusal is printed and yields an empty pallet, which the callers' checks
// then fail on.
pb::PalletConfig build(const pb::ScannerInputs& in, const pb::ValidationLimits& limits = {}) {
  auto result = pb::build_from_scanner(in, catalog(), limits);
  if (!result) {
    for (const auto& d : result.diagnostics) qWarning("%s", pb::to_string(d).c_str());
    return {};
  }
  return *result;
}

pb::Diagnostics failure(const pb::ScannerInputs& in, const pb::ValidationLimits& limits = {}) {
  auto result = pb::build_from_scanner(in, catalog(), limits);
  return result.ok() ? pb::Diagnostics{} : result.diagnostics;
}

// Every item rests exactly where it would come to rest: on the highest top among the earlier
// items it overlaps (more than 1 mm^2), else on the deck.
bool rests_where_it_falls(const pb::PalletConfig& config) {
  for (std::size_t i = 0; i < config.items.size(); ++i) {
    double rest = config.base_dims_m[2];
    for (std::size_t j = 0; j < i; ++j) {
      if (pb::footprint_overlap_area(config.items[i], config.items[j]) > 1e-6) {
        rest = std::max(rest, config.items[j].top_z());
      }
    }
    if (config.items[i].position[2] != rest) return false;
  }
  return true;
}

void verify_valid(const pb::PalletConfig& config, const pb::ValidationLimits& limits = {}) {
  QVERIFY(!config.items.empty());
  const auto diags = pb::validate(config, limits);
  for (const auto& d : pb::errors_of(diags)) qWarning("%s", pb::to_string(d).c_str());
  QVERIFY(!pb::has_errors(diags));
  QVERIFY(rests_where_it_falls(config));
  QVERIFY(pb::overhang_m(config) <= limits.max_overhang_m);
}

std::vector<double> distinct(const pb::PalletConfig& config, std::size_t axis, std::size_t first,
                             std::size_t count) {
  std::set<double> values;
  for (std::size_t i = first; i < first + count; ++i) values.insert(config.items[i].position[axis]);
  return {values.begin(), values.end()};
}

}  // namespace

class LayerLayoutTest : public QObject {
  Q_OBJECT

 private slots:
  void columnStacksTheSamePositions() {
    const auto config = build(inputs(pb::LayerPattern::column, 6, 4, {"SKU-FM-001"}));
    QCOMPARE(config.items.size(), std::size_t{24});
    QCOMPARE(config.base_dims_m, (pb::Vec3{1.2, 0.8, 0.15}));
    QCOMPARE(config.base_mass_kg, 25.0);
    // 3 x 2 cells of 0.40 x 0.30 m at yaw 0, filled row-major from -X, -Y.
    const std::vector<double> xs{-0.4, 0.0, 0.4};
    const std::vector<double> ys{-0.15, 0.15};
    for (std::size_t l = 0; l < 4; ++l) {
      for (std::size_t k = 0; k < 6; ++k) {
        const pb::Item& item = config.items[l * 6 + k];
        QVERIFY(std::abs(item.position[0] - xs[k % 3]) < 1e-12);
        QVERIFY(std::abs(item.position[1] - ys[k / 3]) < 1e-12);
        QCOMPARE(item.position[2], config.items[k].position[2] + 0.2 * static_cast<double>(l));
        QCOMPARE(item.position[0], config.items[k].position[0]);
        QCOMPARE(item.orientation_deg, 0.0);
      }
    }
    QCOMPARE(pb::stack_height_m(config), 0.15 + 4 * 0.2);
    verify_valid(config);
  }

  void columnTurnsTheLayerWhenThatFitsBetter() {
    // Eight 0.40 x 0.30 m cartons fill the EUR deck exactly at yaw 90 (4 x 2 of 0.30 x 0.40).
    const auto config = build(inputs(pb::LayerPattern::column, 8, 2, {"SKU-FM-001"}));
    for (const auto& item : config.items) QCOMPARE(item.orientation_deg, 90.0);
    QCOMPARE(distinct(config, 0, 0, 8).size(), std::size_t{4});
    QCOMPARE(distinct(config, 1, 0, 8).size(), std::size_t{2});
    QVERIFY(pb::overhang_m(config) < 1e-12);
    verify_valid(config);
  }

  void exactFitsValidateWithoutOverhang() {
    // No overhang allowed (1 nm: a carton that fills the deck reaches past its edge by one ulp).
    pb::ValidationLimits strict;
    strict.max_overhang_m = 1e-9;
    for (const auto pattern : {pb::LayerPattern::column, pb::LayerPattern::brick,
                               pb::LayerPattern::pinwheel, pb::LayerPattern::irregular}) {
      for (int ti = 1; ti <= 6; ++ti) {
        verify_valid(build(inputs(pattern, ti, 3, {"SKU-FM-001"}), strict), strict);
      }
    }
    verify_valid(build(inputs(pb::LayerPattern::column, 8, 3, {"SKU-FM-001"}), strict), strict);
  }

  void overhangOnlyWhenNothingFitsOnTheDeck() {
    // Nine 0.40 x 0.30 m cartons: 3 x 3 at yaw 0 is 0.90 m wide, 5 cm beyond each long edge.
    const auto config = build(inputs(pb::LayerPattern::column, 9, 1, {"SKU-FM-001"}));
    QVERIFY(std::abs(pb::overhang_m(config) - 0.05) < 1e-12);
    verify_valid(config);
  }

  void brickShiftsAlternateLayersByAQuarterCell() {
    // Four cartons: a 2 x 2 grid of 0.80 x 0.60 m leaves room for the full quarter-cell offset,
    // split -0.05 / +0.05; every end carton keeps three quarters of its length on the layer below.
    const auto config = build(inputs(pb::LayerPattern::brick, 4, 3, {"SKU-FM-001"}));
    for (std::size_t k = 0; k < 4; ++k) {
      QVERIFY(std::abs(config.items[k].position[0] - ((k % 2 == 0 ? -0.2 : 0.2) - 0.05)) < 1e-12);
      QVERIFY(std::abs(config.items[4 + k].position[0] - ((k % 2 == 0 ? -0.2 : 0.2) + 0.05)) <
              1e-12);
      QCOMPARE(config.items[8 + k].position[0], config.items[k].position[0]);
      QCOMPARE(config.items[4 + k].position[1], config.items[k].position[1]);
    }
    QCOMPARE(pb::overhang_m(config), 0.0);
    verify_valid(config);
    QVERIFY(pb::stands(config, 0.09));  // the end cartons: 0.3 of 0.4 m over the layer below
  }

  void brickShiftIsLimitedByTheOverhangLimit() {
    // Six cartons fill the 1.20 m deck length: a quarter cell (0.1 m) fits the 10 cm limit; a
    // 2 cm limit allows 4 cm.
    const auto config = build(inputs(pb::LayerPattern::brick, 6, 4, {"SKU-FM-001"}));
    const double offset = config.items[6].position[0] - config.items[0].position[0];
    QVERIFY(std::abs(offset - 0.1) < 1e-5);
    QVERIFY(std::abs(pb::overhang_m(config) - 0.05) < 1e-5);
    verify_valid(config);

    pb::ValidationLimits strict;
    strict.max_overhang_m = 0.02;
    const auto tight = build(inputs(pb::LayerPattern::brick, 6, 4, {"SKU-FM-001"}), strict);
    QVERIFY(std::abs(tight.items[6].position[0] - tight.items[0].position[0] - 0.04) < 1e-5);
    verify_valid(tight, strict);
  }

  void pinwheelTurnsOddLayers() {
    const auto config = build(inputs(pb::LayerPattern::pinwheel, 6, 4, {"SKU-FM-001"}));
    for (std::size_t i = 0; i < config.items.size(); ++i) {
      QCOMPARE(config.items[i].orientation_deg, (i / 6) % 2 == 0 ? 0.0 : 90.0);
    }
    // Odd layers: 3 x 2 cells of 0.30 x 0.40 m.
    const auto xs = distinct(config, 0, 6, 6);
    QCOMPARE(xs.size(), std::size_t{3});
    QVERIFY(std::abs(xs[0] + 0.3) < 1e-12 && std::abs(xs[2] - 0.3) < 1e-12);
    const auto ys = distinct(config, 1, 6, 6);
    QVERIFY(std::abs(ys[0] + 0.2) < 1e-12 && std::abs(ys[1] - 0.2) < 1e-12);
    QCOMPARE(config.items[6].position[2], 0.15 + 0.2);
    QCOMPARE(config.items[12].position[2], 0.15 + 0.4);
    verify_valid(config);
  }

  void irregularShelfPacksInBarcodeOrder() {
    // 0.50 + 0.30 m on the first shelf; 0.55 m does not fit beside them and opens a second shelf
    // 0.30 m further along Y. The packing (0.90 x 0.65 m) is centred on the deck.
    const auto config = build(inputs(pb::LayerPattern::irregular, 4, 1,
                                     {"SKU-FM-002", "SKU-FD-003", "SKU-FS-003", "SKU-FV-003"}));
    const std::vector<pb::Vec2> expected{{0.25 - 0.45, 0.15 - 0.325},
                                         {0.65 - 0.45, 0.125 - 0.325},
                                         {0.275 - 0.45, 0.3 + 0.175 - 0.325},
                                         {0.725 - 0.45, 0.3 + 0.125 - 0.325}};
    for (std::size_t k = 0; k < 4; ++k) {
      QVERIFY(std::abs(config.items[k].position[0] - expected[k][0]) < 1e-12);
      QVERIFY(std::abs(config.items[k].position[1] - expected[k][1]) < 1e-12);
      QCOMPARE(config.items[k].position[2], 0.15);
    }
    verify_valid(config);
  }

  void itemsRestOnWhatIsUnderThem() {
    // A layer of mixed heights: the layer above rests on the tallest carton under each item,
    // not on the tallest carton of the layer.
    const auto config = build(inputs(pb::LayerPattern::column, 2, 2,
                                     {"SKU-FV-003", "SKU-FD-004", "SKU-FV-003", "SKU-FV-003"}));
    // 2 cells of 0.50 x 0.35 m (the milk crate's footprint) side by side.
    QCOMPARE(config.items[2].position[2], 0.15 + 0.08);
    QCOMPARE(config.items[3].position[2], 0.15 + 0.30);
    verify_valid(config);
  }

  void leanShiftsEachLayerByItsHeight() {
    auto in = inputs(pb::LayerPattern::column, 4, 4, {"SKU-FM-001"});
    in.lean_angle_deg = 3.0;
    const auto config = build(in);
    const double t = std::tan(3.0 * std::numbers::pi / 180.0);
    for (std::size_t l = 0; l < 4; ++l) {
      const double shift = std::round(t * 0.2 * static_cast<double>(l) / 1e-4) * 1e-4;
      QCOMPARE(config.items[4 * l].position[0] - config.items[0].position[0] + 0.0, shift);
    }
    QVERIFY(std::abs(config.items[12].position[0] - config.items[0].position[0] - 0.0314) < 1e-12);
    verify_valid(config);
  }

  void leanIsClampedToTheOverhangLimit() {
    auto in = inputs(pb::LayerPattern::column, 4, 6, {"SKU-FM-001"});
    in.lean_angle_deg = 30.0;
    const auto config = build(in);
    QVERIFY(pb::overhang_m(config) <= 0.1);
    QVERIFY(pb::overhang_m(config) > 0.0999);
    verify_valid(config);
    in.lean_angle_deg = -30.0;
    const auto mirrored = build(in);
    QVERIFY(mirrored.items.back().position[0] < 0.0);
    verify_valid(mirrored);
  }

  void topOverhangPushesTheTopLayer() {
    auto in = inputs(pb::LayerPattern::column, 6, 3, {"SKU-FM-001"});
    in.top_overhang_m = 0.04;
    const auto config = build(in);
    for (std::size_t k = 0; k < 6; ++k) {
      QCOMPARE(config.items[6 + k].position[0], config.items[k].position[0]);
      QVERIFY(std::abs(config.items[12 + k].position[0] - config.items[k].position[0] - 0.04) <
              1e-12);
    }
    QVERIFY(std::abs(pb::overhang_m(config) - 0.04) < 1e-12);
    verify_valid(config);
    in.top_overhang_m = 0.5;
    const auto clamped = build(in);
    QVERIFY(pb::overhang_m(clamped) <= 0.1 && pb::overhang_m(clamped) > 0.0999);
    verify_valid(clamped);
  }

  void barcodesRepeatCyclically() {
    const auto config =
        build(inputs(pb::LayerPattern::column, 2, 3, {"SKU-FD-001", "SKU-FD-003", "SKU-FD-002"}));
    const std::vector<std::string> expected{"SKU-FD-001", "SKU-FD-003", "SKU-FD-002",
                                            "SKU-FD-001", "SKU-FD-003", "SKU-FD-002"};
    for (std::size_t i = 0; i < 6; ++i) QCOMPARE(config.items[i].sku, expected[i]);
    // Extra barcodes are ignored, even unknown ones.
    const auto extra = build(inputs(pb::LayerPattern::column, 1, 1, {"SKU-FD-001", "NOPE"}));
    QCOMPARE(extra.items.size(), std::size_t{1});
    verify_valid(config);
  }

  void inputsReachThePallet() {
    auto in = inputs(pb::LayerPattern::column, 1, 1, {"SKU-FD-001"});
    in.pallet_id = "scan-7";
    in.base_pallet_type = pb::PalletType::gma;
    in.wrap = pb::WrapType::banded;
    in.env = pb::Environment::transitioning;
    in.body_temp_c = 3.5;
    in.seconds_since_temp_change = 45.0;
    in.belt_surface = pb::BeltSurface::steel_roller;
    const auto config = build(in);
    QCOMPARE(config.pallet_id, std::string("scan-7"));
    QCOMPARE(config.base_pallet_type, pb::PalletType::gma);
    QCOMPARE(config.base_dims_m, (pb::Vec3{1.219, 1.016, 0.14}));
    QCOMPARE(config.base_mass_kg, 17.0);
    QCOMPARE(config.wrap, pb::WrapType::banded);
    QCOMPARE(config.env, pb::Environment::transitioning);
    QCOMPARE(config.body_temp_c, 3.5);
    QCOMPARE(config.seconds_since_temp_change, 45.0);
    QCOMPARE(config.belt_surface, pb::BeltSurface::steel_roller);
    QCOMPARE(config.items[0].position, (pb::Vec3{0.0, 0.0, 0.14}));
  }

  void tooManyItemsPerLayerSaysHowManyFit() {
    const auto d = failure(inputs(pb::LayerPattern::column, 10, 2, {"SKU-FM-001"}));
    QCOMPARE(d.size(), std::size_t{1});
    QCOMPARE(d[0].pointer, std::string("/items_per_layer"));
    QCOMPARE(d[0].message,
             std::string("layer 0 does not fit 10 cartons (largest SKU-FM-001, 0.40 x 0.30 m) in "
                         "a column pattern on the 1.200 x 0.800 m EUR deck, even with 10.0 cm of "
                         "overhang; at most 9 fit on every layer, so set items_per_layer to 9 or "
                         "fewer"));
    pb::ValidationLimits strict;
    strict.max_overhang_m = 0.0;
    const auto s = failure(inputs(pb::LayerPattern::pinwheel, 9, 2, {"SKU-FM-001"}), strict);
    QCOMPARE(s.size(), std::size_t{1});
    QVERIFY(s[0].message.find("at most 6 fit") != std::string::npos);
  }

  void theFailingLayerIsNamed() {
    const auto d = failure(inputs(
        pb::LayerPattern::column, 6, 2,
        {"SKU-FM-001", "SKU-FM-001", "SKU-FM-001", "SKU-FM-001", "SKU-FM-001", "SKU-FM-001",
         "SKU-FS-003", "SKU-FS-003", "SKU-FS-003", "SKU-FS-003", "SKU-FS-003", "SKU-FS-003"}));
    QCOMPARE(d.size(), std::size_t{1});
    QVERIFY2(d[0].message.rfind("layer 1 does not fit 6 cartons (largest SKU-FS-003", 0) == 0,
             d[0].message.c_str());
    QVERIFY(d[0].message.find("at most 4 fit") != std::string::npos);
  }

  void inputErrorsPointAtTheField() {
    const auto unknown = failure(inputs(pb::LayerPattern::brick, 2, 1, {"SKU-FD-001", "NOPE"}));
    QCOMPARE(unknown.size(), std::size_t{1});
    QCOMPARE(unknown[0].pointer, std::string("/skus/1"));
    QCOMPARE(unknown[0].message,
             std::string("unknown SKU 'NOPE'; use a SKU from the catalog (palletballet-cli "
                         "catalog)"));

    auto in = inputs(pb::LayerPattern::brick, 0, 0, {});
    in.lean_angle_deg = 50.0;
    in.top_overhang_m = std::nan("");
    const auto d = failure(in);
    QCOMPARE(d.size(), std::size_t{5});
    QCOMPARE(d[0].pointer, std::string("/layers"));
    QCOMPARE(d[0].message, std::string("0 layers is not a pallet; use 1..50"));
    QCOMPARE(d[1].pointer, std::string("/items_per_layer"));
    QCOMPARE(d[2].pointer, std::string("/skus"));
    QCOMPARE(d[3].pointer, std::string("/lean_angle_deg"));
    QCOMPARE(d[4].pointer, std::string("/top_overhang_m"));
    QCOMPARE(failure(inputs(pb::LayerPattern::brick, 101, 1, {"SKU-FD-001"}))[0].pointer,
             std::string("/items_per_layer"));
    QCOMPARE(failure(inputs(pb::LayerPattern::brick, 1, 51, {"SKU-FD-001"}))[0].pointer,
             std::string("/layers"));
  }

  void capsOfTheLimitsAreErrors() {
    // Seven layers of 0.30 m milk crates reach 2.25 m.
    const auto d = failure(inputs(pb::LayerPattern::column, 2, 7, {"SKU-FD-004"}));
    QCOMPARE(d.size(), std::size_t{1});
    QVERIFY(d[0].pointer.rfind("/items/", 0) == 0);
    QVERIFY(d[0].message.find("m limit") != std::string::npos);
  }

  // The contract: whatever the scanner reports, a built pallet validates, nothing floats or
  // interpenetrates, and a refusal is one of the documented ones.
  void randomInputsAlwaysValidate() {
    const auto all = catalog().all();
    int built = 0;
    for (std::uint64_t seed = 0; seed < 600; ++seed) {
      pb::Rng rng(seed);
      pb::ScannerInputs in;
      in.pattern = static_cast<pb::LayerPattern>(rng.uniform_int(0, 3));
      in.base_pallet_type = static_cast<pb::PalletType>(rng.uniform_int(0, 2));
      in.items_per_layer = rng.uniform_int(1, 12);
      in.layers = rng.uniform_int(1, 7);
      const int distinct_skus = rng.uniform_int(1, 3) == 1 ? 1 : rng.uniform_int(1, 40);
      for (int i = 0; i < distinct_skus; ++i) {
        in.skus.push_back(all[static_cast<std::size_t>(rng.uniform_int(0, 29))].sku);
      }
      in.lean_angle_deg = rng.bernoulli(0.3) ? rng.uniform(-10.0, 10.0) : 0.0;
      in.top_overhang_m = rng.bernoulli(0.3) ? rng.uniform(0.0, 0.15) : 0.0;
      pb::ValidationLimits limits;
      if (rng.bernoulli(0.2)) limits.max_overhang_m = rng.uniform(0.0, 0.05);
      auto result = pb::build_from_scanner(in, catalog(), limits);
      if (result) {
        ++built;
        QCOMPARE(result->items.size(), static_cast<std::size_t>(in.items_per_layer * in.layers));
        verify_valid(*result, limits);
        continue;
      }
      for (const auto& d : pb::errors_of(result.diagnostics)) {
        const bool fit = d.pointer == "/items_per_layer";
        const bool cap = d.message.find("m limit") != std::string::npos ||
                         d.message.find("may carry") != std::string::npos;
        // Cartons of different sizes in one layer leave an uneven top that some of the next
        // layer's cartons cannot stand on: such a scan is refused, naming the carton. Cartons of
        // one size always stand in every pattern.
        const bool uneven =
            distinct_skus > 1 && d.message.find("cannot stand") != std::string::npos;
        QVERIFY2(fit || cap || uneven, pb::to_string(d).c_str());
        if (!fit) continue;
        // For a single SKU the count the message offers builds (or meets only the caps); with
        // several, fewer items per layer regroup the cyclic barcodes into different layers.
        const auto at = d.message.find("at most ");
        if (at == std::string::npos || distinct_skus > 1) continue;
        in.items_per_layer = std::stoi(d.message.substr(at + 8));
        auto retry = pb::build_from_scanner(in, catalog(), limits);
        for (const auto& r : pb::errors_of(retry.diagnostics)) {
          QVERIFY2(
              r.pointer != "/items_per_layer" || retry.ok(),
              qPrintable(QString::fromStdString(pb::to_string(d) + " -> " + pb::to_string(r))));
        }
      }
    }
    qInfo("%d of 600 random scans built", built);
    QVERIFY2(built >= 200, qPrintable(QString::number(built)));
  }
};

QTEST_APPLESS_MAIN(LayerLayoutTest)
#include "layer_layout_test.moc"
