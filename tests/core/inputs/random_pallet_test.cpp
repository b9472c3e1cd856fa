// SPDX-License-Identifier: MIT
#include "core/inputs/random_pallet.hpp"
#include "core/inputs/static_stability.hpp"

#include <QtTest>
#include <algorithm>
#include <bit>
#include <cmath>
#include <map>

#include "core/contract/json_io.hpp"
#include "core/contract/pallet_metrics.hpp"
#include "core/contract/pallet_type.hpp"

namespace {

const pb::Catalog& catalog() {
  return pb::Catalog::builtin();
}

pb::PalletConfig make(const pb::RandomPalletOptions& options,
                      const pb::ValidationLimits& limits = {}) {
  auto result = pb::random_pallet(options, catalog(), limits);
  if (!result) {
    for (const auto& d : result.diagnostics) qWarning("%s", pb::to_string(d).c_str());
    pb::PalletConfig refused;
    refused.pallet_id.clear();
    return refused;
  }
  return *result;
}

pb::RandomPalletOptions seeded(std::uint64_t seed) {
  pb::RandomPalletOptions options;
  options.seed = seed;
  return options;
}

// FNV-1a over the exact bits of what the generator computes (not over JSON formatting, which
// another file owns): a change of platform, compiler or algorithm that moves one bit fails.
std::uint64_t fingerprint(const pb::PalletConfig& config) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  auto mix_bytes = [&h](const void* data, std::size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 0x100000001b3ULL;
  };
  auto mix = [&](double v) {
    const auto bits = std::bit_cast<std::uint64_t>(v);
    mix_bytes(&bits, sizeof bits);
  };
  mix(config.body_temp_c);
  mix(config.seconds_since_temp_change);
  for (const auto& item : config.items) {
    mix_bytes(item.sku.data(), item.sku.size());
    for (double v : item.position) mix(v);
    mix(item.orientation_deg);
  }
  return h;
}

enum class Homogeneity { single_sku, sku_per_layer, mixed };

Homogeneity homogeneity_of(const pb::ScannerInputs& in) {
  const auto& s = in.skus;
  if (std::all_of(s.begin(), s.end(), [&](const auto& x) { return x == s.front(); })) {
    return Homogeneity::single_sku;
  }
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] != s[i - i % static_cast<std::size_t>(in.items_per_layer)]) return Homogeneity::mixed;
  }
  return Homogeneity::sku_per_layer;
}

// |count - n p| within 4 standard deviations of a binomial.
bool within_4_sigma(int count, int n, double p) {
  return std::abs(count - n * p) <= 4.0 * std::sqrt(n * p * (1.0 - p));
}

template <class K>
void verify_shares(const std::map<K, int>& counts, const std::map<K, double>& shares, int n,
                   const char* what) {
  for (const auto& [key, p] : shares) {
    const int count = counts.count(key) ? counts.at(key) : 0;
    QVERIFY2(within_4_sigma(count, n, p), qPrintable(QString("%1 %2: %3 of %4, expected share %5")
                                                         .arg(what)
                                                         .arg(static_cast<int>(key))
                                                         .arg(count)
                                                         .arg(n)
                                                         .arg(p)));
  }
}

}  // namespace

class RandomPalletTest : public QObject {
  Q_OBJECT

 private slots:
  void sameSeedGivesIdenticalBytes() {
    for (std::uint64_t seed : {0ULL, 23ULL, 4242ULL}) {
      const std::string a = pb::pallet_to_json(make(seeded(seed))).dump();
      const std::string b = pb::pallet_to_json(make(seeded(seed))).dump();
      QCOMPARE(a, b);
    }
    QVERIFY(pb::pallet_to_json(make(seeded(1))).dump() !=
            pb::pallet_to_json(make(seeded(2))).dump());
  }

