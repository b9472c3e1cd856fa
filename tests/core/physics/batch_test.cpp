// SPDX-License-Identifier: MIT
// The batch against serial loops of pb::step (mj_step with Coulomb friction, step.hpp), bit for
// bit, on a real pallet scene (three cartons, explicit contact pairs, a velocity-driven belt):
// every thread count, subsets by ids and mask, resets, per-simulation controls and parameters; and
// the failure rules: a failing simulation is named (the lowest index), keeps its pre-call state,
// and does not stop the others.
#include "core/physics/batch.hpp"

#include <sys/resource.h>

#include <QtTest>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "core/inputs/scenario.hpp"
#include "core/physics/engine.hpp"
#include "core/physics/scene.hpp"
#include "core/physics/simulate.hpp"
#include "core/physics/step.hpp"

using namespace pb;

namespace {

constexpr int kSims = 5;

QString q(const std::string& s) {
  return QString::fromStdString(s);
}

Item carton(double x, double z) {
  Item item;
  item.sku = "BATCH";
  item.weight_kg = 12.0;
  item.dims_m = {0.4, 0.3, 0.25};
  item.position = {x, 0.0, z};
  return item;
}

// Two cartons side by side on the deck and one across them.
PalletConfig three_cartons() {
  PalletConfig config;
  config.pallet_id = "batch-test";
  config.items = {carton(-0.21, 0.15), carton(0.21, 0.15), carton(0.0, 0.40)};
  config.wrap = WrapType::none;
  return config;
}

// Each simulation's own belt profile: accelerate at 0.5 * (sim + 1) m/s^2 up to 1 m/s.
void drive(const SceneLayout& layout, int sim, const mjModel& m, mjData& d) {
  const double t = d.time + m.opt.timestep;
  d.ctrl[layout.belt_x_act] = std::min(1.0, 0.5 * (sim + 1) * t);
}

// The reference: one model copy and one mjData per simulation, stepped in a plain loop.
struct Serial {
  ModelPtr model;
  DataPtr data;
};

std::vector<Serial> serial_copies(const mjModel& model, int n) {
  std::vector<Serial> out;
  for (int i = 0; i < n; ++i) {
    ModelPtr m(mj_copyModel(nullptr, &model));
    DataPtr d(mj_makeData(m.get()));
    out.push_back({std::move(m), std::move(d)});
  }
  return out;
}

// An empty vector's data() may be null, and memcmp of a null pointer is undefined even for 0 bytes.
bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

// Bitwise, NaN included (operator== would call two NaN states different).
bool same_bits(const SimState& a, const SimState& b) {
  const std::vector<double> ta{a.time}, tb{b.time};
  return same_bits(ta, tb) && same_bits(a.qpos, b.qpos) && same_bits(a.qvel, b.qvel) &&
         same_bits(a.act, b.act) && same_bits(a.qacc_warmstart, b.qacc_warmstart) &&
         same_bits(a.ctrl, b.ctrl) && same_bits(a.qfrc_applied, b.qfrc_applied) &&
         same_bits(a.xfrc_applied, b.xfrc_applied) && same_bits(a.mocap_pos, b.mocap_pos) &&
         same_bits(a.mocap_quat, b.mocap_quat) && same_bits(a.userdata, b.userdata) &&
         std::memcmp(a.warning.data(), b.warning.data(), sizeof(a.warning)) == 0;
}

// ---- memory, measured in a child process (this executable with kMemoryChild) ----

constexpr const char* kMemoryChild = "--memory-child";
constexpr int kMemorySims = 4096;
const char* g_self = nullptr;  // argv[0]

long peak_rss_kb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss;  // kilobytes on Linux
}

long current_rss_kb() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
  }
  return -1;
}

