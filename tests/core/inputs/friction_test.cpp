// SPDX-License-Identifier: MIT
#include "core/inputs/friction.hpp"

#include <QtTest>
#include <cmath>
#include <nlohmann/json.hpp>

using namespace pb;
using Json = nlohmann::json;

namespace {

QString q(const std::string& s) {
  return QString::fromStdString(s);
}

QStringList q(const std::vector<std::string>& strings) {
  QStringList out;
  for (const auto& s : strings) out << q(s);
  return out;
}

QString describe(const Diagnostics& diagnostics) {
  QStringList lines;
  for (const auto& d : diagnostics) lines << q(to_string(d));
  return lines.join(QStringLiteral("; "));
}

bool near(double a, double b) {
  return std::abs(a - b) <= 1e-12;
}

const FrictionModel& model() {
  return FrictionModel::builtin();
}

FrictionValue steady(std::string_view key, double t) {
  return *model().steady(key, t);
}

// A valid table in the reference's format, mutated by the malformed-document cases.
Json valid_table() {
  return Json::parse(R"({
    "_comment": "test table",
    "surface_pairs": {
      "carton/carton": {
        "description": "case on case",
        "source": "made up",
        "control_points": [
          {"temp_c": -10.0, "mu_s": 0.40, "mu_d": 0.30},
          {"temp_c": 0.0, "mu_s": 0.35, "mu_d": 0.30},
          {"temp_c": 10.0, "mu_s": 0.45, "mu_d": 0.40}
        ]
      }
    },
    "transition_penalty": {
      "_comment": "frost melt",
      "danger_zone_temp_c": [-2.0, 8.0],
      "min_multiplier": 0.65,
      "recovery_seconds": 600.0
    }
  })");
}

Json& points_of(Json& table) {
  return table["surface_pairs"]["carton/carton"]["control_points"];
}

PalletConfig pallet(PalletType type, BeltSurface belt, double temp_c = -18.0,
                    double seconds = 3600.0) {
  PalletConfig config;
  config.base_pallet_type = type;
  config.belt_surface = belt;
  config.body_temp_c = temp_c;
  config.seconds_since_temp_change = seconds;
  return config;
}

}  // namespace

class FrictionTest : public QObject {
  Q_OBJECT

 private slots:
  void builtinHasBeltAndItemPairs() {
    const QStringList expected = {"plastic_pallet/rubber_belt", "wood_pallet/rubber_belt",
                                  "wood_pallet/steel_roller",   "carton/carton",
                                  "carton/plastic_pallet",      "carton/wood_pallet"};
    QCOMPARE(q(model().pair_keys()), expected);
    for (const char* key : {"carton/carton", "carton/plastic_pallet", "carton/wood_pallet"}) {
      const SurfacePair* pair = model().find(key);
      QVERIFY(pair != nullptr);
      QVERIFY2(!pair->source.empty(), key);
      QCOMPARE(pair->points.size(), std::size_t{7});
    }
    const FrostMeltPenalty& p = model().penalty();
    QCOMPARE(p.zone_lo_c, -2.0);
    QCOMPARE(p.zone_hi_c, 8.0);
    QCOMPARE(p.min_multiplier, 0.65);
    QCOMPARE(p.recovery_s, 600.0);
  }

  void valuesAtTablePoints() {
    struct Case {
      const char* key;
      double t, mu_s, mu_d;
    };
    for (const Case& c :
         {Case{"wood_pallet/rubber_belt", -25.0, 0.22, 0.18},
          Case{"wood_pallet/rubber_belt", 0.0, 0.30, 0.25},
          Case{"wood_pallet/rubber_belt", 25.0, 0.52, 0.45},
          Case{"plastic_pallet/rubber_belt", 5.0, 0.32, 0.27},
          Case{"wood_pallet/steel_roller", -15.0, 0.20, 0.15},
          Case{"carton/carton", 0.0, 0.34, 0.28}, Case{"carton/wood_pallet", -5.0, 0.40, 0.33},
          Case{"carton/plastic_pallet", 15.0, 0.33, 0.28}}) {
      const FrictionValue v = steady(c.key, c.t);
      QVERIFY2(v.mu_s == c.mu_s && v.mu_d == c.mu_d, c.key);
      QCOMPARE(v.penalty, 1.0);
    }
  }