  // The curated "random scanner feed" scenario's recipe, pinned: if this changes, so does a
  // curated scenario.
  void seed23IsPinned() {
    pb::RandomPalletOptions options;
    options.seed = 23;
    options.anomaly_rate = 0.1;
    options.min_layers = 2;
    options.max_layers = 5;
    options.min_items_per_layer = 2;
    options.max_items_per_layer = 5;
    const auto config = make(options);
    QCOMPARE(config.pallet_id, std::string("R-23"));
    QCOMPARE(config.notes, std::string("random seed 23: brick 4x2 on EUR, homogeneous, frozen"));
    QCOMPARE(config.items.size(), std::size_t{8});
    QCOMPARE(fingerprint(config), std::uint64_t{0x2d417835bde8be33});
    QCOMPARE(fingerprint(make(seeded(0))), std::uint64_t{0x9c4cae5f3dfd7e28});
    // An anomaly exercises tan() and the clamps.
    pb::RandomPalletOptions anomalous = seeded(7);
    anomalous.anomaly_rate = 1.0;
    const auto leaning = make(anomalous);
    QCOMPARE(
        leaning.notes,
        std::string(
            "random seed 7: brick 4x4 on CHEP, one SKU per layer, refrigerated; "
            "anomaly: lean 2.6 deg, top overhang 5.5 cm; 10 cartons a layer reduced "
            "to 4 to fit the deck; the alternate layers are not shifted: so laid, some cartons "
            "of the brick pattern would not stand on the layer below"));
    QCOMPARE(fingerprint(leaning), std::uint64_t{0xba14b8a685974890});
  }

  void everySeedValidates() {
    int reduced = 0, trimmed = 0;
    const int n = 500;
    for (std::uint64_t seed = 0; seed < static_cast<std::uint64_t>(n); ++seed) {
      auto result = pb::random_pallet(seeded(seed), catalog());
      QVERIFY2(result.ok(), qPrintable(QString("seed %1").arg(seed)));
      const pb::PalletConfig& config = *result;
      const auto diags = pb::validate(config);
      for (const auto& d : pb::errors_of(diags)) qWarning("%s", pb::to_string(d).c_str());
      QVERIFY2(!pb::has_errors(diags), qPrintable(QString("seed %1").arg(seed)));
      QCOMPARE(config.pallet_id, "R-" + std::to_string(seed));
      QVERIFY(!config.items.empty());
      const auto& spec = pb::pallet_type_spec(config.base_pallet_type);
      QVERIFY(pb::total_mass_kg(config) <= std::min(1200.0, spec.rated_load_kg + spec.mass_kg));
      QVERIFY(pb::stack_height_m(config) <= 1.85);
      QVERIFY(pb::overhang_m(config) <= 0.10);
      QCOMPARE(config.wrap, pb::WrapType::stretch);
      QVERIFY(config.notes.rfind("random seed " + std::to_string(seed) + ": ", 0) == 0);
      reduced += config.notes.find("cartons a layer reduced") != std::string::npos ? 1 : 0;
      trimmed += config.notes.find("trimmed") != std::string::npos ? 1 : 0;
    }
    qInfo("of %d seeds: cartons a layer reduced in %d, layers trimmed in %d", n, reduced, trimmed);
  }

  // Issue 12: every pattern, unwrapped (and with the wrap drawn per pallet), hundreds of seeds
  // each: every pallet validates with the standing rule and every item's load acts at least the
  // margin inside what it rests on; the rest of a seed's pallet does not depend on the wrap.
  void everyPatternStandsUnwrapped() {
    std::map<std::string, int> per_pattern;
    int reduced = 0, trimmed = 0, fell_back = 0;
    const int n = 2400;
    for (std::uint64_t seed = 0; seed < static_cast<std::uint64_t>(n); ++seed) {
      pb::RandomPalletOptions options = seeded(seed);
      options.min_layers = 2;
      options.wrap = pb::WrapType::none;
      auto result = pb::random_pallet(options, catalog());
      QVERIFY2(result.ok(), qPrintable(QString("seed %1").arg(seed)));
      const pb::PalletConfig& config = *result;
      QCOMPARE(config.wrap, pb::WrapType::none);
      const auto diags = pb::validate(config);
      for (const auto& d : pb::errors_of(diags)) qWarning("%s", pb::to_string(d).c_str());
      QVERIFY2(!pb::has_errors(diags), qPrintable(QString("seed %1").arg(seed)));
      QVERIFY2(pb::stands(config, pb::ValidationLimits{}.stability_margin_m),
               qPrintable(QString("seed %1").arg(seed)));
      const std::string pattern = config.notes.substr(
          config.notes.find(": ") + 2,
          config.notes.find(' ', config.notes.find(": ") + 2) - config.notes.find(": ") - 2);
      ++per_pattern[pattern];
      reduced += config.notes.find("so that every item stands") != std::string::npos &&
                 config.notes.find("reduced to") != std::string::npos;
      trimmed += config.notes.find("and so that every item stands") != std::string::npos;
      fell_back += config.notes.find("not turned") != std::string::npos ||
                   config.notes.find("not shifted") != std::string::npos;
      if (seed % 8 == 0) {  // the wrap is drawn last: the same load under any wrap
        options.wrap = std::nullopt;
        auto mixed = pb::random_pallet(options, catalog());
        QVERIFY(mixed.ok());
        QCOMPARE(mixed->items, config.items);
      }
    }
    for (const char* p : {"column", "brick", "pinwheel", "irregular"}) {
      qInfo("%s: %d pallets", p, per_pattern[p]);
      QVERIFY2(per_pattern[p] >= 100, p);
    }
    qInfo(
        "of %d seeds: anomaly reduced in %d, layers trimmed to stand in %d, alternate layers laid "
        "plain "
        "in %d",
        n, reduced, trimmed, fell_back);
  }