// Settles a curated pallet, then makes kMemorySims simulations of it and steps each twice.
// Prints "peak_before peak_after rss_before rss_after state_bytes mjdata_bytes" (kB, kB, kB, kB,
// bytes per simulation state, bytes of one mjData) on stdout.
int memory_child() {
  auto scenario = load_scenario("stable-dairy-slab");
  if (!scenario) return 3;
  auto scene = build_scene(scenario->pallet);
  if (!scene) return 3;
  auto simulator = Simulator::create(*scene);
  if (!simulator) return 3;
  auto rest = simulator->settle();
  if (!rest) return 3;
  const mjModel& m = *scene->model;
  const long peak_before = peak_rss_kb(), rss_before = current_rss_kb();
  auto batch = Batch::create(m, kMemorySims, 2);
  if (!batch) return 4;
  SimState start = batch->reset_state();
  start.qpos = rest->state.qpos;
  start.qvel = rest->state.qvel;
  start.qacc_warmstart = rest->state.qacc_warmstart;
  if (batch->set_reset_state(start) || batch->reset() || batch->step({}, 2)) return 5;
  const long peak_after = peak_rss_kb(), rss_after = current_rss_kb();
  const long state_bytes = long(sizeof(double)) * (1 + m.nq + 3 * m.nv + m.na + m.nu + 6 * m.nbody +
                                                   7 * m.nmocap + m.nuserdata) +
                           long(sizeof(mjWarningStat)) * mjNWARNING;
  DataPtr one(mj_makeData(&m));
  const long mjdata_bytes = long(one->nbuffer) + long(one->nstack) * long(sizeof(mjtNum));
  std::printf("%ld %ld %ld %ld %ld %ld\n", peak_before, peak_after, rss_before, rss_after,
              state_bytes, mjdata_bytes);
  return 0;
}

}  // namespace

class BatchTest : public QObject {
  Q_OBJECT

 private:
  std::unique_ptr<Scene> scene_;

  const mjModel& model() const { return *scene_->model; }

  Batch make(int sims, int threads) const {
    auto batch = Batch::create(model(), sims, threads);
    if (!batch) qFatal("Batch::create failed: %s", batch.diagnostics.front().message.c_str());
    return std::move(*batch.value);
  }

  StepHooks belt_hooks() const {
    const SceneLayout* layout = &scene_->layout;
    return {[layout](int sim, const mjModel& m, mjData& d) { drive(*layout, sim, m, d); }, {}};
  }

  void check_lockstep(const Batch& batch, const std::vector<Serial>& ref, int call) const {
    for (int i = 0; i < batch.size(); ++i) {
      const auto& r = ref[std::size_t(i)];
      QVERIFY2(same_bits(batch.get_state(i), capture_state(*r.model, *r.data)),
               qPrintable(QString("simulation %1 differs after call %2").arg(i).arg(call)));
    }
  }

 private slots:
  void initTestCase() {
    auto scene = build_scene(three_cartons(), {}, FrictionModel::builtin());
    QVERIFY2(scene.ok(), scene.ok() ? "" : qPrintable(q(scene.diagnostics.front().message)));
    scene_ = std::make_unique<Scene>(std::move(*scene.value));
    QVERIFY(model().npair > 0);  // the scene's contacts are explicit pairs
  }

  void lockstep_with_serial_loops_data() {
    QTest::addColumn<int>("threads");
    QTest::addColumn<int>("nstep");
    for (int threads : {1, 2, 3}) {
      for (int nstep : {1, 3}) {
        QTest::addRow("threads %d nstep %d", threads, nstep) << threads << nstep;
      }
    }
  }

