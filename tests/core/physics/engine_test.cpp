// SPDX-License-Identifier: MIT
#include "core/physics/engine.hpp"

#include <QtTest>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include <mujoco/mjxmacro.h>
#include <unistd.h>

using namespace pb;

namespace {

QString q(const std::string& s) {
  return QString::fromStdString(s);
}

// One free box above a ground plane; `size` is the MJCF <size> element (or nothing).
std::string box_on_plane(const std::string& size = "") {
  return "<mujoco>" + size +
         "<worldbody><geom name=\"floor\" type=\"plane\" size=\"1 1 0.1\"/>"
         "<body name=\"box\" pos=\"0 0 0.1\"><freejoint/>"
         "<geom type=\"box\" size=\"0.1 0.1 0.1\"/></body></worldbody></mujoco>";
}

// A fixed box (top face at z = 0) and a free box of the same footprint resting on it.
constexpr const char* kTwoBoxes =
    "<mujoco><worldbody>"
    "<geom name=\"lower\" type=\"box\" pos=\"0 0 -0.2\" size=\"0.3 0.2 0.2\"/>"
    "<body name=\"upper\" pos=\"0 0 0.1\"><freejoint/>"
    "<geom name=\"upper\" type=\"box\" size=\"0.3 0.2 0.1\"/></body>"
    "</worldbody></mujoco>";

ModelPtr compiled(const std::string& xml) {
  auto model = compile_mjcf(xml);
  if (!model) qFatal("the test model does not compile: %s", model.diagnostics[0].message.c_str());
  return std::move(*model.value);
}

// The process's resident set, kB.
long resident_kb() {
  std::ifstream statm("/proc/self/statm");
  long pages = 0, resident = 0;
  statm >> pages >> resident;
  return resident * (sysconf(_SC_PAGESIZE) / 1024);
}

DataPtr data_for(const mjModel* model) {
  auto data = make_data(model);
  if (!data) qFatal("no data for the test model: %s", data.diagnostics[0].message.c_str());
  return std::move(*data.value);
}

}  // namespace

class EngineTest : public QObject {
  Q_OBJECT

  mjfCollision builtin_box_box_ = nullptr;

  // The upper box of kTwoBoxes placed with its bottom face at `bottom_z` (0: face to face).
  struct Stacked {
    ModelPtr model;
    DataPtr data;
    int lower = -1, upper = -1;
  };
  Stacked stacked(double bottom_z) {
    Stacked s{compiled(kTwoBoxes), nullptr};
    s.data = data_for(s.model.get());
    s.data->qpos[2] = bottom_z + 0.1;
    mj_kinematics(s.model.get(), s.data.get());
    s.lower = mj_name2id(s.model.get(), mjOBJ_GEOM, "lower");
    s.upper = mj_name2id(s.model.get(), mjOBJ_GEOM, "upper");
    return s;
  }

 private slots:
  void initTestCase() {
    // Nothing in this process has touched MuJoCo yet: this is the built-in collider.
    builtin_box_box_ = mjCOLLISIONFUNC[mjGEOM_BOX][mjGEOM_BOX];
    QVERIFY(builtin_box_box_ != nullptr);
    init_engine();
  }

  void compilesAValidModel() {
    auto model = compile_mjcf(box_on_plane());
    QVERIFY2(model.ok(), model.ok() ? "" : model.diagnostics[0].message.c_str());
    QVERIFY(model.diagnostics.empty());
    QCOMPARE((*model)->nbody, 2);
    QCOMPARE((*model)->ngeom, 2);
    QCOMPARE((*model)->nq, 7);
    QCOMPARE(mj_name2id(model->get(), mjOBJ_BODY, "box"), 1);
    auto data = make_data(model->get());
    QVERIFY(data.ok());
    QVERIFY(data.diagnostics.empty());
    QCOMPARE((*data)->qpos[2], 0.1);
  }

