// SPDX-License-Identifier: MIT
#include "core/physics/step.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

namespace pb {

namespace {

// The pair a contact belongs to (its index), or -1.
int pair_of(const mjModel* m, const mjContact& c) {
  if (c.dim != 3) return -1;
  const double tag = c.friction[4];
  const int p = static_cast<int>(std::lround(tag)) - 1;
  if (p < 0 || p >= m->npair || std::abs(tag - double(p + 1)) > 1e-9) return -1;
  return p;
}

// How fast the two bodies' surfaces slide past each other at the contact (m/s).
double slip_speed(const mjModel* m, const mjData* d, const mjContact& c) {
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
  return std::hypot(rel[0] - along_n * n[0], rel[1] - along_n * n[1], rel[2] - along_n * n[2]);
}

// How much of its friction cone a contact used in the last constraint solve, in the cone's own
// measure, with the contact's normal force: for the pyramid (rows n +- mu_i t_i; tangent force
// (f+ - f-) mu_i, normal force the sum of all rows) the sum over tangent directions of |f+ - f-|;
// for the ellipse the norm of t_i / mu_i. It reaches the normal force exactly when the solver
// holds the contact on the cone's surface. Returns {used, normal}.
std::pair<double, double> cone_use(const mjModel* m, const mjData* d, const mjContact& c) {
  if (c.efc_address < 0 || c.dim < 3) return {0.0, 0.0};
  const mjtNum* f = d->efc_force + c.efc_address;
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
};

std::optional<PairState> pair_state(const mjModel* m, mjData* d) {
  const int n = m->npair;
  if (n == 0 || m->nuserdata < kFrictionStateSlots * n) return std::nullopt;
  return PairState{d->userdata, d->userdata + n, d->userdata + 2 * n, d->userdata + 3 * n};
}

}  // namespace

bool any_pair_sliding(const mjModel* m, const mjData* d) {
  const int n = m->npair;
  if (n == 0 || m->nuserdata < kFrictionStateSlots * n) return false;
  // The sliding flags are the first of the pairs' slots (PairState).
  return std::any_of(d->userdata, d->userdata + n, [](mjtNum v) { return v != 0.0; });
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
  for (int p = 0; p < m->npair; ++p) s->use[p] = normal[p] > 0.0 ? s->use[p] / normal[p] : kUnknown;
}

// Between mj_collision and mj_makeConstraint: each pair's state from its contacts' slip and the
// last solve's cone use, then each of its contacts' sliding coefficient from that state.
void coulomb_friction(const mjModel* m, mjData* d) {
  const auto s = pair_state(m, d);
  if (!s) return;
  mjtNum* fastest = s->scratch;
  std::fill(fastest, fastest + m->npair, kUnknown);
  bool velocities = false;
  for (int i = 0; i < d->ncon; ++i) {
    const int p = pair_of(m, d->contact[i]);
    if (p < 0) continue;
    // The slip matters only to a pair that slides or was on its cone; the others just hold.
    const bool needed = s->sliding[p] != 0.0 || s->use[p] >= kConeSaturated;
    if (needed && !velocities) {
      mj_comVel(m, d);  // this step's body velocities (mj_fwdVelocity computes them again)
      velocities = true;
    }
    fastest[p] = std::max(fastest[p], needed ? slip_speed(m, d, d->contact[i]) : 0.0);
  }
  bool any_sliding = false;
  for (int p = 0; p < m->npair; ++p) {
    // A pair with no contact this step, or none in the last solve (a box-box contact set can be
    // empty for a step while a pallet slides on its belt), keeps its state.
    if (fastest[p] == kUnknown || s->use[p] == kUnknown) {
      any_sliding = any_sliding || s->sliding[p] != 0.0;
      continue;
    }
    const bool slips = fastest[p] > kStickMps;
    if (s->sliding[p] != 0.0) {
      if (!slips) s->sliding[p] = 0.0;
    } else if (slips && s->use[p] >= kConeSaturated) {
      s->slipped[p] += fastest[p] * m->opt.timestep;
      if (s->slipped[p] >= kBreakLooseM) s->sliding[p] = 1.0;
    } else {
      s->slipped[p] = 0.0;
    }
    if (s->sliding[p] == 0.0) continue;
    any_sliding = true;
    s->slipped[p] = 0.0;
  }
  if (!any_sliding) return;
  for (int i = 0; i < d->ncon; ++i) {
    mjContact& c = d->contact[i];
    const int p = pair_of(m, c);
    if (p >= 0 && s->sliding[p] != 0.0) c.friction[0] = c.friction[1] = c.friction[2];
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
  mj_makeConstraint(m, d);
  mj_transmission(m, d);
  mj_projectConstraint(m, d);
  mj_sensorPos(m, d);
  if (mjENABLED(mjENBL_ENERGY)) mj_energyPos(m, d);
  mj_fwdVelocity(m, d);
  mj_sensorVel(m, d);
  if (mjENABLED(mjENBL_ENERGY)) mj_energyVel(m, d);
  mj_fwdActuation(m, d);
  mj_fwdAcceleration(m, d);
  mj_fwdConstraint(m, d);
  record_cone_use(m, d);
  mj_sensorAcc(m, d);
  mj_checkAcc(m, d);
  mj_Euler(m, d);
}

}  // namespace pb
