// SPDX-License-Identifier: MIT
#include "core/inputs/scenario.hpp"

#include <QtTest>

#include "core/contract/pallet_metrics.hpp"
#include "core/inputs/validation.hpp"

using namespace pb;

class ScenarioTest : public QObject {
  Q_OBJECT

 private slots:
  void sevenCuratedScenariosInOrder() {
    const std::vector<std::string> expected = {"stable-dairy-slab",        "frozen-meat-sprint",
                                               "tall-unwrapped-tower",     "top-heavy-surprise",
                                               "frozen-pallet-jerk-start", "asymmetric-load",
                                               "random-scanner-feed"};
    QCOMPARE(scenario_slugs(), expected);
    QCOMPARE(all_scenarios().size(), std::size_t{7});
  }

  void everyScenarioValidatesAndMatchesItsRecipe() {
    for (const Scenario& s : all_scenarios()) {
      const Diagnostics diags = validate(s.pallet);
      QVERIFY2(!has_errors(diags),
               (s.slug + ": " + (diags.empty() ? "" : to_string(diags[0]))).c_str());
      QVERIFY2(validate_profile(s.suggested_profile).empty(), s.slug.c_str());
      auto rebuilt = build_from_recipe(s);
      QVERIFY2(rebuilt.ok(), s.slug.c_str());
      QVERIFY2(*rebuilt.value == s.pallet,
               (s.slug + " differs from what its recipe builds").c_str());
    }
  }

  void frozenMeatCarriesAll24Cartons() {
    // The reference's grid sizing floored 1.2 / 0.4 to 2 and silently built 16 cartons (193 kg).
    for (const char* slug : {"frozen-meat-sprint", "frozen-pallet-jerk-start"}) {
      auto s = load_scenario(slug);
      QVERIFY(s.ok());
      QCOMPARE(s->pallet.items.size(), std::size_t{24});
      QCOMPARE(total_mass_kg(s->pallet), 25.0 + 24 * 10.5);
      QCOMPARE(s->pallet.env, Environment::frozen);
      QCOMPARE(s->pallet.body_temp_c, -25.0);
    }
    QCOMPARE(load_scenario("frozen-meat-sprint")->pallet.wrap, WrapType::stretch);
    QCOMPARE(load_scenario("frozen-pallet-jerk-start")->pallet.wrap, WrapType::none);
  }

  void curatedFactsHold() {
    auto tower = load_scenario("tall-unwrapped-tower");
    QCOMPARE(tower->pallet.items.size(), std::size_t{8});
    QCOMPARE(tower->pallet.wrap, WrapType::none);
    QVERIFY(qAbs(stack_height_m(tower->pallet) - (0.15 + 8 * 0.12)) < 1e-12);
    QCOMPARE(tower->suggested_profile.target_speed_mps, 2.0);
    QCOMPARE(tower->suggested_profile.accel_mps2, 5.0);  // the top of the analysed range
    auto slab = load_scenario("stable-dairy-slab");
    QCOMPARE(slab->pallet.items.size(), std::size_t{8});
    QCOMPARE(slab->pallet.wrap, WrapType::stretch);
    auto asym = load_scenario("asymmetric-load");
    QCOMPARE(asym->pallet.items.size(), std::size_t{6});
    QVERIFY(composite_com_m(asym->pallet)[0] > 0.05);  // the tall column sits forward of centre
    auto feed = load_scenario("random-scanner-feed");
    QCOMPARE(feed->pallet.env, Environment::transitioning);  // mid frost-melt, as curated
  }

  void unknownSlugListsTheKnownOnes() {
    auto s = load_scenario("nope");
    QVERIFY(!s.ok());
    QCOMPARE(s.diagnostics.size(), std::size_t{1});
    QVERIFY(s.diagnostics[0].message.find("stable-dairy-slab") != std::string::npos);
  }

  void jsonRoundTrip() {
    for (const Scenario& s : all_scenarios()) {
      const Json j = scenario_to_json(s);
      auto back = scenario_from_json(j);
      QVERIFY(back.ok());
      QCOMPARE(scenario_to_json(*back.value).dump(), j.dump());
    }
  }

  void malformedScenarioNamesTheField() {
    Json j = scenario_to_json(*load_scenario("stable-dairy-slab").value);
    j.erase("slug");
    j["pallet"]["wrap"] = "glue";
    auto s = scenario_from_json(j);
    QVERIFY(!s.ok());
    bool slug = false, wrap = false;
    for (const auto& d : s.diagnostics) {
      slug = slug || (d.pointer == "/slug" && d.message.find("'slug'") != std::string::npos);
      wrap = wrap || d.pointer == "/pallet/wrap";
    }
    QVERIFY(slug);
    QVERIFY(wrap);
  }
};

QTEST_APPLESS_MAIN(ScenarioTest)
#include "scenario_test.moc"