  void brokenXmlIsAnErrorValue() {
    auto model = compile_mjcf("<mujoco><worldbody></mujoco>");
    QVERIFY(!model.ok());
    QCOMPARE(model.diagnostics.size(), std::size_t{1});
    const Diagnostic& d = model.diagnostics[0];
    QCOMPARE(d.pointer, std::string());
    QCOMPARE(d.severity, Severity::error);
    QVERIFY2(d.message.starts_with("MuJoCo could not compile the scene: "), d.message.c_str());
    QVERIFY2(d.message.find("XML") != std::string::npos, d.message.c_str());
  }

  void unknownElementIsAnErrorValue() {
    auto model = compile_mjcf("<mujoco><worldbody><cube/></worldbody></mujoco>");
    QVERIFY(!model.ok());
    QVERIFY2(model.diagnostics[0].message.find("cube") != std::string::npos,
             model.diagnostics[0].message.c_str());
  }

  // Empty text must be an error value like any other unusable text.
  void emptyTextIsAnErrorValue() {
    std::string escaped;
    std::optional<Result<ModelPtr>> model;
    try {
      model = compile_mjcf("");
    } catch (const EngineError& e) {
      escaped = e.what();
    }
    // Regression: MuJoCo raises mju_error("mj_makeEmptyFileVFS expects positive filesize") for
    // empty text; that EngineError must not leave the core (uncaught, it ends the process).
    QVERIFY2(escaped.empty(), escaped.c_str());
    QVERIFY(model.has_value() && !model->ok());
    QVERIFY2(model->diagnostics[0].message.find("empty") != std::string::npos,
             model->diagnostics[0].message.c_str());
  }

  // The compiler runs the pipeline once: a stack too small for it is MuJoCo's fatal
  // "Stack overflow" (its default handler would exit the process), here a value.
  void stackTooSmallToCompileIsAnErrorValue() {
    auto model = compile_mjcf(box_on_plane("<size nstack=\"1\"/>"));
    QVERIFY(!model.ok());
    QCOMPARE(model.diagnostics.size(), std::size_t{1});
    QVERIFY2(model.diagnostics[0].message.find("Stack overflow") != std::string::npos,
             model.diagnostics[0].message.c_str());
    // The process goes on and the engine still works.
    QVERIFY(compile_mjcf(box_on_plane("<size nstack=\"1000\"/>")).ok());
  }

  // A stack that cannot be allocated makes mj_makeData call mju_error (MuJoCo's allocator fails):
  // make_data returns it.
  void unallocatableDataIsAnErrorValue() {
    ModelPtr model = compiled(box_on_plane());
    model->nstack = -1000000;  // 8 * 2^64 - 8e6 bytes: malloc fails
    auto data = make_data(model.get());
    QVERIFY(!data.ok());
    QCOMPARE(data.diagnostics.size(), std::size_t{1});
    QCOMPARE(data.diagnostics[0].pointer, std::string());
    QCOMPARE(data.diagnostics[0].message, std::string("MuJoCo error: Could not allocate memory"));
  }

  // MuJoCo allocates through the engine's allocator (init_engine): blocks aligned as its own
  // (64 bytes), and one of tens of megabytes (a large load's mjData) on a huge page's boundary,
  // zeroed by mj_makeData as before; one that cannot be had is MuJoCo's error, as before.
  void largeBlocksAreAllocatedInHugePages() {
    init_engine();
    for (const std::size_t size : {std::size_t{1}, std::size_t{100}, std::size_t{40} << 20}) {
      void* block = mju_malloc(size);
      QVERIFY(block != nullptr);
      const auto address = reinterpret_cast<std::uintptr_t>(block);
      QCOMPARE(address % (size >= (std::size_t{32} << 20) ? std::size_t{2} << 20 : 64), 0u);
      std::memset(block, 1, size);  // all of it is ours
      mju_free(block);
    }
    ModelPtr model = compiled(box_on_plane("<size njmax=\"2000\"/>"));  // efc_AR 32 MB
    DataPtr data = data_for(model.get());
    QCOMPARE(data->efc_AR[std::size_t(model->njmax) * std::size_t(model->njmax) - 1], 0.0);
    QCOMPARE(guarded([] { mju_malloc(std::numeric_limits<std::size_t>::max() - 1); }).value_or(""),
             std::string("MuJoCo error: Could not allocate memory"));
  }