  // 24 calls mixing every feature; after each, every simulation equals its serial loop.
  void lockstep_with_serial_loops() {
    QFETCH(int, threads);
    QFETCH(int, nstep);
    Batch batch = make(kSims, threads);
    QCOMPARE(batch.threads(), threads);
    std::vector<Serial> ref = serial_copies(model(), kSims);

    // Per-simulation parameters: pair friction, one carton's mass, the timestep.
    const int top = scene_->layout.item_bodies.back();
    BatchView friction = *batch.expand("pair_friction");
    BatchView mass = *batch.expand("body_mass");
    BatchView timestep = *batch.expand("opt.timestep");
    QCOMPARE(friction.width, 5 * model().npair);
    QCOMPARE(mass.width, model().nbody);
    QCOMPARE(timestep.width, 1);
    for (int i = 0; i < kSims; ++i) {
      mjModel& m = *ref[std::size_t(i)].model;
      for (int k = 0; k < friction.width; ++k) {
        friction(i, k) *= 1.0 - 0.1 * i;
        m.pair_friction[k] = friction(i, k);
      }
      mass(i, top) *= 1.0 + 0.5 * i;
      m.body_mass[top] = mass(i, top);
      timestep(i, 0) = i % 2 == 0 ? 0.002 : 0.001;
      m.opt.timestep = timestep(i, 0);
    }

    const StepHooks hooks = belt_hooks();
    auto serial_step = [&](int i) {
      Serial& r = ref[std::size_t(i)];
      for (int k = 0; k < nstep; ++k) {
        drive(scene_->layout, i, *r.model, *r.data);
        pb::step(r.model.get(), r.data.get());
      }
    };
    const std::vector<int> ids{0, 2, 4};
    const std::vector<bool> mask{true, true, false, false, true};
    for (int call = 0; call < 24; ++call) {
      if (call == 8) {  // a reset of two simulations
        QVERIFY(!batch.reset(Selection::of_ids({1, 3})));
        for (int i : {1, 3})
          mj_resetData(ref[std::size_t(i)].model.get(), ref[std::size_t(i)].data.get());
      }
      if (call == 12) {  // a push written through a live view
        batch.view(StateField::qvel)(2, scene_->layout.item_dofs.back()) += 0.05;
        ref[2].data->qvel[scene_->layout.item_dofs.back()] += 0.05;
      }
      std::optional<BatchError> error;
      std::vector<int> stepped;
      if (call % 3 == 1) {
        error = batch.step(Selection::of_ids(ids), nstep, hooks);
        stepped = ids;
      } else if (call % 3 == 2) {
        error = batch.step(Selection::of_mask(mask), nstep, hooks);
        stepped = {0, 1, 4};
      } else {
        error = batch.step({}, nstep, hooks);
        stepped = {0, 1, 2, 3, 4};
      }
      QVERIFY2(!error, error ? qPrintable(q(error->message)) : "");
      for (int i : stepped) serial_step(i);
      check_lockstep(batch, ref, call);
      if (QTest::currentTestFailed()) return;
    }
    // The run moved things, and the parameters made the simulations differ.
    const SimState s0 = batch.get_state(0), s2 = batch.get_state(2), s4 = batch.get_state(4);
    QVERIFY(s0.qpos != std::vector<double>(model().qpos0, model().qpos0 + model().nq));
    QVERIFY(s0.qpos != s2.qpos);
    QVERIFY(s2.qpos != s4.qpos);
  }

  // Same profile, same timestep: only the expanded friction or mass makes sims 1 and 2 differ.
  void parameters_change_the_run() {
    Batch batch = make(3, 2);
    BatchView friction = *batch.expand("pair_friction");
    BatchView mass = *batch.expand("body_mass");
    for (int k = 0; k < friction.width; ++k) friction(1, k) *= 0.5;
    mass(2, scene_->layout.item_bodies.front()) *= 2.0;
    const SceneLayout* layout = &scene_->layout;
    const StepHooks same{[layout](int, const mjModel& m, mjData& d) { drive(*layout, 4, m, d); },
                         {}};
    QVERIFY(!batch.step({}, 200, same));
    const BatchView qpos = batch.view(StateField::qpos);
    const int x = scene_->layout.item_qpos.front();
    QVERIFY(qpos(0, x) != qpos(1, x));
    QVERIFY(qpos(0, x) != qpos(2, x));
    QCOMPARE(batch.get_state(0).time, 200 * model().opt.timestep);
  }