  void linearBetweenPoints() {
    // wood/rubber: (-25: 0.22/0.18) (-15: 0.28/0.23) (-5: 0.34/0.28) (0: 0.30/0.25) (5: 0.38/0.32)
    FrictionValue v = steady("wood_pallet/rubber_belt", -20.0);
    QVERIFY(near(v.mu_s, 0.25) && near(v.mu_d, 0.205));
    v = steady("wood_pallet/rubber_belt", -22.5);
    QVERIFY(near(v.mu_s, 0.235) && near(v.mu_d, 0.1925));
    v = steady("wood_pallet/rubber_belt", -2.5);  // the wet-frost dip: falling toward 0 C
    QVERIFY(near(v.mu_s, 0.32) && near(v.mu_d, 0.265));
    v = steady("wood_pallet/rubber_belt", 2.5);
    QVERIFY(near(v.mu_s, 0.34) && near(v.mu_d, 0.285));
  }

  void clampedOutsideTheTable() {
    FrictionValue v = steady("wood_pallet/rubber_belt", -40.0);
    QCOMPARE(v.mu_s, 0.22);
    QCOMPARE(v.mu_d, 0.18);
    v = steady("wood_pallet/rubber_belt", 40.0);
    QCOMPARE(v.mu_s, 0.52);
    QCOMPARE(v.mu_d, 0.45);
    v = steady("carton/carton", -1e9);
    QCOMPARE(v.mu_s, 0.38);
    QVERIFY(std::isnan(steady("carton/carton", std::nan("")).mu_s));
  }

  void unknownPairHasNoValue() {
    QVERIFY(model().find("ice/rubber_belt") == nullptr);
    QVERIFY(!model().steady("ice/rubber_belt", 0.0));
    QVERIFY(!model().effective("ice/rubber_belt", 0.0, 0.0));
    QVERIFY(model().curve("ice/rubber_belt", -10.0, 10.0, 1.0, 0.0).empty());
  }

  void frostMeltMultiplier() {
    const FrostMeltPenalty& p = model().penalty();  // zone [-2, 8], centre 3, 0.65, 600 s
    QCOMPARE(p.multiplier(3.0, 0.0), 0.65);
    QCOMPARE(p.multiplier(3.0, 300.0), 1.0 - 0.5 * 0.35);
    QCOMPARE(p.multiplier(3.0, 600.0), 1.0);
    QCOMPARE(p.multiplier(3.0, 7200.0), 1.0);
    QCOMPARE(p.multiplier(5.5, 0.0), 1.0 - 0.5 * 0.35);  // half-way to the edge
    QCOMPARE(p.multiplier(-2.0, 0.0), 1.0);              // edges are inside, with factor 0
    QCOMPARE(p.multiplier(8.0, 0.0), 1.0);
    QCOMPARE(p.multiplier(-2.001, 0.0), 1.0);
    QCOMPARE(p.multiplier(8.001, 0.0), 1.0);
    QCOMPARE(p.multiplier(-18.0, 0.0), 1.0);
    QVERIFY(p.multiplier(-1.9, 0.0) < 1.0);
    QVERIFY(p.multiplier(7.9, 0.0) < 1.0);
    QCOMPARE(p.multiplier(3.0, -600.0), 0.65);  // never below min_multiplier
  }

  void effectiveAppliesThePenalty() {
    const FrictionValue s = steady("wood_pallet/rubber_belt", 3.0);
    QVERIFY(near(s.mu_s, 0.348) && near(s.mu_d, 0.292));
    FrictionValue e = *model().effective("wood_pallet/rubber_belt", 3.0, 0.0);
    QCOMPARE(e.penalty, 0.65);
    QCOMPARE(e.mu_s, 0.65 * s.mu_s);
    QCOMPARE(e.mu_d, 0.65 * s.mu_d);
    e = *model().effective("wood_pallet/rubber_belt", 3.0, 300.0);
    QCOMPARE(e.mu_s, (1.0 - 0.5 * 0.35) * s.mu_s);
    e = *model().effective("wood_pallet/rubber_belt", 3.0, 600.0);
    QCOMPARE(e.penalty, 1.0);
    QCOMPARE(e.mu_s, s.mu_s);
    e = *model().effective("wood_pallet/rubber_belt", -18.0, 0.0);
    QCOMPARE(e.penalty, 1.0);
  }

