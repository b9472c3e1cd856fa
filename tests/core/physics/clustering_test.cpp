// SPDX-License-Identifier: MIT
#include "core/physics/clustering.hpp"

#include <QtTest>
#include <cmath>
#include <numbers>

#include "core/analysis/analyzer.hpp"
#include "core/physics/scene.hpp"
#include "tests/core/test_friction.hpp"
#include "tests/core/test_pallets.hpp"

using namespace pb;

namespace {

// Grippy cartons on a grippy deck: a squat carton's onsets (slip mu g = 8.8 m/s^2, tip well above)
// are beyond 1.25 x 5 m/s^2; a 1 m tall 0.2 m carton tips at g 0.1 / 0.5 = 1.96 m/s^2.
constexpr test::ConstantMu kGrippy{0.5, 0.9, 0.9};

const FrictionModel& friction_model() {
  static const FrictionModel model = test::constant_friction(kGrippy);
  return model;
}

ContactFriction friction_of(const PalletConfig& config) {
  auto friction = friction_model().for_pallet(config);
  if (!friction) qFatal("the test friction table lacks a pair");
  return *friction.value;
}

// Deck: a squat carton (0) with a squat one on it (1); a tall narrow carton (2) with a squat one
// on it (3), turned 90 degrees on a carrier turned 90 degrees.
PalletConfig mixed_load() {
  using test::carton;
  return test::pallet({carton(-0.3, 0.0, 0.15, {0.4, 0.3, 0.1}, 12.0),
                       carton(-0.3, 0.0, 0.25, {0.4, 0.3, 0.1}, 8.0),
                       carton(0.3, 0.1, 0.15, {0.2, 0.2, 1.0}, 15.0, 90.0),
                       carton(0.3, 0.1, 1.15, {0.2, 0.2, 0.05}, 1.0, 90.0)});
}

}  // namespace

class ClusteringTest : public QObject {
  Q_OBJECT

 private slots:
  // Bottom-up: an item whose onsets all beat the margin joins the rigid body of what carries it
  // (the pallet's, or a free item's); an item that can tip stays free.
  void mergesOnlyItemsThatCannotMoveWithinReach() {
    const PalletConfig config = mixed_load();
    const Clustering c = cluster_items(config, friction_of(config), 5.0, 1.25);
    QCOMPARE(c.reach_mps2, 5.0);
    QCOMPARE(c.carrier[0], kOnPallet);
    QCOMPARE(c.carrier[1], 0);
    QCOMPARE(c.carrier[2], kFreeItem);  // tips at 1.96 m/s^2
    QCOMPARE(c.carrier[3], 2);          // rides on the free tall carton
    QCOMPARE(c.root(1), kOnPallet);
    QCOMPARE(c.root(3), 2);
    QCOMPARE(c.free_count(), 1);
    // A lower reach or margin merges no less; a higher one no more.
    QCOMPARE(cluster_items(config, friction_of(config), 8.0, 1.25).free_count(), 4);
  }

  // A wrapped load is the reduced rung's (its welds hold the items): nothing is clustered.
  void leavesWrappedLoadsAlone() {
    PalletConfig config = mixed_load();
    config.wrap = WrapType::stretch;
    QCOMPARE(cluster_items(config, friction_of(config), 5.0, 1.25).free_count(), 4);
  }

  // The scene merges what the clustering says: one free joint per free item, no contact pair
  // inside a rigid body, the exact composite mass, and every merged item exactly where the
  // pallet says it is (nested frames, yaw on yaw).
  void sceneMergesItemsIntoTheirCarriers() {
    const PalletConfig config = mixed_load();
    SceneOptions o;
    o.rigid_carrier = cluster_items(config, friction_of(config), 5.0, 1.25).carrier;
    auto scene = build_scene(config, o, friction_model());
    QVERIFY2(scene.ok(), scene.ok() ? "" : scene.diagnostics.front().message.c_str());
    const mjModel* m = scene->model.get();
    QCOMPARE(m->nv, 2 + 6 + 6);  // belt x, y; the pallet; item 2
    QCOMPARE(scene->layout.free_items, 1);
    QCOMPARE(scene->layout.item_dofs.size(), std::size_t{1});
    // belt/pallet, pallet/item 2, item 0 or 1 against item 2 (within 5 cm? no: 0.3 m apart),
    // item 3 against nothing but its carrier (merged): two pairs.
    QCOMPARE(m->npair, 2);
    const int p = scene->layout.pallet_body;
    QVERIFY(std::abs(m->body_subtreemass[p] - (25.0 + 12.0 + 8.0)) < 1e-9);
    const int tall = scene->layout.item_bodies[2];
    QVERIFY(std::abs(m->body_subtreemass[tall] - 16.0) < 1e-9);
    mjData* d = mj_makeData(m);
    mj_forward(m, d);
    for (std::size_t i = 0; i < config.items.size(); ++i) {
      const Item& item = config.items[i];
      const int b = scene->layout.item_bodies[i];
      const double expected[3] = {item.position[0], item.position[1],
                                  item.position[2] + item.dims_m[2] / 2};
      for (int k = 0; k < 3; ++k) QVERIFY(std::abs(d->xpos[3 * b + k] - expected[k]) < 1e-12);
      const double yaw = item.orientation_deg * std::numbers::pi / 180.0;
      QVERIFY(std::abs(std::abs(d->xquat[4 * b]) - std::cos(yaw / 2)) < 1e-12);
    }
    mj_deleteData(d);
  }

  // The Analyzer runs the clustered level only when asked, reports it, and drops the merged
  // items' mechanisms from the bounds it seeds from.
  void analyzerUsesTheLevelOnlyWhenAsked() {
    const PalletConfig config = mixed_load();
    Analyzer automatic({}, friction_model());
    auto a = automatic.prepare(config);
    QVERIFY(a.ok());
    QCOMPARE((*a.value)->fidelity.level, Fidelity::full);
    AnalyzerOptions options;
    options.fidelity = Fidelity::clustered;
    Analyzer clustered(options, friction_model());
    auto c = clustered.prepare(config);
    QVERIFY(c.ok());
    QCOMPARE((*c.value)->fidelity.level, Fidelity::clustered);
    for (const auto& mech : (*c.value)->bounds.along) QVERIFY(mech.item == -1 || mech.item == 2);
  }
};

QTEST_APPLESS_MAIN(ClusteringTest)
#include "clustering_test.moc"