  // expand("body_mass"): gravity and contact loads use body_mass at every step, but MuJoCo 2.2
  // takes a simple body's inertia from dof_M0, a derived constant of mj_setConst. So until
  // set_const() a carton of twice the mass weighs twice as much and accelerates as before; after
  // it, it moves exactly half as far under the same push. Closed forms: contact load at rest m g;
  // in free flight x_n = F/m dt^2 n (n + 1) / 2 (semi-implicit Euler from rest).
  void heavier_body_behaves_heavier() {
    Batch batch = make(2, 2);
    const int top = scene_->layout.item_bodies.back();
    const int x = scene_->layout.item_qpos.back();
    BatchView mass = *batch.expand("body_mass");
    BatchView inertia = *batch.expand("body_inertia");
    const double m0 = model().body_mass[top];
    mass(1, top) = 2.0 * m0;
    for (int k = 0; k < 3; ++k) inertia(1, 3 * top + k) *= 2.0;

    // At rest on the two lower cartons: the sum of the top carton's contact normal forces.
    std::vector<double> load(2, 0.0);
    const StepHooks weigh{
        {}, [&load, top](int sim, const mjModel& m, const mjData& d) {
          double total = 0.0;
          for (int c = 0; c < d.ncon; ++c) {
            const mjContact& con = d.contact[c];
            if (m.geom_bodyid[con.geom1] != top && m.geom_bodyid[con.geom2] != top) {
              continue;
            }
            mjtNum force[6];
            mj_contactForce(&m, &d, c, force);
            total += std::abs(force[0] * con.frame[2]);
          }
          load[std::size_t(sim)] = total;
          return true;
        }};
    QVERIFY(!batch.step({}, 300, weigh));
    const double g = -model().opt.gravity[2];
    qInfo("top carton's contact load at rest: %.3f N at m, %.3f N at 2m; m g = %.3f N", load[0],
          load[1], m0 * g);
    QVERIFY2(std::abs(load[0] / (m0 * g) - 1.0) < 0.01, "load at m");
    QVERIFY2(std::abs(load[1] / (2.0 * m0 * g) - 1.0) < 0.01, "load at 2m");

    // Free flight: no gravity, the carton lifted clear of everything, then pushed along x.
    BatchView gravity = *batch.expand("opt.gravity");
    for (int i = 0; i < 2; ++i) {
      for (int k = 0; k < 3; ++k) gravity(i, k) = 0.0;
      SimState s = batch.get_state(i);
      s.qpos[std::size_t(x + 2)] += 0.5;
      std::fill(s.qvel.begin(), s.qvel.end(), 0.0);
      s.xfrc_applied[std::size_t(6 * top)] = 12.0;  // N
      QVERIFY(!batch.set_state(i, s));
    }
    const std::vector<SimState> lifted{batch.get_state(0), batch.get_state(1)};
    constexpr int kPush = 100;
    const double dt = model().opt.timestep;
    auto closed_form = [&](double kg) { return 12.0 / kg * dt * dt * kPush * (kPush + 1) / 2; };
    auto push = [&](int sim) {
      return batch.view(StateField::qpos)(sim, x) - lifted[std::size_t(sim)].qpos[std::size_t(x)];
    };
    QVERIFY(!batch.step({}, kPush));
    qInfo("pushed before set_const: %.9f m at m, %.9f m at 2m", push(0), push(1));
    QVERIFY(std::abs(push(0) / closed_form(m0) - 1.0) < 1e-9);
    QVERIFY(std::abs(push(1) / closed_form(m0) - 1.0) < 1e-9);  // the old inertia (dof_M0)

    QCOMPARE(batch.model().body_subtreemass[top], m0);
    QVERIFY(!batch.set_const());
    QCOMPARE(batch.expand("body_subtreemass")->operator()(1, top), 2.0 * m0);
    QCOMPARE(batch.expand("body_subtreemass")->operator()(0, top), m0);
    QCOMPARE(batch.model().body_subtreemass[top], m0);  // the batch's model is untouched
    for (int i = 0; i < 2; ++i) QVERIFY(!batch.set_state(i, lifted[std::size_t(i)]));
    QVERIFY(!batch.step({}, kPush));
    qInfo("pushed after set_const: %.9f m at m, %.9f m at 2m; closed form %.9f, %.9f", push(0),
          push(1), closed_form(m0), closed_form(2.0 * m0));
    QVERIFY(std::abs(push(0) / closed_form(m0) - 1.0) < 1e-9);
    QVERIFY(std::abs(push(1) / closed_form(2.0 * m0) - 1.0) < 1e-9);
  }

  // After set_const, each simulation steps bit for bit like a model copy given the same fields
  // and mj_setConst, contacts and belt included.
  void set_const_matches_mj_setConst_data() {
    QTest::addColumn<int>("threads");
    for (int threads : {1, 2, 3}) QTest::addRow("threads %d", threads) << threads;
  }
  void set_const_matches_mj_setConst() {
    QFETCH(int, threads);
    Batch batch = make(3, threads);
    std::vector<Serial> ref = serial_copies(model(), 3);
    const int top = scene_->layout.item_bodies.back();
    const int bottom = scene_->layout.item_bodies.front();
    BatchView mass = *batch.expand("body_mass");
    BatchView inertia = *batch.expand("body_inertia");
    auto scale = [&](int sim, int body, double factor) {
      mass(sim, body) *= factor;
      ref[std::size_t(sim)].model->body_mass[body] *= factor;
      for (int k = 0; k < 3; ++k) {
        inertia(sim, 3 * body + k) *= factor;
        ref[std::size_t(sim)].model->body_inertia[3 * body + k] *= factor;
      }
    };
    scale(1, top, 2.0);
    scale(2, bottom, 0.5);
    scale(2, top, 3.0);
    QVERIFY(!batch.set_const(Selection::of_ids({1, 2})));
    for (Serial& r : ref) {
      mj_setConst(r.model.get(), r.data.get());
      mj_resetData(r.model.get(), r.data.get());
    }
    const StepHooks hooks = belt_hooks();
    for (int call = 0; call < 5; ++call) {
      QVERIFY(!batch.step({}, 10, hooks));
      for (int i = 0; i < 3; ++i) {
        for (int k = 0; k < 10; ++k) {
          drive(scene_->layout, i, *ref[std::size_t(i)].model, *ref[std::size_t(i)].data);
          pb::step(ref[std::size_t(i)].model.get(), ref[std::size_t(i)].data.get());
        }
      }
      check_lockstep(batch, ref, call);
      if (QTest::currentTestFailed()) return;
    }
    QVERIFY(!same_bits(batch.get_state(0).qvel, batch.get_state(1).qvel));
  }