  void penaltyAppliesToItemPairs() {
    for (const char* key : {"carton/carton", "carton/wood_pallet", "carton/plastic_pallet"}) {
      const FrictionValue s = steady(key, 3.0);
      const FrictionValue e = *model().effective(key, 3.0, 0.0);
      QCOMPARE(e.penalty, 0.65);
      QCOMPARE(e.mu_s, 0.65 * s.mu_s);
      QCOMPARE(e.mu_d, 0.65 * s.mu_d);
    }
  }

  void curveSamplesInclusive() {
    auto c = model().curve("wood_pallet/rubber_belt", -25.0, 25.0, 5.0, 0.0);
    QCOMPARE(c.size(), std::size_t{11});
    for (std::size_t i = 0; i < c.size(); ++i) {
      QCOMPARE(c[i].temp_c, -25.0 + 5.0 * static_cast<double>(i));
      const FrictionValue s = steady("wood_pallet/rubber_belt", c[i].temp_c);
      QCOMPARE(c[i].steady.mu_s, s.mu_s);
      QCOMPARE(c[i].steady.mu_d, s.mu_d);
      QCOMPARE(c[i].steady.penalty, 1.0);
    }
    // 0 C: zone factor 1 - 3/5 = 0.4 at 0 s.
    QCOMPARE(c[5].temp_c, 0.0);
    QCOMPARE(c[5].effective.penalty, 1.0 - 0.4 * 0.35);
    QCOMPARE(c[5].effective.mu_s, c[5].steady.mu_s * c[5].effective.penalty);
    QCOMPARE(c[0].effective.penalty, 1.0);

    c = model().curve("wood_pallet/rubber_belt", -25.0, 25.0, 0.1, 0.0);
    QCOMPARE(c.size(), std::size_t{501});
    QCOMPARE(c.back().temp_c, 25.0);
    c = model().curve("carton/carton", 0.0, 1.0, 0.3, 600.0);
    QCOMPARE(c.size(), std::size_t{4});
    QCOMPARE(c.back().temp_c, 0.9);
    QCOMPARE(c.back().effective.penalty, 1.0);
    QCOMPARE(model().curve("carton/carton", 2.0, 2.0, 1.0, 0.0).size(), std::size_t{1});
    QVERIFY(model().curve("carton/carton", 0.0, 10.0, 0.0, 0.0).empty());
    QVERIFY(model().curve("carton/carton", 0.0, 10.0, -1.0, 0.0).empty());
    QVERIFY(model().curve("carton/carton", 10.0, 0.0, 1.0, 0.0).empty());
    // A step below the temperatures' resolution: one sample, not a loop that never reaches t1.
    QCOMPARE(model().curve("carton/carton", 1e300, 1e300, 1.0, 0.0).size(), std::size_t{1});
  }

  void forPalletKeys() {
    struct Case {
      PalletType type;
      BeltSurface belt;
      const char* belt_key;
      const char* item_key;
    };
    for (const Case& c : {Case{PalletType::eur, BeltSurface::rubber_belt, "wood_pallet/rubber_belt",
                               "carton/wood_pallet"},
                          Case{PalletType::eur, BeltSurface::steel_roller,
                               "wood_pallet/steel_roller", "carton/wood_pallet"},
                          Case{PalletType::gma, BeltSurface::rubber_belt, "wood_pallet/rubber_belt",
                               "carton/wood_pallet"},
                          Case{PalletType::gma, BeltSurface::steel_roller,
                               "wood_pallet/steel_roller", "carton/wood_pallet"},
                          Case{PalletType::chep, BeltSurface::rubber_belt,
                               "plastic_pallet/rubber_belt", "carton/plastic_pallet"}}) {
      const auto r = model().for_pallet(pallet(c.type, c.belt));
      QVERIFY2(r.ok(), qPrintable(describe(r.diagnostics)));
      QVERIFY(r.diagnostics.empty());
      QCOMPARE(q(r->belt_pallet_key), QString(c.belt_key));
      QCOMPARE(q(r->item_pallet_key), QString(c.item_key));
      QCOMPARE(q(r->item_item_key), QStringLiteral("carton/carton"));
      QCOMPARE(r->belt_pallet.mu_s, steady(c.belt_key, -18.0).mu_s);
      QCOMPARE(r->item_pallet.mu_d, steady(c.item_key, -18.0).mu_d);
      QCOMPARE(r->item_item.mu_s, steady("carton/carton", -18.0).mu_s);
    }
  }

