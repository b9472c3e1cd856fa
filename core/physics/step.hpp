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
/// cone it used in the last step (0..1); scratch.
inline constexpr int kFrictionStateSlots = 4;
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

/// mj_step for the Euler integrator (the only one the scenes use; any other is stepped by
/// mj_step itself), with each pair contact's sliding coefficient set between collision detection
/// and constraint construction: the pair's static coefficient (friction[0]) while it holds, its
/// kinetic one (friction[2], which a condim-3 contact does not otherwise use) once it has broken
/// loose, until it sticks again. A contact whose friction[4] does not name a pair (the aftermath
/// model's geom contacts) is left as MuJoCo made it. While no pair has broken loose the step is
/// mj_step's, bit for bit.
void step(const mjModel* m, mjData* d);

}  // namespace pb
