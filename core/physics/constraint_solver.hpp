// SPDX-License-Identifier: MIT
// The constraint solve of a step (mj_fwdConstraint's part of it) by conjugate gradient
// preconditioned with the cost's own Hessian. MuJoCo's CG minimises the same convex cost (Gauss's
// plus each constraint's, in accelerations) but preconditions with the mass matrix alone, which
// knows nothing of the contacts: a stack's cartons are coupled through contacts far stiffer than
// their masses, so each iteration moves the load by one contact's worth and a large brick takes
// 50-240 iterations a step. Here the preconditioner is M + J' D J over the constraints active
// where the solve starts (with each cone contact's Hessian), factored once a step by a sparse
// Cholesky decomposition whose blocks are the bodies (BlockCholesky): the same minimum, reached in
// a handful of iterations. The constraints' states and forces are updated here too, as
// mj_constraintUpdate does, so that J v and J' f are taken block by block.
#pragma once

#include <mujoco/mujoco.h>

#include <memory>

namespace pb {

/// The MJCF custom numeric (value 1) by which a scene asks step() for this solve instead of
/// MuJoCo's CG (Solver::pcg).
inline constexpr const char* kPreconditionedCg = "pb_preconditioned_cg";
/// A model with fewer degrees of freedom is solved by MuJoCo's CG even so: a wrapped load's
/// reduced model (the pallet and the belt, 8) takes MuJoCo's CG a few iterations, and building
/// and factoring a preconditioner costs more than it saves (stable-dairy-slab's envelope 17 ->
/// 28 ms, random-scanner-feed's 25 -> 28). Three free bodies on the belt are 20.
inline constexpr int kPreconditionedCgMinDofs = 20;

/// Solves the constraints of one step, as mj_fwdConstraint does for the primal solvers: from the
/// better of the warm start and the unconstrained acceleration, it sets qacc, efc_force,
/// efc_state, qfrc_constraint, efc_b, qacc_warmstart and solver_iter, and stops by MuJoCo's rule
/// (an iteration's improvement or the gradient below opt.tolerance, scaled by the mean inertia
/// and the degrees of freedom; at most opt.iterations), here only once the preconditioner was
/// built at the current constraint states: it is built again when it is stale and an iteration
/// improves little, or every few iterations. It keeps between calls what depends only on the
/// model: the Hessian's sparsity pattern (every coupling the model's contact pairs and
/// equalities can make) and its fill-reducing ordering, so that a solve's answer depends on the
/// model and the data alone, bit for bit, whichever thread solves it after whatever else. One
/// per thread; several models may share it.
class ConstraintSolver {
 public:
  ConstraintSolver();
  ~ConstraintSolver();
  ConstraintSolver(const ConstraintSolver&) = delete;
  ConstraintSolver& operator=(const ConstraintSolver&) = delete;

  void solve(const mjModel* m, mjData* d);

  /// How often a Hessian pattern was analysed (a new model, or a solve with constraints its
  /// model's pairs do not predefine), and how often the preconditioner could not be
  /// factored (the solve then preconditions with the mass matrix, as MuJoCo's CG does).
  int analyses() const;
  int fallbacks() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The calling thread's solver (what step() uses).
ConstraintSolver& thread_constraint_solver();

}  // namespace pb