  void per_simulation_timestep_sets_time() {
    Batch batch = make(2, 2);
    BatchView timestep = *batch.expand("opt.timestep");
    timestep(1, 0) = 0.0005;
    QVERIFY(!batch.step({}, 4));
    QCOMPARE(batch.get_state(0).time, 4 * model().opt.timestep);
    QCOMPARE(batch.get_state(1).time, 4 * 0.0005);
    QCOMPARE(batch.model().opt.timestep, model().opt.timestep);  // the batch's copy is untouched
  }

  void expand_rules() {
    Batch batch = make(3, 1);
    BatchView first = *batch.expand("geom_friction");
    QCOMPARE(first.width, 3 * model().ngeom);
    QCOMPARE(first.sims, 3);
    for (int i = 0; i < 3; ++i) {
      for (int k = 0; k < first.width; ++k) QCOMPARE(first(i, k), model().geom_friction[k]);
    }
    BatchView gravity = *batch.expand("opt.gravity");
    QCOMPARE(gravity.width, 3);
    QCOMPARE(gravity(2, 2), model().opt.gravity[2]);
    QCOMPARE(batch.expand("geom_friction")->data, first.data);  // the same view again

    auto unknown = batch.expand("geom_frictions");
    QVERIFY(!unknown.ok());
    QCOMPARE(unknown.diagnostics.front().message,
             std::string("the model has no field \"geom_frictions\": give an mjModel array "
                         "(\"geom_friction\") or an option (\"opt.timestep\")"));
    auto integer = batch.expand("opt.integrator");
    QVERIFY(!integer.ok());
    QCOMPARE(integer.diagnostics.front().message,
             std::string("the field \"opt.integrator\" is not of type mjtNum: only real-valued "
                         "fields can vary per simulation"));
    QVERIFY(!batch.expand("body_parentid").ok());
  }

  // Views, get_state, set_state and the reset state.
  void states_and_views() {
    Batch batch = make(3, 2);
    const SimState initial = batch.reset_state();
    QCOMPARE(initial.qpos, std::vector<double>(model().qpos0, model().qpos0 + model().nq));
    QCOMPARE(initial.qvel, std::vector<double>(std::size_t(model().nv), 0.0));
    QVERIFY(batch.get_state(2) == initial);

    QVERIFY(!batch.step(Selection::of_ids({1}), 10, belt_hooks()));
    const SimState moved = batch.get_state(1);
    QCOMPARE(moved.time, 10 * model().opt.timestep);
    const BatchView qpos = batch.view(StateField::qpos);
    QCOMPARE(qpos.width, model().nq);
    QCOMPARE(qpos.sims, 3);
    for (int k = 0; k < model().nq; ++k) QCOMPARE(qpos(1, k), moved.qpos[std::size_t(k)]);
    QCOMPARE(batch.view(StateField::time)(1, 0), moved.time);
    QCOMPARE(batch.view(StateField::xfrc_applied).width, 6 * model().nbody);

    // Sim 0 continues from sim 1's state exactly as another batch started from it does.
    QVERIFY(!batch.set_state(0, moved));
    QVERIFY(!batch.step(Selection::of_ids({0, 1}), 5, belt_hooks()));
    Batch twin = make(2, 1);
    QVERIFY(!twin.set_state(0, moved));
    QVERIFY(!twin.step(Selection::of_ids({0}), 5, belt_hooks()));
    QVERIFY(same_bits(batch.get_state(0), twin.get_state(0)));

    // A settled-like reset state: reset() restores it.
    SimState rest = batch.reset_state();
    rest.qpos = moved.qpos;
    rest.qacc_warmstart = moved.qacc_warmstart;
    QVERIFY(!batch.set_reset_state(rest));
    QVERIFY(!batch.reset(Selection::of_mask({false, true, true})));
    QVERIFY(batch.get_state(1) == rest);
    QVERIFY(batch.get_state(2) == rest);
    QVERIFY(!(batch.get_state(0) == rest));

    SimState wrong = rest;
    wrong.qvel.pop_back();
    auto error = batch.set_state(0, wrong);
    QVERIFY(error);
    QCOMPARE(error->sim, -1);
    QCOMPARE(error->message, "the state's qvel has " + std::to_string(model().nv - 1) +
                                 " values but the model needs " + std::to_string(model().nv) +
                                 ": start from get_state or reset_state");
    QVERIFY(batch.set_reset_state(wrong));
    QVERIFY(batch.reset_state() == rest);
    QCOMPARE(batch.set_state(3, rest)->message,
             std::string("simulation 3 is outside [0, 3): give a simulation of the batch"));
  }

