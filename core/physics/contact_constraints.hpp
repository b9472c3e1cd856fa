// SPDX-License-Identifier: MIT
// MuJoCo's mj_makeConstraint for the scenes our own constraint solve steps (an unwrapped load:
// contacts only), bit for bit, less what only MuJoCo's solvers read. MuJoCo 2.2's version builds
// every contact's rows through dense nv-sized scratch, copies them row by row, and then transposes
// the sparse Jacobian and finds the supernodes of both, which constraint_solver.hpp never reads:
// 14-18 % of an unwrapped load's step (core/README.md, "The constraint rows, built here").
#pragma once

#include <mujoco/mujoco.h>

namespace pb {

/// Whether make_contact_constraints can build `m`'s constraints: a sparse Jacobian, the elliptic
/// cone, and no constraint but contacts (no active equality, joint or tendon limit, or dof or
/// tendon friction loss).
bool contact_constraints_apply(const mjModel* m);

/// For a model contact_constraints_apply accepts, after mj_collision: what mj_makeConstraint
/// computes (nefc, ne, nf, efc_J in MuJoCo's sparse layout and its row supernodes, efc_pos,
/// efc_margin, efc_frictionloss, efc_type, efc_id, efc_diagApprox, efc_R, efc_D, efc_KBIP, each
/// contact's efc_address, exclude and mu, maxuse_con and maxuse_efc), with the same floating-point
/// operations in the same order, but not efc_JT and its supernodes. Returns false, having changed
/// nothing, where a contact is not between simple bodies (of 12 degrees of freedom at most
/// together), has more than three dimensions or a mixed solref, or the rows would overflow njmax:
/// then call mj_makeConstraint (which warns).
bool make_contact_constraints(const mjModel* m, mjData* d);

}  // namespace pb
