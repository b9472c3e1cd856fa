// SPDX-License-Identifier: MIT
#include "core/probe_run.hpp"

#include <QtTest>
#include <memory>
#include <optional>

#include "core/envelope.hpp"
#include "test_friction.hpp"
#include "test_pallets.hpp"

using namespace pb;

namespace {

struct Rig {
  std::unique_ptr<Scene> scene;
  std::optional<Simulator> sim;
  RestState rest;
};

std::unique_ptr<Rig> rig(const SceneOptions& options = {}) {
  auto scene = build_scene(test::pallet({test::carton(0.0, 0.0, 0.15)}), options,
                           test::constant_friction({1.0, 0.3, 0.4}));
  if (!scene) qFatal("scene");
  auto out = std::make_unique<Rig>();
  out->scene = std::make_unique<Scene>(std::move(*scene.value));
  auto sim = Simulator::create(*out->scene);
  if (!sim) qFatal("simulator");
  out->sim.emplace(std::move(*sim.value));
  auto rest = out->sim->settle();
  if (!rest) qFatal("settle");
  out->rest = std::move(*rest.value);
  return out;
}

// Steps a ProbeRun by hand on its own mjData, as a batch worker does.
SimResult by_hand(const Rig& r, const ConveyorProfile& profile, const SimOptions& o) {
  const mjModel& m = *r.scene->model;
  auto data = make_data(&m);
  if (!data) qFatal("data");
  mjData* d = data.value->get();
  ProbeRun run(*r.scene, r.rest, profile, o);
  load_rest_state(m, r.scene->layout, r.rest, run.initial_speed(), *d);
  while (!run.done()) {
    run.before_step(*d);
    mj_step(&m, d);
    if (!run.after_step(m, *d)) break;
  }
  return run.take_result();
}

}  // namespace

class ProbeRunTest : public QObject {
  Q_OBJECT

 private slots:
  // The state machine stepped by hand gives exactly the Simulator's run: failing, safe with an
  // early stop, and starting at speed (an e-stop).
  void byHandEqualsSimulator_data() {
    QTest::addColumn<double>("accel");
    QTest::addColumn<bool>("estop");
    QTest::newRow("slides") << 4.5 << false;
    QTest::newRow("safe, stops early") << 1.0 << false;
    QTest::newRow("e-stop from speed") << 4.0 << true;
  }
  void byHandEqualsSimulator() {
    QFETCH(double, accel);
    QFETCH(bool, estop);
    auto r = rig();
    const ConveyorProfile profile =
        estop ? decel_probe_profile(accel, 1.5, {}) : accel_probe_profile(accel, {});
    SimOptions o;
    const SimResult serial = r->sim->run(r->rest, profile, o);
    const SimResult hand = by_hand(*r, profile, o);
    QCOMPARE(hand.outcome, serial.outcome);
    QCOMPARE(hand.steps, serial.steps);
    QCOMPARE(hand.stopped_early, serial.stopped_early);
    QCOMPARE(bool(hand.failure), bool(serial.failure));
    if (serial.failure) QCOMPARE(hand.failure->time_s, serial.failure->time_s);
    QCOMPARE(hand.trace.size(), serial.trace.size());
    QCOMPARE(hand.trace.pallet(hand.trace.size() - 1).pos,
             serial.trace.pallet(serial.trace.size() - 1).pos);
  }

  void beltWatchNeedsThreeGrowingSteps() {
    BeltWatch w;
    QVERIFY(!w.check(0.06));
    QVERIFY(!w.check(0.07));
    QVERIFY(!w.check(0.01));  // shrank: the count restarts
    QVERIFY(!w.check(0.06));
    QVERIFY(!w.check(0.08));
    QVERIFY(w.check(0.10).has_value());
    BeltWatch small;
    for (double e : {0.01, 0.02, 0.03, 0.04}) QVERIFY(!small.check(e));  // below 5 cm/s
  }

  void divergingBeltIsUnstableNotAFailure() {
    SceneOptions options;
    options.belt_kv_ratio = 4.0;
    auto r = rig(options);
    const SimResult s = by_hand(*r, accel_probe_profile(1.0, {}), {});
    QCOMPARE(s.outcome, Outcome::unstable);
    QVERIFY(!s.failure);
    QVERIFY2(s.reason.find("belt") != std::string::npos, s.reason.c_str());
  }

  void relativeSpeedIsZeroAtRest() {
    auto r = rig();
    const mjModel& m = *r->scene->model;
    auto data = make_data(&m);
    QVERIFY(data);
    mjData* d = data.value->get();
    load_rest_state(m, r->scene->layout, r->rest, 1.5, *d);
    double spin = -1.0;
    QVERIFY(max_relative_speed(r->scene->layout, *d, 1.5, 0.0, &spin) < 0.01);
    QVERIFY(spin >= 0.0 && spin < 0.05);
    QVERIFY(std::abs(max_relative_speed(r->scene->layout, *d, 0.0, 0.0, nullptr) - 1.5) < 0.01);
  }
};

QTEST_APPLESS_MAIN(ProbeRunTest)
#include "probe_run_test.moc"