  void invalid_calls_run_nothing() {
    Batch batch = make(4, 2);
    auto check = [&](std::optional<BatchError> error, const std::string& message) {
      QVERIFY(error);
      QCOMPARE(error->sim, -1);
      QVERIFY(error->failed.empty());
      QCOMPARE(error->message, message);
    };
    const std::string ids = "give sorted unique ids";
    check(batch.step(Selection::of_ids({2, 1})),
          "simulation id 1 is out of order, repeated or outside [0, 4): " + ids);
    check(batch.step(Selection::of_ids({1, 1})),
          "simulation id 1 is out of order, repeated or outside [0, 4): " + ids);
    check(batch.step(Selection::of_ids({0, 4})),
          "simulation id 4 is out of order, repeated or outside [0, 4): " + ids);
    check(batch.reset(Selection::of_ids({-1})),
          "simulation id -1 is out of order, repeated or outside [0, 4): " + ids);
    check(batch.step(Selection::of_mask({true, false, true})),
          "the mask has 3 flags but the batch has 4 simulations: give one flag per simulation");
    check(batch.step({}, -1), "nstep must be >= 0, not -1");
    for (int i = 0; i < 4; ++i) QCOMPARE(batch.get_state(i).time, 0.0);
    QVERIFY(!batch.step(Selection::of_ids({}), 3));  // an empty selection is a valid no-op
    QVERIFY(!batch.step({}, 0));
    for (int i = 0; i < 4; ++i) QCOMPARE(batch.get_state(i).time, 0.0);
  }

  void errors_are_isolated_data() {
    QTest::addColumn<int>("threads");
    for (int threads : {1, 2, 3}) QTest::addRow("threads %d", threads) << threads;
  }