  // MuJoCo 2.2.2's mjData holds its dual solvers' njmax x njmax matrix and index (12 njmax^2
  // bytes) whatever the solver. Where the model solves primal, make_data maps that span onto one
  // shared block: it is not resident, the model steps as before, and reset_data is mj_resetData
  // outside the span, bit for bit.
  void theDualSolversMatrixIsSharedWhereNothingReadsIt() {
    ModelPtr model = compiled(box_on_plane("<size njmax=\"3000\"/>"));  // span 108 MB
    const std::size_t nj = std::size_t(model->njmax);
    const long before = resident_kb();
    DataPtr shared = data_for(model.get());
    const long grown_kb = resident_kb() - before;
    QVERIFY2(shared_data_bytes(shared.get()) > 12 * nj * nj - 2 * kSharedSpanBytes,
             qPrintable(QString::number(shared_data_bytes(shared.get()))));
    QVERIFY2(grown_kb < 20 * 1024, qPrintable(QString("grew by %1 kB").arg(grown_kb)));
    // One block, mapped again and again: what is written in it is 2 MB further on too.
    const std::size_t middle = nj * nj / 2, period = kSharedSpanBytes / sizeof(mjtNum);
    shared->efc_AR[middle] = 42.0;
    QCOMPARE(shared->efc_AR[middle + period], 42.0);

    // The same steps on data made without sharing (mj_makeData), then both reset.
    mjData* plain = mj_makeData(model.get());
    QCOMPARE(shared_data_bytes(plain), std::size_t{0});
    for (mjData* d : {shared.get(), plain}) {
      d->qvel[0] = 0.3;
      for (int i = 0; i < 50; ++i) mj_step(model.get(), d);
    }
    QCOMPARE(shared->qpos[0], plain->qpos[0]);
    QVERIFY(shared->qfrc_constraint[2] != 0.0);  // an array after the span, to be cleared
    reset_data(model.get(), shared.get());
    mj_resetData(model.get(), plain);
    QCOMPARE(shared->time, 0.0);
    int compared = 0;
    {
      const mjModel* m = model.get();
      MJDATA_POINTERS_PREAMBLE(m)
#define X(type, name, nr, nc)                                                                  \
  if (std::strcmp(#name, "efc_AR") != 0 && std::strcmp(#name, "efc_AR_colind") != 0) {         \
    ++compared;                                                                                \
    QVERIFY2(                                                                                  \
        std::memcmp(shared->name, plain->name, sizeof(type) * std::size_t(m->nr) * (nc)) == 0, \
        #name);                                                                                \
  }
      MJDATA_POINTERS
#undef X
    }
    QVERIFY(compared > 90);  // every array of mjData but the two (98 in 2.2.2)
    mj_deleteData(plain);
    shared.reset();

    // A dual solver reads the matrix: its data holds it.
    ModelPtr pgs = compiled(box_on_plane("<option solver=\"PGS\"/><size njmax=\"3000\"/>"));
    DataPtr held = data_for(pgs.get());
    QCOMPARE(shared_data_bytes(held.get()), std::size_t{0});
    held->efc_AR[middle] = 42.0;
    QCOMPARE(held->efc_AR[middle + period], 0.0);
  }

  // A stack overflow while stepping (mj_stackAlloc -> mju_error) unwinds to guarded().
  void stackOverflowWhileSteppingIsReturned() {
    ModelPtr model = compiled(box_on_plane());
    model->nstack = 5;  // enough to allocate, far too small for the pipeline
    DataPtr data = data_for(model.get());
    const auto error = guarded([&] { mj_forward(model.get(), data.get()); });
    QVERIFY(error.has_value());
    QCOMPARE(*error, std::string("MuJoCo error: Stack overflow"));
    // After the reset MuJoCo needs (it leaves its stack pointer raised), the next call fails the
    // same way again instead of running on a corrupted stack.
    mj_resetData(model.get(), data.get());
    QCOMPARE(guarded([&] { mj_forward(model.get(), data.get()); }).value_or(""),
             std::string("MuJoCo error: Stack overflow"));
  }

  void guardedReturnsNothingWithoutAnError() {
    int calls = 0;
    QCOMPARE(guarded([&] { ++calls; }), std::optional<std::string>());
    QCOMPARE(calls, 1);
  }

  void guardedReturnsTheEngineMessage() {
    QCOMPARE(guarded([] { mju_error_i("bad index %d", 7); }).value_or(""),
             std::string("MuJoCo error: bad index 7"));
  }

  // The error unwinds in the thread that raised it: the worker gets its message, the main
  // thread's concurrent guarded work is unaffected.
  void guardedWorksInAWorkerThread() {
    ModelPtr model = compiled(box_on_plane());
    model->nstack = 5;
    DataPtr worker_data = data_for(model.get());
    std::optional<std::string> worker_error;
    std::thread worker(
        [&] { worker_error = guarded([&] { mj_forward(model.get(), worker_data.get()); }); });
    ModelPtr good = compiled(box_on_plane());
    DataPtr main_data = data_for(good.get());
    const auto main_error = guarded([&] {
      for (int i = 0; i < 100; ++i) mj_step(good.get(), main_data.get());
    });
    worker.join();
    QCOMPARE(worker_error.value_or(""), std::string("MuJoCo error: Stack overflow"));
    QVERIFY2(!main_error, main_error.value_or("").c_str());
    QCOMPARE(main_data->time, 100 * good->opt.timestep);
  }

  void stableDataHasNoInstability() {
    ModelPtr model = compiled(box_on_plane());
    DataPtr data = data_for(model.get());
    for (int i = 0; i < 50; ++i) mj_step(model.get(), data.get());
    QCOMPARE(instability_reason(model.get(), data.get()), std::optional<std::string>());
  }

  void warningCountersAreInstabilities() {
    ModelPtr model = compiled(box_on_plane());
    DataPtr data = data_for(model.get());
    mj_forward(model.get(), data.get());
    data->warning[mjWARN_BADQACC].number = 1;
    // No time in the reason: after a divergence MuJoCo has already reset the clock.
    QCOMPARE(instability_reason(model.get(), data.get()).value_or(""),
             std::string("the accelerations diverged (NaN or > 1e10) and MuJoCo reset the "
                         "simulation (1 time(s))"));
    data->warning[mjWARN_BADQACC].number = 0;
    data->warning[mjWARN_CNSTRFULL].number = 3;
    QCOMPARE(instability_reason(model.get(), data.get()).value_or(""),
             std::string("the constraint buffer overflowed (njmax too small): constraints were "
                         "dropped (3 time(s))"));
  }

  void nonFiniteStateIsAnInstability() {
    ModelPtr model = compiled(box_on_plane());
    DataPtr data = data_for(model.get());
    data->qpos[2] = std::numeric_limits<double>::quiet_NaN();
    QCOMPARE(instability_reason(model.get(), data.get()).value_or(""),
             std::string("a position became non-finite"));
    data->qpos[2] = 0.1;
    data->qvel[5] = std::numeric_limits<double>::infinity();
    QCOMPARE(instability_reason(model.get(), data.get()).value_or(""),
             std::string("a velocity became non-finite"));
  }

  // A real overflow: a box on a plane makes 4 contacts; room for 1. MuJoCo only warns (counted
  // once per collision pass) and drops the rest; the text is recorded for this thread, not
  // printed.
  void contactBufferOverflowIsAnInstability() {
    ModelPtr model = compiled(box_on_plane("<size nconmax=\"1\"/>"));
    DataPtr data = data_for(model.get());
    mj_forward(model.get(), data.get());
    QCOMPARE(data->ncon, 1);
    QCOMPARE(instability_reason(model.get(), data.get()).value_or(""),
             std::string("the contact buffer overflowed (nconmax too small): contacts were "
                         "dropped (1 time(s))"));
    QVERIFY2(last_engine_warning().find("nconmax") != std::string::npos,
             last_engine_warning().c_str());
    std::string other_thread_warning = "unset";
    std::thread([&] { other_thread_warning = last_engine_warning(); }).join();
    QCOMPARE(other_thread_warning, std::string());
  }

  void boxBoxColliderIsWrappedOnce() {
    const mjfCollision installed = mjCOLLISIONFUNC[mjGEOM_BOX][mjGEOM_BOX];
    QVERIFY(installed != nullptr);
    QVERIFY(installed != builtin_box_box_);
    init_engine();  // a second call must not wrap the filter in itself
    QVERIFY(mjCOLLISIONFUNC[mjGEOM_BOX][mjGEOM_BOX] == installed);
    // Other pairs keep MuJoCo's colliders.
    QVERIFY(mjCOLLISIONFUNC[mjGEOM_PLANE][mjGEOM_BOX] != nullptr);
  }

  // Face-to-face boxes 1 mm into each other: real contacts, all kept, unchanged. (2.2.2 reports
  // this pair of identical footprints as 9 corner contacts of depth 0.5 mm.)
  void realBoxContactsAreKept() {
    Stacked s = stacked(-0.001);
    std::vector<mjContact> raw(mjMAXCONPAIR), kept(mjMAXCONPAIR);
    const int n_raw =
        builtin_box_box_(s.model.get(), s.data.get(), raw.data(), s.lower, s.upper, 0.0);
    QVERIFY(n_raw > 0);
    const long long dropped_before = phantom_contacts_dropped();
    const int n_kept = mjCOLLISIONFUNC[mjGEOM_BOX][mjGEOM_BOX](s.model.get(), s.data.get(),
                                                               kept.data(), s.lower, s.upper, 0.0);
    QCOMPARE(n_kept, n_raw);
    for (std::size_t i = 0; i < static_cast<std::size_t>(n_kept); ++i) {
      QVERIFY(kept[i].dist < 0.0);
      QVERIFY(kept[i].dist >= -kPhantomContactDepth);
      QCOMPARE(kept[i].dist, raw[i].dist);
      for (std::size_t k = 0; k < 3; ++k) QCOMPARE(kept[i].pos[k], raw[i].pos[k]);
    }
    QCOMPARE(phantom_contacts_dropped(), dropped_before);
  }

  // Boxes 5 cm into each other: every contact is deeper than the cut, so the filter drops all of
  // them and counts each one.
  void deepBoxContactsAreDroppedAndCounted() {
    Stacked s = stacked(-0.05);
    std::vector<mjContact> raw(mjMAXCONPAIR), kept(mjMAXCONPAIR);
    const int n_raw =
        builtin_box_box_(s.model.get(), s.data.get(), raw.data(), s.lower, s.upper, 0.0);
    QVERIFY(n_raw > 0);
    for (std::size_t i = 0; i < static_cast<std::size_t>(n_raw); ++i) {
      QVERIFY(raw[i].dist < -kPhantomContactDepth);
    }
    const long long dropped_before = phantom_contacts_dropped();
    const int n_kept = mjCOLLISIONFUNC[mjGEOM_BOX][mjGEOM_BOX](s.model.get(), s.data.get(),
                                                               kept.data(), s.lower, s.upper, 0.0);
    QCOMPARE(n_kept, 0);
    QCOMPARE(phantom_contacts_dropped(), dropped_before + n_raw);
    // The filter is in MuJoCo's pipeline: mj_forward keeps no box-box contact either.
    mj_forward(s.model.get(), s.data.get());
    QCOMPARE(s.data->ncon, 0);
    QCOMPARE(phantom_contacts_dropped(), dropped_before + 2 * n_raw);
  }

  // Two cartons of a 96-carton column's settle (bench scale's), face to face 0.03 mm into each
  // other (their poses as MuJoCo had them): 2.2.2's collider adds to their five real contacts one
  // 9.3 mm deep at the face's edge, shallower than the cut but far deeper than the boxes overlap
  // along its normal; it kicked the stack at 0.1 m/s. The filter drops it and keeps the others.
  void aContactDeeperThanItsBoxesOverlapIsDropped() {
    ModelPtr model = compiled(
        "<mujoco><worldbody>"
        "<body><freejoint/><geom name=\"lower\" type=\"box\" size=\"0.149625 0.124625 "
        "0.1\"/></body>"
        "<body><freejoint/><geom name=\"upper\" type=\"box\" size=\"0.149625 0.124625 "
        "0.1\"/></body>"
        "</worldbody></mujoco>");
    DataPtr data = data_for(model.get());
    mjData* d = data.get();
    mj_kinematics(model.get(), d);
    const int lower = mj_name2id(model.get(), mjOBJ_GEOM, "lower");
    const int upper = mj_name2id(model.get(), mjOBJ_GEOM, "upper");
    const double pos[2][3] = {{-0.4503716667114856, 0.25037031720081621, 1.0495334111850458},
                              {-0.45037062930652916, 0.2503687502890688, 1.2495045059104419}};
    const double mat[2][9] = {
        {0.99999999998784372, 2.1917768592840141e-09, 4.9307877950243727e-06,
         -2.155057481032511e-09, 0.99999999997227129, -7.4469597442378177e-06,
         -4.9307878112097222e-06, 7.4469597335211586e-06, 0.99999999996011502},
        {0.99999999998517441, 1.9084591142163983e-09, 5.4453221814071231e-06, -1.8636718575851e-09,
         0.99999999996617561, -8.2249048086264972e-06, -5.4453221969198319e-06,
         8.2249047983562634e-06, 0.99999999995134992}};
    for (int b = 0; b < 2; ++b) {
      const int g = b == 0 ? lower : upper;
      mju_copy(d->geom_xpos + 3 * g, pos[b], 3);
      mju_copy(d->geom_xmat + 9 * g, mat[b], 9);
    }
    std::vector<mjContact> raw(mjMAXCONPAIR), kept(mjMAXCONPAIR);
    const int n_raw = builtin_box_box_(model.get(), d, raw.data(), lower, upper, 0.0);
    int phantoms = 0;
    for (int i = 0; i < n_raw; ++i) {
      if (raw[i].dist < -1e-3) {
        ++phantoms;
        QVERIFY(raw[i].dist > -kPhantomContactDepth);  // the depth cut alone keeps it
      } else {
        QVERIFY(raw[i].dist > -1e-4);  // the real ones: 0.03 mm
      }
    }
    QCOMPARE(phantoms, 1);
    const long long dropped_before = phantom_contacts_dropped();
    const int n_kept =
        mjCOLLISIONFUNC[mjGEOM_BOX][mjGEOM_BOX](model.get(), d, kept.data(), lower, upper, 0.0);
    QCOMPARE(n_kept, n_raw - 1);
    for (int i = 0; i < n_kept; ++i) QVERIFY(kept[i].dist > -1e-4);
    QCOMPARE(phantom_contacts_dropped(), dropped_before + 1);
  }

  void droppedCounterNeverDecreases() {
    long long last = phantom_contacts_dropped();
    QVERIFY(last >= 0);
    for (const auto& [bottom, drops] : {std::pair{-0.001, false}, std::pair{-0.05, true},
                                        std::pair{0.0, false}, std::pair{-0.08, true}}) {
      Stacked s = stacked(bottom);
      mj_forward(s.model.get(), s.data.get());
      const long long now = phantom_contacts_dropped();
      QVERIFY2(now >= last, q(std::to_string(now) + " < " + std::to_string(last)).toUtf8());
      QCOMPARE(now > last, drops);
      last = now;
    }
  }
};

QTEST_APPLESS_MAIN(EngineTest)
#include "engine_test.moc"