  void capsOfTheLimitsApply() {
    pb::ValidationLimits limits;
    limits.max_stack_height_m = 0.9;
    limits.max_gross_mass_kg = 400.0;
    for (std::uint64_t seed = 0; seed < 50; ++seed) {
      const auto config = make(seeded(seed), limits);
      QVERIFY(!pb::has_errors(pb::validate(config, limits)));
      QVERIFY(pb::stack_height_m(config) <= 0.9);
      QVERIFY(pb::total_mass_kg(config) <= 400.0);
    }
    // Seed 0 draws more than fits under 0.9 m and says so.
    const auto inputs = pb::random_scanner_inputs(seeded(0), catalog());
    const auto config = make(seeded(0), limits);
    QVERIFY(config.items.size() < static_cast<std::size_t>(inputs.layers * inputs.items_per_layer));
    QVERIFY2(config.notes.find("; trimmed from " + std::to_string(inputs.layers) + " layers") !=
                 std::string::npos,
             config.notes.c_str());
  }

  // Eighty-three cartons a layer drawn, nine fit the deck: the mass cap is then asked of five
  // layers of nine (655 kg), not of five of 83 (it was trimmed to one layer "for the mass cap").
  void theDeckIsFittedBeforeTheCapsTrimLayers() {
    pb::RandomPalletOptions options = seeded(1);
    options.min_items_per_layer = 40;
    options.max_items_per_layer = 100;
    const auto inputs = pb::random_scanner_inputs(options, catalog());
    const auto config = make(options);
    QVERIFY2(
        config.notes.find(std::to_string(inputs.items_per_layer) +
                          " cartons a layer reduced to 9 to fit the deck") != std::string::npos,
        config.notes.c_str());
    QCOMPARE(config.items.size(), std::size_t{9} * static_cast<std::size_t>(inputs.layers));
    QVERIFY2(config.notes.find("trimmed") == std::string::npos, config.notes.c_str());
  }

  // Forty to fifty layers asked of a 1.85 m cap: each pallet is trimmed before it is laid out
  // (laid out first, the stack reached past the validator's 10 m coordinates and seed 3 was an
  // error), and the note names the caps that trimmed it.
  void farTooManyLayersAreTrimmedToTheHeightCap() {
    pb::RandomPalletOptions options;
    options.min_layers = 40;
    options.max_layers = 50;
    for (std::uint64_t seed = 0; seed < 20; ++seed) {
      options.seed = seed;
      const auto made = pb::random_pallet(options, catalog());
      QVERIFY2(made.ok(), made.ok() ? "" : pb::to_string(made.diagnostics[0]).c_str());
      QVERIFY(!pb::has_errors(pb::validate(*made)));
      QVERIFY(pb::stack_height_m(*made) <= pb::ValidationLimits{}.max_stack_height_m);
      const bool named = made->notes.find("layers for the height cap") != std::string::npos ||
                         made->notes.find("layers for the mass cap") != std::string::npos;
      QVERIFY2(named, made->notes.c_str());
    }
  }

  void itemsPerLayerIsReducedToWhatFits() {
    pb::RandomPalletOptions options;
    options.min_items_per_layer = 10;
    options.max_items_per_layer = 10;
    int reduced = 0;
    for (std::uint64_t seed = 0; seed < 40; ++seed) {
      options.seed = seed;
      const auto inputs = pb::random_scanner_inputs(options, catalog());
      const auto config = make(options);
      QVERIFY(!pb::has_errors(pb::validate(config)));
      if (config.notes.find("10 cartons a layer reduced") != std::string::npos) ++reduced;
      if (inputs.pattern == pb::LayerPattern::column) QCOMPARE(inputs.items_per_layer, 2);
    }
    QVERIFY(reduced > 0);
  }