  // Sims 3 and 1 diverge (NaN velocity); sim 2's hook raises an engine error on its third step.
  void errors_are_isolated() {
    QFETCH(int, threads);
    Batch batch = make(kSims, threads);
    std::vector<Serial> ref = serial_copies(model(), kSims);
    const StepHooks belt = belt_hooks();
    QVERIFY(!batch.step({}, 2, belt));
    for (int i = 0; i < kSims; ++i) {
      for (int k = 0; k < 2; ++k) {
        drive(scene_->layout, i, *ref[std::size_t(i)].model, *ref[std::size_t(i)].data);
        pb::step(ref[std::size_t(i)].model.get(), ref[std::size_t(i)].data.get());
      }
    }
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (int i : {3, 1}) batch.view(StateField::qvel)(i, scene_->layout.pallet_dof) = nan;
    std::vector<SimState> before;
    for (int i = 0; i < kSims; ++i) before.push_back(batch.get_state(i));

    const SceneLayout* layout = &scene_->layout;
    const StepHooks failing{[layout](int sim, const mjModel& m, mjData& d) {
                              if (sim == 2 && d.time > 3.5 * m.opt.timestep) mju_error("boom");
                              drive(*layout, sim, m, d);
                            },
                            {}};
    auto error = batch.step({}, 4, failing);
    QVERIFY(error);
    QCOMPARE(error->sim, 1);
    QCOMPARE(error->failed, (std::vector<int>{1, 2, 3}));
    // The reason is the engine's, for the same run in a serial loop.
    Serial diverged = std::move(serial_copies(model(), 1).front());
    mj_copyData(diverged.data.get(), diverged.model.get(), ref[1].data.get());
    diverged.data->qvel[scene_->layout.pallet_dof] = nan;
    pb::step(diverged.model.get(), diverged.data.get());
    QCOMPARE(q(error->message),
             q("simulation 1: " + *instability_reason(diverged.model.get(), diverged.data.get())));
    QVERIFY(q(error->message).startsWith("simulation 1: the velocities diverged"));
    for (int i : {1, 2, 3}) QVERIFY(same_bits(batch.get_state(i), before[std::size_t(i)]));
    for (int i : {0, 4}) {
      for (int k = 0; k < 4; ++k) {
        drive(scene_->layout, i, *ref[std::size_t(i)].model, *ref[std::size_t(i)].data);
        pb::step(ref[std::size_t(i)].model.get(), ref[std::size_t(i)].data.get());
      }
      QVERIFY(same_bits(batch.get_state(i),
                        capture_state(*ref[std::size_t(i)].model, *ref[std::size_t(i)].data)));
    }

    // Only the engine error left: it is named, with MuJoCo's message.
    QVERIFY(!batch.set_state(1, batch.reset_state()));
    QVERIFY(!batch.set_state(3, batch.reset_state()));
    error = batch.step(Selection::of_ids({1, 2, 3}), 4, failing);
    QVERIFY(error);
    QCOMPARE(error->sim, 2);
    QCOMPARE(error->message, std::string("simulation 2: MuJoCo error: boom"));
    QVERIFY(same_bits(batch.get_state(2), before[2]));

    // A hook that throws fails its simulation only.
    const StepHooks throwing{[](int sim, const mjModel&, mjData&) {
                               if (sim == 4) throw std::runtime_error("no profile");
                             },
                             {}};
    error = batch.step(Selection::of_ids({0, 4}), 1, throwing);
    QVERIFY(error);
    QCOMPARE(error->failed, std::vector<int>{4});
    QCOMPARE(error->message, std::string("simulation 4: a step hook threw: no profile"));

    // The workers that failed serve every simulation correctly afterwards.
    for (int i = 0; i < kSims; ++i) {
      QVERIFY(!batch.set_state(
          i, capture_state(*ref[std::size_t(i)].model, *ref[std::size_t(i)].data)));
    }
    for (int call = 0; call < 3; ++call) {
      QVERIFY(!batch.step({}, 2, belt));
      for (int i = 0; i < kSims; ++i) {
        for (int k = 0; k < 2; ++k) {
          drive(scene_->layout, i, *ref[std::size_t(i)].model, *ref[std::size_t(i)].data);
          pb::step(ref[std::size_t(i)].model.get(), ref[std::size_t(i)].data.get());
        }
      }
      check_lockstep(batch, ref, call);
    }
  }

  // A huge control is an instability too (MuJoCo zeroes it and warns).
  void huge_control_fails_its_simulation() {
    Batch batch = make(3, 2);
    const SceneLayout* layout = &scene_->layout;
    const StepHooks huge{[layout](int sim, const mjModel&, mjData& d) {
                           d.ctrl[layout->belt_x_act] = sim == 2 ? 1e12 : 0.1;
                         },
                         {}};
    auto error = batch.step({}, 2, huge);
    QVERIFY(error);
    QCOMPARE(error->failed, std::vector<int>{2});
    QVERIFY(q(error->message).startsWith("simulation 2: a control was NaN or huge"));
    QCOMPARE(batch.get_state(2).time, 0.0);
    QCOMPARE(batch.get_state(1).time, 2 * model().opt.timestep);
  }

  void observe_stops_one_simulation() {
    Batch batch = make(3, 3);
    const StepHooks hooks{{}, [](int sim, const mjModel&, const mjData&) { return sim != 1; }};
    QVERIFY(!batch.step({}, 3, hooks));
    const double dt = model().opt.timestep;
    QCOMPARE(batch.get_state(0).time, 3 * dt);
    QCOMPARE(batch.get_state(1).time, dt);
    QCOMPARE(batch.get_state(2).time, 3 * dt);
  }

  // Two threads calling one batch: the calls are serialised, none is lost.
  void concurrent_calls_are_serialised() {
    Batch batch = make(4, 2);
    std::atomic<int> errors{0};
    auto caller = [&] {
      for (int k = 0; k < 25; ++k) errors += batch.step({}, 1) ? 1 : 0;
    };
    std::thread a(caller), b(caller);
    a.join();
    b.join();
    QCOMPARE(errors.load(), 0);
    for (int i = 0; i < 4; ++i) QCOMPARE(batch.get_state(i).time, 50 * model().opt.timestep);
  }

