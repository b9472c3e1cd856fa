// SPDX-License-Identifier: MIT
// The preconditioned constraint solve against MuJoCo's own Newton solver run to convergence on the
// same constraint problem: an interlocked two-layer brick at rest, and the same brick with its
// cartons sliding over each other and the deck (contacts in the cone's middle zone, where the
// cone's Hessian enters the preconditioner), with MuJoCo's sparse Jacobian and its dense one, and
// in the pyramidal cone.
#include "core/physics/constraint_solver.hpp"

#include <QtTest>

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/physics/engine.hpp"
#include "core/physics/probe_run.hpp"
#include "tests/core/test_friction.hpp"
#include "tests/core/test_pallets.hpp"
#include "tests/core/test_rig.hpp"

using namespace pb;

namespace {

// Six 0.4 x 0.4 x 0.25 m cartons on the deck, four 0.6 x 0.4 x 0.25 m across them.
PalletConfig brick() {
  std::vector<Item> items;
  for (double x : {-0.4, 0.0, 0.4}) {
    for (double y : {-0.2, 0.2}) items.push_back(test::carton(x, y, 0.15, {0.4, 0.4, 0.25}, 12.0));
  }
  for (double x : {-0.3, 0.3}) {
    for (double y : {-0.2, 0.2}) items.push_back(test::carton(x, y, 0.40, {0.6, 0.4, 0.25}, 18.0));
  }
  return test::pallet(items);
}

struct Compared {
  double qacc_error = 0.0;   // |ours - converged| / |converged|
  double force_error = 0.0;  // max |ours - converged| / max |converged|
  int cone_contacts = 0;     // in the cone's middle zone at the converged answer
  int iterations = 0;
};

double norm(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x * x;
  return std::sqrt(s);
}

// The state of `d` solved by our solver (from qacc_smooth, no warm start) and by MuJoCo's Newton
// at tolerance 1e-14 on a copy of `m` with the same Jacobian layout.
Compared compare(const mjModel* m, mjData* d) {
  Compared out;
  ModelPtr newton(mj_copyModel(nullptr, m));
  newton->opt.solver = mjSOL_NEWTON;
  newton->opt.tolerance = 1e-14;
  newton->opt.iterations = 1000;
  auto nd = make_data(newton.get());
  if (!nd) return {1.0, 1.0, 0, 0};
  mjData* r = nd->get();
  mju_copy(r->qpos, d->qpos, m->nq);
  mju_copy(r->qvel, d->qvel, m->nv);
  mj_forward(newton.get(), r);
  out.cone_contacts =
      static_cast<int>(std::count(r->efc_state, r->efc_state + r->nefc, int(mjCNSTRSTATE_CONE)));

  mj_forward(m, d);  // the same constraint rows
  mju_copy(d->qacc_warmstart, d->qacc_smooth, m->nv);
  ConstraintSolver solver;
  solver.solve(m, d);
  out.iterations = d->solver_iter;
  std::vector<double> dq(m->nv), ref(r->qacc, r->qacc + m->nv);
  for (int i = 0; i < m->nv; ++i) dq[i] = d->qacc[i] - r->qacc[i];
  out.qacc_error = norm(dq) / norm(ref);
  double df = 0.0, fmax = 0.0;
  for (int i = 0; i < r->nefc; ++i) {
    df = std::max(df, std::abs(d->efc_force[i] - r->efc_force[i]));
    fmax = std::max(fmax, std::abs(r->efc_force[i]));
  }
  out.force_error = df / fmax;
  // qfrc_constraint is J' efc_force at the answer (what the step integrates).
  std::vector<double> jtf(m->nv);
  mj_mulJacTVec(m, d, jtf.data(), d->efc_force);
  for (int i = 0; i < m->nv; ++i) {
    if (std::abs(jtf[i] - d->qfrc_constraint[i]) > 1e-9 * (1.0 + std::abs(jtf[i]))) {
      out.force_error = 1.0;
    }
  }
  return out;
}

// The brick's cartons set sliding: each gets its own horizontal velocity and spin.
void set_sliding(const mjModel* m, mjData* d) {
  for (int j = 0, k = 0; j < m->njnt; ++j) {
    if (m->jnt_type[j] != mjJNT_FREE) continue;
    const int v = m->jnt_dofadr[j];
    d->qvel[v] += 0.15 * ((k % 3) - 1);
    d->qvel[v + 1] += 0.1 * ((k % 2) ? 1 : -1);
    d->qvel[v + 5] += 0.3 * ((k % 2) ? -1 : 1);
    ++k;
  }
}

}  // namespace

class ConstraintSolverTest : public QObject {
  Q_OBJECT

 private:
  test::Rig rig_ = test::settled_rig(brick(), test::constant_friction({1.0, 0.4, 0.5, 0.8}));

  void check(const mjModel* m, bool sliding, const char* what, bool elliptic = true) {
    auto data = make_data(m);
    QVERIFY(data.ok());
    mjData* d = data->get();
    load_rest_state(rig_.scene->layout, rig_.rest, 0.0, *d);
    if (sliding) set_sliding(m, d);
    const Compared c = compare(m, d);
    qInfo("%s: %d iterations, qacc %.1e and forces %.1e from converged Newton, %d cone rows", what,
          c.iterations, c.qacc_error, c.force_error, c.cone_contacts);
    QVERIFY(c.qacc_error < 1e-5);
    QVERIFY(c.force_error < 1e-4);
    if (sliding && elliptic) QVERIFY(c.cone_contacts > 0);
  }

 private slots:
  void initTestCase() { QVERIFY2(rig_.error.empty(), rig_.error.c_str()); }

  void reachesTheConvergedSolveAtRest() { check(rig_.scene->model.get(), false, "at rest"); }

  void reachesTheConvergedSolveWhileCartonsSlide() {
    check(rig_.scene->model.get(), true, "sliding");
  }

  void aDenseJacobianGivesTheSameSolve() {
    ModelPtr dense(mj_copyModel(nullptr, rig_.scene->model.get()));
    dense->opt.jacobian = mjJAC_DENSE;
    check(dense.get(), true, "sliding, dense Jacobian");
  }

  // The pyramid's rows are each a non-negative constraint of their own.
  void aPyramidalConeGivesTheSameSolve() {
    ModelPtr pyramid(mj_copyModel(nullptr, rig_.scene->model.get()));
    pyramid->opt.cone = mjCONE_PYRAMIDAL;
    check(pyramid.get(), true, "sliding, pyramidal cone", false);
  }

  // From its own answer the solve has nothing left to do.
  void aWarmStartAtTheAnswerStaysThere() {
    const mjModel* m = rig_.scene->model.get();
    auto data = make_data(m);
    QVERIFY(data.ok());
    mjData* d = data->get();
    load_rest_state(rig_.scene->layout, rig_.rest, 0.0, *d);
    set_sliding(m, d);
    mj_forward(m, d);
    ConstraintSolver solver;
    solver.solve(m, d);
    const std::vector<double> first(d->qacc, d->qacc + m->nv);
    solver.solve(m, d);
    QVERIFY(d->solver_iter <= 1);
    for (int i = 0; i < m->nv; ++i) {
      QVERIFY(std::abs(d->qacc[i] - first[i]) <= 1e-6 * (1.0 + std::abs(first[i])));
    }
    QCOMPARE(solver.fallbacks(), 0);
  }
};

QTEST_APPLESS_MAIN(ConstraintSolverTest)
#include "constraint_solver_test.moc"
