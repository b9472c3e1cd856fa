// SPDX-License-Identifier: MIT
#include "core/physics/step.hpp"

#include "core/physics/constraint_solver.hpp"
#include "core/physics/contact_constraints.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

namespace pb {

namespace {

// The pair a contact belongs to (its index), or -1.
int pair_of(const mjModel* m, const mjContact& c) {
  if (c.dim != 3 && c.dim != 1) return -1;
  const double tag = c.friction[4];
  const int p = static_cast<int>(std::lround(tag)) - 1;
  if (p < 0 || p >= m->npair || std::abs(tag - double(p + 1)) > 1e-9) return -1;
  return p;
}

// Whether the scene asks for MuJoCo's friction cone on sliding pairs (kSolverKineticFriction).
bool solver_kinetic(const mjModel* m) {
  if (m->nnumeric == 0) return false;
  const int id = mj_name2id(m, mjOBJ_NUMERIC, kSolverKineticFriction);
  return id >= 0 && m->numeric_data[m->numeric_adr[id]] != 0.0;
}

// Whether the scene asks for our preconditioned CG (kPreconditionedCg), MuJoCo's is the model's
// solver and the model is large enough for it to pay.
bool preconditioned_cg(const mjModel* m) {
  if (m->nnumeric == 0 || m->opt.solver != mjSOL_CG || m->nv < kPreconditionedCgMinDofs) {
    return false;
  }
  const int id = mj_name2id(m, mjOBJ_NUMERIC, kPreconditionedCg);
  return id >= 0 && m->numeric_data[m->numeric_adr[id]] != 0.0;
}

// How the second body's surface slides past the first's at the contact (m/s, tangential).
void slip_velocity(const mjModel* m, const mjData* d, const mjContact& c, double out[3]) {
  double v[2][3];
  for (int k = 0; k < 2; ++k) {
    const int body = m->geom_bodyid[k == 0 ? c.geom1 : c.geom2];
    mjtNum vel[6];  // rotational, then linear, at the body frame's origin (xpos), world axes
    mj_objectVelocity(m, d, mjOBJ_XBODY, body, vel, 0);
    const mjtNum* o = d->xpos + 3 * body;
    const mjtNum r[3] = {c.pos[0] - o[0], c.pos[1] - o[1], c.pos[2] - o[2]};
    v[k][0] = vel[3] + vel[1] * r[2] - vel[2] * r[1];
    v[k][1] = vel[4] + vel[2] * r[0] - vel[0] * r[2];
    v[k][2] = vel[5] + vel[0] * r[1] - vel[1] * r[0];
  }
  const double rel[3] = {v[1][0] - v[0][0], v[1][1] - v[0][1], v[1][2] - v[0][2]};
  const mjtNum* n = c.frame;  // the first row is the normal
  const double along_n = rel[0] * n[0] + rel[1] * n[1] + rel[2] * n[2];
  for (int k = 0; k < 3; ++k) out[k] = rel[k] - along_n * n[k];
}

// How much of its friction cone a contact used in the last constraint solve, in the cone's own
// measure, with the contact's normal force: for the pyramid (rows n +- mu_i t_i; tangent force
// (f+ - f-) mu_i, normal force the sum of all rows) the sum over tangent directions of |f+ - f-|;
// for the ellipse the norm of t_i / mu_i. It reaches the normal force exactly when the solver
// holds the contact on the cone's surface. Returns {used, normal}.
std::pair<double, double> cone_use(const mjModel* m, const mjData* d, const mjContact& c) {
  if (c.efc_address < 0) return {0.0, 0.0};
  const mjtNum* f = d->efc_force + c.efc_address;
  if (c.dim == 1) return {f[0], f[0]};  // a sliding pair's contact: on its cone
  if (c.dim < 3) return {0.0, 0.0};
  if (m->opt.cone == mjCONE_PYRAMIDAL) {
    double used = 0.0, normal = 0.0;
    for (int i = 0; i < c.dim - 1; ++i) {
      used += std::abs(f[2 * i] - f[2 * i + 1]);
      normal += f[2 * i] + f[2 * i + 1];
    }
    return {used, normal};
  }
  double used = 0.0;
  for (int i = 1; i < c.dim; ++i) {
    const double t = c.friction[i - 1] > 0.0 ? f[i] / c.friction[i - 1] : 0.0;
    used += t * t;
  }
  return {std::sqrt(used), f[0]};
}

// A pair's slip or cone use when it had no contact to measure it on.
constexpr double kUnknown = -1.0;

// The per-pair slots of d->userdata (kFrictionStateSlots of them, npair each).
struct PairState {
  mjtNum* sliding;  // 1 once broken loose, until it sticks
  mjtNum* slipped;  // m slipped on the static cone since the pair last held
  mjtNum* use;      // how much of its cone the pair used in the last step
  mjtNum* scratch;
  mjtNum* load;  // N: the pair's normal force in the last solve that had contacts
  mjtNum* slip;  // 3 per pair: its contacts' mean slip (m/s) when kinetic friction last acted
};

std::optional<PairState> pair_state(const mjModel* m, mjData* d) {
  const int n = m->npair;
  if (n == 0 || m->nuserdata < kFrictionStateSlots * n) return std::nullopt;
  mjtNum* u = d->userdata;
  return PairState{u, u + n, u + 2 * n, u + 3 * n, u + 4 * n, u + 5 * n};
}

}  // namespace

bool any_pair_sliding(const mjModel* m, const mjData* d) {
  const int n = m->npair;
  if (n == 0 || m->nuserdata < kFrictionStateSlots * n) return false;
  // The sliding flags are the first of the pairs' slots (PairState).
  return std::any_of(d->userdata, d->userdata + n, [](mjtNum v) { return v != 0.0; });
}

double max_cone_use(const mjModel* m, const mjData* d) {
  const int n = m->npair;
  if (n == 0 || m->nuserdata < kFrictionStateSlots * n) return 0.0;
  if (any_pair_sliding(m, d)) return 1.0;
  const mjtNum* use = d->userdata + 2 * n;  // PairState::use (kUnknown, -1, without contacts)
  return std::max(0.0, *std::max_element(use, use + n));
}

bool only_pair_sliding(const mjModel* m, const mjData* d, int pair) {
  const int n = m->npair;
  if (pair < 0 || pair >= n || m->nuserdata < kFrictionStateSlots * n) return false;
  for (int p = 0; p < n; ++p) {
    if ((d->userdata[p] != 0.0) != (p == pair)) return false;
  }
  return true;
}

namespace {

// After the constraint solve: how much of its friction cone each pair used, over all its contacts
// together (one lightly loaded corner on its cone is not the pair slipping).
void record_cone_use(const mjModel* m, mjData* d) {
  const auto s = pair_state(m, d);
  if (!s) return;
  mjtNum* normal = s->scratch;
  std::fill(s->use, s->use + m->npair, 0.0);
  std::fill(normal, normal + m->npair, 0.0);
  for (int i = 0; i < d->ncon; ++i) {
    const int p = pair_of(m, d->contact[i]);
    if (p < 0) continue;
    const auto [used, n] = cone_use(m, d, d->contact[i]);
    s->use[p] += used;
    normal[p] += n;
  }
  for (int p = 0; p < m->npair; ++p) {
    s->use[p] = normal[p] > 0.0 ? s->use[p] / normal[p] : kUnknown;
    if (normal[p] > 0.0) s->load[p] = normal[p];
  }
}

// Between mj_collision and mj_makeConstraint: each pair's state from its contacts' slip and the
// last solve's cone use, then each of its contacts' sliding coefficient from that state.
void coulomb_friction(const mjModel* m, mjData* d) {
  const auto s = pair_state(m, d);
  if (!s) return;
  const bool solver = solver_kinetic(m);
  mjtNum* fastest = s->scratch;
  std::fill(fastest, fastest + m->npair, kUnknown);
  // Per sliding pair, how its contacts now slip along its slip when kinetic friction last acted
  // (negative: that friction stopped it within the step and turned it back).
  mjtNum* along = s->slipped;  // a sliding pair's slipped slot is unused
  bool velocities = false;
  for (int i = 0; i < d->ncon; ++i) {
    const int p = pair_of(m, d->contact[i]);
    if (p < 0) continue;
    // The slip matters only to a pair that slides or was on its cone; the others just hold.
    const bool sliding = s->sliding[p] != 0.0;
    const bool needed = sliding || s->use[p] >= kConeSaturated;
    if (needed && !velocities) {
      mj_comVel(m, d);  // this step's body velocities (mj_fwdVelocity computes them again)
      velocities = true;
    }
    double v[3] = {0.0, 0.0, 0.0};
    if (needed) slip_velocity(m, d, d->contact[i], v);
    fastest[p] = std::max(fastest[p], std::hypot(v[0], v[1], v[2]));
    if (sliding) {
      const mjtNum* was = s->slip + 3 * p;
      along[p] += v[0] * was[0] + v[1] * was[1] + v[2] * was[2];
    }
  }
  bool any_sliding = false;
  for (int p = 0; p < m->npair; ++p) {
    // A pair with no contact this step, or none in the last solve (a box-box contact set can be
    // empty for a step while a pallet slides on its belt), keeps its state.
    if (fastest[p] == kUnknown || s->use[p] == kUnknown) {
      any_sliding = any_sliding || s->sliding[p] != 0.0;
      if (s->sliding[p] != 0.0) s->slipped[p] = 0.0;
      continue;
    }
    const bool slips = fastest[p] > kStickMps;
    if (s->sliding[p] != 0.0) {
      // Explicit kinetic friction that turned the slip back has stopped it: the pair holds.
      const bool turned_back = !solver && along[p] < 0.0;
      if (!slips || turned_back) {
        s->sliding[p] = 0.0;
        s->slipped[p] = 0.0;  // it holds from here, on nothing slipped (along's sum is gone)
      }
    } else if (slips && s->use[p] >= kConeSaturated) {
      s->slipped[p] += fastest[p] * m->opt.timestep;
      if (s->slipped[p] >= kBreakLooseM) s->sliding[p] = 1.0;
    } else {
      s->slipped[p] = 0.0;
    }
    if (s->sliding[p] == 0.0) {
      std::fill(s->slip + 3 * p, s->slip + 3 * p + 3, 0.0);
      continue;
    }
    any_sliding = true;
    s->slipped[p] = 0.0;
  }
  if (!any_sliding) return;
  for (int i = 0; i < d->ncon; ++i) {
    mjContact& c = d->contact[i];
    const int p = pair_of(m, c);
    if (p < 0 || s->sliding[p] == 0.0) continue;
    if (solver) {
      c.friction[0] = c.friction[1] = c.friction[2];
    } else {
      c.dim = 1;
    }
  }
}

}  // namespace

// mj_applyFT (on a 70-carton brick whose cartons slide, 3 % of the run) builds the dense 3 x nv
// Jacobians and multiplies them out; here each dof's row of J' f is summed from zero over the
// force's nonzero components, added to qfrc, and the zero torque's row added after it.
void apply_force(const mjModel* m, const mjData* d, const mjtNum force[3], const mjtNum at[3],
                 int body, mjtNum* qfrc) {
  const mjtNum* com = d->subtree_com + 3 * m->body_rootid[body];
  const mjtNum offset[3] = {at[0] - com[0], at[1] - com[1], at[2] - com[2]};
  while (body != 0 && m->body_dofnum[body] == 0) body = m->body_parentid[body];
  if (body == 0) return;
  for (int da = m->body_dofadr[body] + m->body_dofnum[body] - 1; da >= 0;
       da = m->dof_parentid[da]) {
    const mjtNum* cdof = d->cdof + 6 * da;
    const mjtNum cross[3] = {cdof[1] * offset[2] - cdof[2] * offset[1],
                             cdof[2] * offset[0] - cdof[0] * offset[2],
                             cdof[0] * offset[1] - cdof[1] * offset[0]};
    mjtNum sum = 0.0;
    for (int k = 0; k < 3; ++k) {
      if (force[k] != 0.0) sum += (cdof[3 + k] + cross[k]) * force[k];
    }
    qfrc[da] += sum;
    qfrc[da] += 0.0;
  }
}

namespace {

// x + 0.0 for every dof's entry (a -0 becomes +0), as mj_applyFT's zero rows leave them.
void normalise_zeros(const mjModel* m, mjtNum* qfrc) {
  for (int i = 0; i < m->nv; ++i) qfrc[i] += 0.0;
}

// After mj_fwdVelocity: a sliding pair's contacts are frictionless in the solve (coulomb_friction
// made them dim 1) and Coulomb's kinetic friction acts on them here, explicitly: at each contact
// against its slip, mu_d times its share of the pair's normal force in the last solve (shared by
// how deep each contact sinks: a soft contact's force grows with its depth). The pair's mean slip
// is kept: should the friction turn it back within the step, the slip has stopped and the pair
// holds again (coulomb_friction), as a light carton under a heavy one does.
void kinetic_friction(const mjModel* m, mjData* d) {
  const auto s = pair_state(m, d);
  if (!s || !any_pair_sliding(m, d) || solver_kinetic(m)) return;
  auto sliding_contact = [&](const mjContact& c) { return c.dim == 1 ? pair_of(m, c) : -1; };
  mjtNum* depth = s->scratch;
  std::fill(depth, depth + m->npair, 0.0);
  for (int i = 0; i < d->ncon; ++i) {
    const int p = sliding_contact(d->contact[i]);
    if (p < 0) continue;
    depth[p] += std::max(-d->contact[i].dist, 0.0);
    std::fill(s->slip + 3 * p, s->slip + 3 * p + 3, 0.0);
  }
  bool applied = false;
  for (int i = 0; i < d->ncon; ++i) {
    const mjContact& c = d->contact[i];
    const int p = sliding_contact(c);
    if (p < 0 || !(depth[p] > 0.0)) continue;
    const double share = std::max(-c.dist, 0.0) / depth[p];
    double v[3];
    slip_velocity(m, d, c, v);
    for (int k = 0; k < 3; ++k) s->slip[3 * p + k] += share * v[k];
    const double speed = std::hypot(v[0], v[1], v[2]);
    if (!(speed > 0.0)) continue;
    const double k = c.friction[2] * share * s->load[p] / speed;
    mjtNum on2[3] = {-k * v[0], -k * v[1], -k * v[2]}, on1[3] = {k * v[0], k * v[1], k * v[2]};
    if (!applied) normalise_zeros(m, d->qfrc_passive);
    applied = true;
    apply_force(m, d, on2, c.pos, m->geom_bodyid[c.geom2], d->qfrc_passive);
    apply_force(m, d, on1, c.pos, m->geom_bodyid[c.geom1], d->qfrc_passive);
  }
}

// The field's slots, after the pairs', or null.
mjtNum* field_slots(const mjModel* m, mjData* d) {
  const int at = kFrictionStateSlots * m->npair;
  return m->nuserdata >= at + kDemandFieldSlots ? d->userdata + at : nullptr;
}

// After mj_collision: each level contact's first tangent direction along the stated field at it
// (DemandField), the second completing a right-handed frame with the normal.
void align_pyramids(const mjModel* m, mjData* d) {
  const mjtNum* f = field_slots(m, d);
  if (f == nullptr || (f[0] == 0.0 && f[1] == 0.0 && f[2] == 0.0)) return;
  for (int i = 0; i < d->ncon; ++i) {
    mjContact& c = d->contact[i];
    mjtNum* n = c.frame;
    if (c.dim < 3 || std::abs(n[2]) < kLevelContactNz) continue;
    const double u[3] = {f[0] + f[2] * (c.pos[0] - f[3]), f[1] + f[2] * (c.pos[1] - f[4]), 0.0};
    const double un = u[0] * n[0] + u[1] * n[1];
    double t[3] = {u[0] - un * n[0], u[1] - un * n[1], -un * n[2]};
    const double norm = std::sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
    if (!(norm > 1e-9)) continue;
    for (double& x : t) x /= norm;
    mjtNum* t1 = n + 3;
    mjtNum* t2 = n + 6;
    for (int k = 0; k < 3; ++k) t1[k] = t[k];
    t2[0] = n[1] * t[2] - n[2] * t[1];
    t2[1] = n[2] * t[0] - n[0] * t[2];
    t2[2] = n[0] * t[1] - n[1] * t[0];
  }
}

}  // namespace

void set_demand_field(const mjModel* m, mjData* d, const DemandField& field) {
  mjtNum* f = field_slots(m, d);
  if (f == nullptr) return;
  f[0] = field.ax;
  f[1] = field.ay;
  f[2] = field.w2;
  f[3] = field.cx;
  f[4] = field.cy;
}

void step(const mjModel* m, mjData* d) {
  if (m->opt.integrator != mjINT_EULER || mjENABLED(mjENBL_FWDINV) || mjcb_control != nullptr) {
    mj_step(m, d);
    return;
  }
  // mj_step = check, mj_forward (mj_forwardSkip with nothing skipped), check, Euler; and
  // mj_fwdPosition's stages in its order, with the friction set after collision detection.
  mj_checkPos(m, d);
  mj_checkVel(m, d);
  mj_kinematics(m, d);
  mj_comPos(m, d);
  mj_camlight(m, d);
  mj_tendon(m, d);
  mj_crb(m, d);
  mj_factorM(m, d);
  mj_collision(m, d);
  align_pyramids(m, d);
  coulomb_friction(m, d);
  const bool own_solve = preconditioned_cg(m);
  if (!own_solve || !contact_constraints_apply(m) || !make_contact_constraints(m, d)) {
    mj_makeConstraint(m, d);  // with our solve, MuJoCo's transposed Jacobian is not read
  }
  mj_transmission(m, d);
  mj_projectConstraint(m, d);
  mj_sensorPos(m, d);
  if (mjENABLED(mjENBL_ENERGY)) mj_energyPos(m, d);
  mj_fwdVelocity(m, d);
  kinetic_friction(m, d);
  mj_sensorVel(m, d);
  if (mjENABLED(mjENBL_ENERGY)) mj_energyVel(m, d);
  mj_fwdActuation(m, d);
  mj_fwdAcceleration(m, d);
  if (own_solve) {
    thread_constraint_solver().solve(m, d);
  } else {
    mj_fwdConstraint(m, d);
  }
  record_cone_use(m, d);
  mj_sensorAcc(m, d);
  mj_checkAcc(m, d);
  mj_Euler(m, d);
}

}  // namespace pb