  // 4096 simulations of a curated pallet (8 cartons) grow resident memory by < 256 MB: memory
  // follows threads, not simulations. Measured in a fresh process, so nothing else this test did
  // is counted. The same simulations with one mjData each would need the figure printed.
  void memory_follows_threads() {
    QVERIFY(g_self != nullptr);
    const std::string command = std::string("'") + g_self + "' " + kMemoryChild;
    FILE* child = popen(command.c_str(), "r");
    QVERIFY(child != nullptr);
    long peak0 = 0, peak1 = 0, rss0 = 0, rss1 = 0, state_bytes = 0, mjdata_bytes = 0;
    const int read = std::fscanf(child, "%ld %ld %ld %ld %ld %ld", &peak0, &peak1, &rss0, &rss1,
                                 &state_bytes, &mjdata_bytes);
    const int status = pclose(child);
    QCOMPARE(status, 0);
    QCOMPARE(read, 6);
    const double peak_mb = double(peak1 - peak0) / 1024.0;
    const double rss_mb = double(rss1 - rss0) / 1024.0;
    const double states_mb = double(kMemorySims) * double(state_bytes) / (1024.0 * 1024.0);
    const double naive_mb = double(kMemorySims) * double(mjdata_bytes) / (1024.0 * 1024.0);
    qInfo(
        "%d simulations: peak RSS +%.1f MB, RSS +%.1f MB (their states: %.1f MB; one mjData "
        "each would be %.0f MB)",
        kMemorySims, peak_mb, rss_mb, states_mb, naive_mb);
#if defined(__SANITIZE_THREAD__)
    // ThreadSanitizer shadows every byte with four and keeps its own allocator (measured: +210 MB
    // here against +42 MB in release): the 256 MB budget is the real build's.
    constexpr double kBudgetMb = 4 * 256.0;
#else
    constexpr double kBudgetMb = 256.0;
#endif
    QVERIFY2(peak_mb < kBudgetMb, qPrintable(QString("peak RSS grew %1 MB").arg(peak_mb)));
    QVERIFY2(rss_mb < kBudgetMb, qPrintable(QString("RSS grew %1 MB").arg(rss_mb)));
    // The measurement sees the batch: its states are resident.
    QVERIFY2(
        rss_mb >= 0.9 * states_mb,
        qPrintable(
            QString("RSS grew %1 MB, less than the states' %2 MB").arg(rss_mb).arg(states_mb)));
  }

  void create_rules() {
    const int cpus = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    QCOMPARE(make(64, 0).threads(), std::min(cpus, 64));
    QCOMPARE(make(1, 0).threads(), 1);
    QCOMPARE(make(2, 8).threads(), 2);
    QCOMPARE(make(2, 8).size(), 2);

    auto none = Batch::create(model(), 0);
    QVERIFY(!none.ok());
    QCOMPARE(none.diagnostics.front().message,
             std::string("a batch needs at least one simulation, not 0"));
    auto negative = Batch::create(model(), 2, -1);
    QVERIFY(!negative.ok());
    QCOMPARE(negative.diagnostics.front().message,
             std::string("the thread count must be >= 0 (0: every logical CPU), not -1"));
    ModelPtr noisy(mj_copyModel(nullptr, &model()));
    noisy->opt.enableflags |= mjENBL_SENSORNOISE;
    auto rejected = Batch::create(*noisy, 2);
    QVERIFY(!rejected.ok());
    QVERIFY(q(rejected.diagnostics.front().message).startsWith("sensor noise is enabled"));

    // The model is copied: later changes to the caller's model do not reach the batch.
    ModelPtr own(mj_copyModel(nullptr, &model()));
    Batch batch = std::move(*Batch::create(*own, 1, 1).value);
    own->opt.timestep = 0.01;
    QCOMPARE(batch.model().opt.timestep, model().opt.timestep);
  }
};

int main(int argc, char** argv) {
  if (argc == 2 && std::string(argv[1]) == kMemoryChild) return memory_child();
  g_self = argv[0];
  BatchTest test;
  QTEST_SET_MAIN_SOURCE_PATH
  return QTest::qExec(&test, argc, argv);
}
#include "batch_test.moc"
