// SPDX-License-Identifier: MIT
// One simulation step: MuJoCo's mj_step, stage by stage, with Coulomb friction that tells static
// from kinetic. MuJoCo 2.2's friction cone has one coefficient per contact; a load breaks loose at
// the static one and then slides at the kinetic one, 15-20 % lower in the tables, which sets how
// far it slides before a detector fires (a start-up ramp to v at a: v^2/2 (1/(mu_d g) - 1/a)).
#pragma once

#include <mujoco/mujoco.h>

namespace pb {

/// What step() keeps per contact pair in mjData::userdata (the scene sizes nuserdata to this
/// many per pair; the slots are part of the simulation state, sim_state.hpp): whether the pair
/// slides; how far it has slipped on its static cone since it last held; how much of its friction
/// cone it used in the last step (0..1); scratch; its normal force in the last solve that had
/// contacts of it (N: what its kinetic friction is computed from while it slides); its contacts'
/// mean slip when kinetic friction last acted on it (3: m/s, world axes).
inline constexpr int kFrictionStateSlots = 8;
/// The MJCF custom numeric (value 1) by which a scene asks for MuJoCo's own friction cone on
/// sliding pairs (SceneOptions::solver_kinetic_friction) instead of explicit Coulomb friction.
inline constexpr const char* kSolverKineticFriction = "pb_solver_kinetic_friction";
/// A pair whose contacts together use this much of their friction cone is on it: the solver holds
/// the friction force at its limit, so the pair slips rather than creeps. (The cone's own measure,
/// cone_use in step.cpp; a soft contact under a load inside the cone uses 0.95 at 0.31 g on a
/// 0.332 belt.)
inline constexpr double kConeSaturated = 0.98;
/// A pair breaks loose (kinetic friction from then on) once it has slipped this far (m) on its
/// static cone without a break: the critical slip distance of rate-and-state friction, set here by
/// what the soft contacts do rather than by the surfaces. A box-box contact set that loses a corner
/// for a step unloads a pallet on its belt, which then slips 0.1-0.2 mm on its cone before it holds
/// again (stable-dairy-slab in a 0.31 g curve, 93 % of its onset). Shorter lets such steps break
/// curves loose at 97 % of their onset (0.1 mm); longer delays a real breakaway, which slips on
/// the static cone for sqrt(2 D / (a - mu_s g)) first: at 0.25 mm a carton 1.1 m/s^2 above its
/// onset slides 7 % short of Coulomb's slide, 3 m/s^2 above it 2 % (step_test).
inline constexpr double kBreakLooseM = 0.00025;
/// A pair slips while a contact of it moves faster than this (m/s) past the other surface; a
/// sliding pair whose contacts all move slower sticks again. MuJoCo's soft contacts creep at up to
/// 1-2 mm/s under a sustained load inside the cone (MUJOCO_2_2_NOTES 3a).
inline constexpr double kStickMps = 0.002;

/// The horizontal acceleration field a load riding the belt is pushed by, where the step's caller
/// knows it (a curve: the belt's acceleration and the turning's centrifugal part,
/// turning_frame.hpp): a(p) = (ax, ay) + w2 (p - (cx, cy)) at a point p (world X, Y).
///
/// MuJoCo's pyramidal friction cone bounds |f_1| + |f_2| by mu N in its contact's two tangent
/// directions, which MuJoCo lays along the world axes for a level contact: Coulomb's mu N for a
/// demand along an axis (a start-up, a stop, a curve's centre line), 1 / (|cos t| + |sin t|) of it
/// for one t off them (5 % less at 3 degrees, 29 % at 45). A curve that turns the load pushes
/// off-centre masses a few degrees off the axes (stable-dairy-slab, its load 0.2 m behind the
/// pallet's centre on a 3 m curve: 3.4 degrees, which took its curve limit from 0.332 to 0.313 g).
/// With a field stated, step() turns each level contact's tangent directions about its normal so
/// the first lies along the field there, where the pyramid holds Coulomb's mu N. The field is kept
/// in mjData::userdata after the pairs' slots (the scene sizes nuserdata for it), so it travels
/// with the data and its captured states; all zero (as after the settle): none, and the contacts'
/// frames are MuJoCo's.
struct DemandField {
  double ax = 0.0, ay = 0.0;  ///< m/s^2 at the centre
  double w2 = 0.0;            ///< 1/s^2: the turning's omega^2
  double cx = 0.0, cy = 0.0;  ///< the centre, m
};
inline constexpr int kDemandFieldSlots = 5;
/// Writes `field` into `d` for the steps that follow (no effect on a model without the slots).
void set_demand_field(const mjModel* m, mjData* d, const DemandField& field);
/// A contact this close to level (|normal_z| at least this) is turned along a stated field; a
/// side contact between neighbours is pushed along its normal and keeps MuJoCo's frame.
inline constexpr double kLevelContactNz = 0.7;

/// qfrc += J' force for a world-frame `force` at the world point `at` on `body`, on the degrees of
/// freedom that move it: MuJoCo 2.2.2's mj_applyFT(m, d, force, {0, 0, 0}, at, body, qfrc) to the
/// bit (its sums in its order), without its dense 3 x nv Jacobians, except that mj_applyFT's zero
/// rows also turn a -0 in qfrc into +0 (step()'s kinetic friction does that once, before its
/// first force). Needs d's kinematics (cdof, subtree_com).
void apply_force(const mjModel* m, const mjData* d, const mjtNum force[3], const mjtNum at[3],
                 int body, mjtNum* qfrc);

/// True while a contact pair of the scene has broken loose (it slides at its kinetic coefficient
/// until it sticks again); false for a model without the pairs' slots.
bool any_pair_sliding(const mjModel* m, const mjData* d);
/// The most of its friction cone a contact pair of the scene used in the last step (0..1, 1 for a
/// pair that has broken loose; at kConeSaturated a pair slips towards breaking loose rather than
/// creeps); 0 for a model without the pairs' slots.
double max_cone_use(const mjModel* m, const mjData* d);
/// True while contact pair `pair` (the scene's order: kBeltPalletPair first) has broken loose and
/// no other pair has.
bool only_pair_sliding(const mjModel* m, const mjData* d, int pair);

/// mj_step for the Euler integrator (the only one the scenes use; any other is stepped by
/// mj_step itself), with Coulomb friction per contact pair: while a pair holds, its contacts are
/// MuJoCo's friction cones at the pair's static coefficient (friction[0]); once it has broken
/// loose, until it sticks again, its contacts enter the solve frictionless (condim 1) and its
/// kinetic friction (friction[2], which a condim-3 contact does not otherwise use) acts on them
/// explicitly: at each contact mu_d N_i against the contact's slip, N_i the pair's normal force in
/// the last solve shared among its contacts by how deep each sinks. MuJoCo's cone at mu_d instead
/// (the scene's kSolverKineticFriction) lets a sliding pallet hop on its belt: its soft sliding
/// contacts push the surfaces apart. A contact whose friction[4] does not name a pair (the
/// aftermath model's geom contacts) is left as MuJoCo made it. Level contacts' tangent directions
/// follow a stated DemandField. While no pair has broken loose and no field is stated the step is
/// mj_step's, bit for bit, unless the scene asks for our constraint solve (Solver::pcg,
/// kPreconditionedCg: then mj_fwdConstraint's part is constraint_solver.hpp's).
void step(const mjModel* m, mjData* d);

}  // namespace pb