  void forPalletAppliesThePenaltyToAllContacts() {
    const auto r = model().for_pallet(pallet(PalletType::eur, BeltSurface::rubber_belt, 3.0, 0.0));
    QVERIFY(r.ok());
    QCOMPARE(r->belt_pallet.penalty, 0.65);
    QCOMPARE(r->item_pallet.penalty, 0.65);
    QCOMPARE(r->item_item.penalty, 0.65);
    QCOMPARE(r->item_item.mu_s, 0.65 * steady("carton/carton", 3.0).mu_s);
  }

  void chepOnSteelRollerHasNoData() {
    const auto r = model().for_pallet(pallet(PalletType::chep, BeltSurface::steel_roller));
    QVERIFY(!r.ok());
    QCOMPARE(r.diagnostics.size(), std::size_t{1});
    QCOMPARE(q(r.diagnostics[0].pointer), QStringLiteral("/belt_surface"));
    QCOMPARE(q(r.diagnostics[0].message),
             QStringLiteral("plastic_pallet on steel_roller has no friction data; use belt_surface "
                            "rubber_belt, or add the pair plastic_pallet/steel_roller to "
                            "resources/friction_table.json"));
  }

  void missingItemPairsNameTheAlternatives() {
    Json table = valid_table();
    table["surface_pairs"]["plastic_pallet/rubber_belt"] = table["surface_pairs"]["carton/carton"];
    table["surface_pairs"]["carton/wood_pallet"] = table["surface_pairs"]["carton/carton"];
    auto custom = FrictionModel::from_json_text(table.dump());
    QVERIFY(custom.ok());
    auto r = custom->for_pallet(pallet(PalletType::chep, BeltSurface::rubber_belt));
    QVERIFY(!r.ok());
    QCOMPARE(describe(r.diagnostics),
             QStringLiteral("/base_pallet_type: cartons on plastic_pallet have no friction data; "
                            "use base_pallet_type EUR or GMA, or add the pair "
                            "carton/plastic_pallet to resources/friction_items.json"));

    table["surface_pairs"].erase("carton/carton");
    custom = FrictionModel::from_json_text(table.dump());
    QVERIFY(custom.ok());
    r = custom->for_pallet(pallet(PalletType::eur, BeltSurface::steel_roller));
    QCOMPARE(describe(r.diagnostics),
             QStringLiteral("/belt_surface: wood_pallet on steel_roller has no friction data; "
                            "add the pair wood_pallet/steel_roller to "
                            "resources/friction_table.json; "
                            "(document): cartons on cartons have no friction data; add the pair "
                            "carton/carton to resources/friction_items.json"));
  }

  void forPalletRejectsNonFiniteState() {
    auto r = model().for_pallet(pallet(PalletType::eur, BeltSurface::rubber_belt, std::nan("")));
    QVERIFY(!r.ok());
    QCOMPARE(r.diagnostics.size(), std::size_t{1});
    QCOMPARE(q(r.diagnostics[0].pointer), QStringLiteral("/body_temp_c"));
    r = model().for_pallet(pallet(PalletType::eur, BeltSurface::rubber_belt, 3.0, -1.0));
    QVERIFY(!r.ok());
    QCOMPARE(r.diagnostics.size(), std::size_t{1});
    QCOMPARE(q(r.diagnostics[0].pointer), QStringLiteral("/seconds_since_temp_change"));
  }