  void distributionsMatchTheReference() {
    const int n = 2000;
    std::map<pb::Environment, int> envs;
    std::map<pb::LayerPattern, int> patterns;
    std::map<pb::PalletType, int> bases;
    std::map<Homogeneity, int> homogeneity;
    int anomalies = 0;
    for (int i = 0; i < n; ++i) {
      const auto in = pb::random_scanner_inputs(seeded(static_cast<std::uint64_t>(i)), catalog());
      ++envs[in.env];
      ++patterns[in.pattern];
      ++bases[in.base_pallet_type];
      ++homogeneity[homogeneity_of(in)];
      anomalies += in.lean_angle_deg != 0.0 ? 1 : 0;
    }
    verify_shares(envs,
                  std::map<pb::Environment, double>{{pb::Environment::frozen, 0.45},
                                                    {pb::Environment::refrigerated, 0.35},
                                                    {pb::Environment::thawed, 0.10},
                                                    {pb::Environment::transitioning, 0.10}},
                  n, "env");
    verify_shares(patterns,
                  std::map<pb::LayerPattern, double>{{pb::LayerPattern::brick, 0.55},
                                                     {pb::LayerPattern::column, 0.20},
                                                     {pb::LayerPattern::pinwheel, 0.20},
                                                     {pb::LayerPattern::irregular, 0.05}},
                  n, "pattern");
    verify_shares(
        bases,
        std::map<pb::PalletType, double>{
            {pb::PalletType::eur, 0.55}, {pb::PalletType::gma, 0.35}, {pb::PalletType::chep, 0.10}},
        n, "base");
    // A layer-by-layer or mixed draw can repeat one SKU by chance (pools of 6 to 12 SKUs), so
    // "one SKU" is a little above .70; the shares are checked against that bound.
    QVERIFY(homogeneity[Homogeneity::single_sku] >= n * 0.70 - 4 * std::sqrt(n * 0.21));
    QVERIFY(homogeneity[Homogeneity::single_sku] <= n * 0.74 + 4 * std::sqrt(n * 0.19));
    QVERIFY(within_4_sigma(homogeneity[Homogeneity::mixed], n, 0.10));
    QVERIFY(within_4_sigma(anomalies, n, 0.08));
  }

  void drawnValuesStayInTheirRanges() {
    for (std::uint64_t seed = 0; seed < 2000; ++seed) {
      const auto in = pb::random_scanner_inputs(seeded(seed), catalog());
      const double t = in.body_temp_c;
      const double s = in.seconds_since_temp_change;
      switch (in.env) {
        case pb::Environment::frozen:
          QVERIFY(t >= -25.0 && t < -18.0);
          break;
        case pb::Environment::refrigerated:
          QVERIFY(t >= 0.0 && t < 5.0);
          break;
        case pb::Environment::thawed:
          QVERIFY(t >= 15.0 && t < 22.0);
          break;
        case pb::Environment::transitioning:
          QVERIFY(t >= -2.0 && t < 8.0);
          break;
      }
      if (in.env == pb::Environment::transitioning) {
        QVERIFY(s >= 30.0 && s < 300.0);
      } else {
        QVERIFY(s >= 1800.0 && s < 7200.0);
      }
      QVERIFY(in.layers >= 3 && in.layers <= 7);
      const int ti = in.items_per_layer;
      if (in.pattern == pb::LayerPattern::column) {
        QVERIFY(ti >= 1 && ti <= 2);
      } else {
        QVERIFY(ti >= 4 && ti <= 10);  // the options' range is above every pattern's minimum
      }
      QCOMPARE(in.skus.size(), static_cast<std::size_t>(in.layers * ti));
      const auto pool_env =
          in.env == pb::Environment::transitioning ? pb::Environment::frozen : in.env;
      for (const auto& sku : in.skus) QCOMPARE(catalog().find(sku)->default_env, pool_env);
      if (in.lean_angle_deg != 0.0) {
        QVERIFY(in.lean_angle_deg >= 2.0 && in.lean_angle_deg < 8.0);
        QVERIFY(in.top_overhang_m >= 0.025 && in.top_overhang_m < 0.10);
      } else {
        QCOMPARE(in.top_overhang_m, 0.0);
      }
      QCOMPARE(in.pallet_id, "R-" + std::to_string(seed));
      QCOMPARE(in.wrap, pb::WrapType::stretch);
    }
  }

