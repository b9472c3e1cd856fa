// SPDX-License-Identifier: MIT
// A state captured from a running simulation and restored into a fresh mjData continues the run
// bitwise; equality sees every array, the warnings and the time.
#include "core/physics/sim_state.hpp"

#include <QtTest>
#include <cstring>

#include "core/inputs/scenario.hpp"
#include "core/physics/engine.hpp"
#include "core/physics/scene.hpp"

using namespace pb;

class SimStateTest : public QObject {
  Q_OBJECT

 private slots:
  void restoredRunsContinueBitwise() {
    auto scenario = load_scenario("tall-unwrapped-tower");
    QVERIFY(scenario.ok());
    auto scene = build_scene(scenario->pallet);
    QVERIFY(scene.ok());
    const mjModel* m = scene->model.get();
    auto a = make_data(m);
    auto b = make_data(m);
    QVERIFY(a.ok() && b.ok());
    mjData* da = a.value->get();
    mjData* db = b.value->get();
    for (int k = 0; k < 50; ++k) mj_step(m, da);
    const SimState s = capture_state(*m, *da);
    QCOMPARE(s.qpos.size(), std::size_t(m->nq));
    QCOMPARE(s.xfrc_applied.size(), std::size_t(6 * m->nbody));
    QCOMPARE(s.time, da->time);
    restore_state(s, *db);
    QVERIFY(capture_state(*m, *db) == s);
    for (int k = 0; k < 50; ++k) {
      mj_step(m, da);
      mj_step(m, db);
    }
    QCOMPARE(std::memcmp(da->qpos, db->qpos, sizeof(mjtNum) * std::size_t(m->nq)), 0);
    QCOMPARE(std::memcmp(da->qvel, db->qvel, sizeof(mjtNum) * std::size_t(m->nv)), 0);
  }

  void equalitySeesEveryPart() {
    SimState a;
    a.qpos = {1.0, 2.0};
    a.userdata = {3.0};
    SimState b = a;
    QVERIFY(a == b);
    b.userdata[0] = 4.0;
    QVERIFY(!(a == b));
    b = a;
    b.time = 1.0;
    QVERIFY(!(a == b));
    b = a;
    b.warning[mjWARN_BADQACC].number = 1;
    QVERIFY(!(a == b));
  }
};

QTEST_APPLESS_MAIN(SimStateTest)
#include "sim_state_test.moc"