  void validTableReads() {
    const auto r = FrictionModel::from_json_text(valid_table().dump());
    QVERIFY2(r.ok(), qPrintable(describe(r.diagnostics)));
    QVERIFY(r.diagnostics.empty());
    const SurfacePair* pair = r->find("carton/carton");
    QVERIFY(pair != nullptr);
    QCOMPARE(q(pair->description), QStringLiteral("case on case"));
    QCOMPARE(q(pair->source), QStringLiteral("made up"));
    QCOMPARE(pair->points.size(), std::size_t{3});
    QCOMPARE(pair->points[2].temp_c, 10.0);
    QCOMPARE(pair->points[2].mu_d, 0.40);
  }

  void malformedTablesPointAtTheProblem() {
    const std::string pts = "/surface_pairs/carton~1carton/control_points";
    struct Case {
      const char* name;
      std::string text;
      std::string pointer;
    };
    std::vector<Case> cases;
    auto mutate = [&](const char* name, std::string pointer, auto change) {
      Json table = valid_table();
      change(table);
      cases.push_back({name, table.dump(), std::move(pointer)});
    };
    cases.push_back({"syntax error", R"({"surface_pairs": {)", ""});
    cases.push_back({"not an object", "[1, 2]", ""});
    mutate("no surface_pairs", "/surface_pairs", [](Json& t) { t.erase("surface_pairs"); });
    mutate("surface_pairs array", "/surface_pairs", [](Json& t) { t["surface_pairs"] = {1}; });
    mutate("key without slash", "/surface_pairs/cartoncarton", [](Json& t) {
      t["surface_pairs"]["cartoncarton"] = t["surface_pairs"]["carton/carton"];
      t["surface_pairs"].erase("carton/carton");
    });
    mutate("key with two slashes", "/surface_pairs/a~1b~1c", [](Json& t) {
      t["surface_pairs"]["a/b/c"] = t["surface_pairs"]["carton/carton"];
      t["surface_pairs"].erase("carton/carton");
    });
    mutate("pair not an object", "/surface_pairs/carton~1carton",
           [](Json& t) { t["surface_pairs"]["carton/carton"] = 0.4; });
    mutate("description not a string", "/surface_pairs/carton~1carton/description",
           [](Json& t) { t["surface_pairs"]["carton/carton"]["description"] = 3; });
    mutate("no control points", "/surface_pairs/carton~1carton/control_points",
           [](Json& t) { t["surface_pairs"]["carton/carton"].erase("control_points"); });
    mutate("empty control points", pts, [](Json& t) { points_of(t) = Json::array(); });
    mutate("point not an object", pts + "/0", [](Json& t) { points_of(t)[0] = 0.4; });
    mutate("missing mu_s", pts + "/1/mu_s", [](Json& t) { points_of(t)[1].erase("mu_s"); });
    mutate("mu_s a string", pts + "/2/mu_s", [](Json& t) { points_of(t)[2]["mu_s"] = "0.4"; });
    mutate("mu_s above 2", pts + "/2/mu_s", [](Json& t) { points_of(t)[2]["mu_s"] = 2.5; });
    mutate("mu_d negative", pts + "/0/mu_d", [](Json& t) { points_of(t)[0]["mu_d"] = -0.1; });
    mutate("mu_d above mu_s", pts + "/1/mu_d", [](Json& t) { points_of(t)[1]["mu_d"] = 0.36; });
    mutate("temp_c repeated", pts + "/1/temp_c",
           [](Json& t) { points_of(t)[1]["temp_c"] = -10.0; });
    mutate("temp_c decreasing", pts + "/2/temp_c",
           [](Json& t) { points_of(t)[2]["temp_c"] = -5.0; });
    mutate("temp_c missing", pts + "/0/temp_c", [](Json& t) { points_of(t)[0].erase("temp_c"); });
    mutate("penalty not an object", "/transition_penalty",
           [](Json& t) { t["transition_penalty"] = Json::array(); });
    mutate("zone reversed", "/transition_penalty/danger_zone_temp_c", [](Json& t) {
      t["transition_penalty"]["danger_zone_temp_c"] = {8.0, -2.0};
    });
    mutate("zone empty", "/transition_penalty/danger_zone_temp_c", [](Json& t) {
      t["transition_penalty"]["danger_zone_temp_c"] = {3.0, 3.0};
    });
    mutate("zone one number", "/transition_penalty/danger_zone_temp_c",
           [](Json& t) { t["transition_penalty"]["danger_zone_temp_c"] = {3.0}; });
    mutate("min_multiplier 0", "/transition_penalty/min_multiplier",
           [](Json& t) { t["transition_penalty"]["min_multiplier"] = 0.0; });
    mutate("min_multiplier above 1", "/transition_penalty/min_multiplier",
           [](Json& t) { t["transition_penalty"]["min_multiplier"] = 1.2; });
    mutate("recovery 0", "/transition_penalty/recovery_seconds",
           [](Json& t) { t["transition_penalty"]["recovery_seconds"] = 0.0; });
    mutate("recovery missing", "/transition_penalty/recovery_seconds",
           [](Json& t) { t["transition_penalty"].erase("recovery_seconds"); });

    for (const Case& c : cases) {
      const auto r = FrictionModel::from_json_text(c.text);
      QVERIFY2(!r.ok(), c.name);
      const Diagnostics errors = errors_of(r.diagnostics);
      QVERIFY2(errors.size() == 1, qPrintable(c.name + QStringLiteral(": ") + describe(errors)));
      QVERIFY2(errors[0].pointer == c.pointer,
               qPrintable(c.name + QStringLiteral(": ") + describe(errors)));
    }
  }