  // The most items a layer asked for holds: a pattern that needs more (brick and pinwheel 4,
  // irregular 3) is not drawn (until session 39 it was, and raised the count past the limit), and
  // a column is at most 2 a layer whatever is asked. Pattern minimums still raise the fewest.
  void aPatternThatNeedsMoreItemsThanAskedIsNotDrawn() {
    pb::RandomPalletOptions options;
    options.min_items_per_layer = 1;
    options.max_items_per_layer = 3;
    std::map<pb::LayerPattern, std::pair<int, int>> seen;  // min, max Ti
    for (std::uint64_t seed = 0; seed < 2000; ++seed) {
      options.seed = seed;
      const auto in = pb::random_scanner_inputs(options, catalog());
      auto [it, inserted] = seen.try_emplace(in.pattern, in.items_per_layer, in.items_per_layer);
      it->second.first = std::min(it->second.first, in.items_per_layer);
      it->second.second = std::max(it->second.second, in.items_per_layer);
    }
    QCOMPARE(seen.size(), std::size_t(2));
    QCOMPARE(seen[pb::LayerPattern::column], std::make_pair(1, 2));
    QCOMPARE(seen[pb::LayerPattern::irregular], std::make_pair(3, 3));
    options.max_items_per_layer = 2;  // only columns
    for (std::uint64_t seed = 0; seed < 50; ++seed) {
      options.seed = seed;
      QCOMPARE(pb::random_scanner_inputs(options, catalog()).pattern, pb::LayerPattern::column);
    }
    options.min_items_per_layer = 1;  // a brick still has its 4, when 4 may be drawn
    options.max_items_per_layer = 5;
    for (std::uint64_t seed = 0; seed < 200; ++seed) {
      options.seed = seed;
      const auto in = pb::random_scanner_inputs(options, catalog());
      if (in.pattern == pb::LayerPattern::brick) QVERIFY(in.items_per_layer >= 4);
      QVERIFY(in.items_per_layer <= 5);
    }
  }

  void anomalyRateExtremes() {
    pb::RandomPalletOptions options;
    options.anomaly_rate = 1.0;
    for (std::uint64_t seed = 0; seed < 100; ++seed) {
      options.seed = seed;
      const auto config = make(options);
      QVERIFY2(config.notes.find("; anomaly: lean ") != std::string::npos, config.notes.c_str());
      QVERIFY(!pb::has_errors(pb::validate(config)));
    }
    options.anomaly_rate = 0.0;
    for (std::uint64_t seed = 0; seed < 100; ++seed) {
      options.seed = seed;
      QVERIFY(make(options).notes.find("anomaly") == std::string::npos);
    }
  }

  void optionsAreChecked() {
    QVERIFY(pb::validate_random_options({}).empty());
    pb::RandomPalletOptions bad;
    bad.anomaly_rate = 1.5;
    bad.min_layers = 0;
    bad.max_layers = 51;
    bad.min_items_per_layer = 5;
    bad.max_items_per_layer = 4;
    const auto d = pb::validate_random_options(bad);
    QCOMPARE(d.size(), std::size_t{4});
    QCOMPARE(d[0].pointer, std::string("/anomaly_rate"));
    QCOMPARE(d[0].message,
             std::string("anomaly_rate 1.500 is not a probability; use 0..1 (0.08 is typical)"));
    QCOMPARE(d[1].pointer, std::string("/min_layers"));
    QCOMPARE(d[1].message, std::string("min_layers 0 is out of range; use 1..50 layers"));
    QCOMPARE(d[2].pointer, std::string("/max_layers"));
    QCOMPARE(d[3].pointer, std::string("/max_items_per_layer"));
    QCOMPARE(d[3].message, std::string("max_items_per_layer 4 must lie in "
                                       "min_items_per_layer..100 items per layer "
                                       "(min_items_per_layer is 5)"));
    pb::RandomPalletOptions nan;
    nan.anomaly_rate = std::nan("");
    QCOMPARE(pb::validate_random_options(nan).size(), std::size_t{1});
    pb::RandomPalletOptions big;
    big.min_items_per_layer = 101;
    big.max_items_per_layer = 101;
    const auto b = pb::validate_random_options(big);
    QCOMPARE(b.size(), std::size_t{2});
    QCOMPARE(b[0].pointer, std::string("/min_items_per_layer"));

    const auto refused = pb::random_pallet(bad, catalog());
    QVERIFY(!refused.ok());
    QCOMPARE(refused.diagnostics, d);
  }
};

QTEST_APPLESS_MAIN(RandomPalletTest)
#include "random_pallet_test.moc"