  void unknownKeysWarnCommentsDoNot() {
    Json table = valid_table();
    points_of(table)[0]["mu"] = 0.4;
    table["surface_pairs"]["carton/carton"]["_note"] = "ignored";
    const auto r = FrictionModel::from_json_text(table.dump());
    QVERIFY(r.ok());
    QCOMPARE(describe(r.diagnostics),
             QStringLiteral("warning: /surface_pairs/carton~1carton/control_points/0/mu: unknown "
                            "key 'mu' is ignored; remove it or fix its spelling"));
  }

  void mergingTables() {
    Json items = valid_table();
    items.erase("transition_penalty");
    auto r = FrictionModel::from_json_text(items.dump());
    QVERIFY(r.ok());
    QCOMPARE(r->penalty().recovery_s, 600.0);  // the reference's values until a table sets one

    Json belts = valid_table();
    belts["surface_pairs"]["wood_pallet/rubber_belt"] = belts["surface_pairs"]["carton/carton"];
    belts["surface_pairs"].erase("carton/carton");
    belts["transition_penalty"]["recovery_seconds"] = 900.0;
    QVERIFY(r->add_json_text(belts.dump()).empty());
    QCOMPARE(r->pair_keys().size(), std::size_t{2});
    QCOMPARE(r->penalty().recovery_s, 900.0);

    // The first penalty stays; a later one is reported and ignored.
    Json later = valid_table();
    later["surface_pairs"]["carton/wood_pallet"] = later["surface_pairs"]["carton/carton"];
    later["surface_pairs"].erase("carton/carton");
    Diagnostics d = r->add_json_text(later.dump());
    QCOMPARE(d.size(), std::size_t{1});
    QCOMPARE(d[0].severity, Severity::warning);
    QCOMPARE(q(d[0].pointer), QStringLiteral("/transition_penalty"));
    QCOMPARE(r->penalty().recovery_s, 900.0);
    QCOMPARE(r->pair_keys().size(), std::size_t{3});

    // A duplicate pair is an error and the table is not added at all.
    Json duplicate = valid_table();
    duplicate["surface_pairs"]["carton/plastic_pallet"] =
        duplicate["surface_pairs"]["carton/carton"];
    d = r->add_json_text(duplicate.dump());
    QVERIFY(has_errors(d));
    QCOMPARE(q(errors_of(d)[0].pointer), QStringLiteral("/surface_pairs/carton~1carton"));
    QCOMPARE(r->pair_keys().size(), std::size_t{3});
    QVERIFY(r->find("carton/plastic_pallet") == nullptr);
  }
};

QTEST_APPLESS_MAIN(FrictionTest)
#include "friction_test.moc"
