// SPDX-License-Identifier: MIT
#include "core/physics/contact_constraints.hpp"

#include <algorithm>
#include <cmath>

namespace pb {

namespace {

// The degrees of freedom of a contact's two bodies this file has room for: two free joints.
constexpr int kMaxPairDofs = 12;

bool sparse_jacobian(const mjModel* m) {
  return m->opt.jacobian == mjJAC_SPARSE || (m->opt.jacobian == mjJAC_AUTO && m->nv >= 60);
}

// The rows a contact takes on the elliptic cone, or 0 where this file cannot build them.
int contact_rows(const mjModel* m, const mjContact& c) {
  if (c.dim != 1 && c.dim != 3) return 0;  // torsional and rolling friction need angular rows
  const int b1 = m->geom_bodyid[c.geom1], b2 = m->geom_bodyid[c.geom2];
  if (!m->body_simple[b1] || !m->body_simple[b2]) return 0;
  if (m->body_dofnum[b1] + m->body_dofnum[b2] > kMaxPairDofs) return 0;
  if ((c.solref[0] > 0) != (c.solref[1] > 0)) return 0;  // MuJoCo warns and replaces it
  return c.dim;
}

// mj_jacSparseSimple: the contact point's translational Jacobian on `body`'s own degrees of
// freedom, negated for the first body, into columns from `start` of the 3 x nv matrix `jac`.
void body_jacobian(const mjModel* m, const mjData* d, double* jac, const double point[3], int body,
                   bool second, int nv, int start) {
  const int n = m->body_dofnum[body];
  if (n == 0) return;
  const double* com = d->subtree_com + 3 * m->body_rootid[body];
  const double offset[3] = {point[0] - com[0], point[1] - com[1], point[2] - com[2]};
  for (int k = 0; k < n; ++k) {
    const double* cdof = d->cdof + 6 * (m->body_dofadr[body] + k);
    double tmp[3];
    mju_cross(tmp, cdof, offset);
    for (int r = 0; r < 3; ++r) {
      const double v = cdof[3 + r] + tmp[r];
      jac[start + k + r * nv] = second ? v : -v;
    }
  }
}

// pow(x, e), without the call where e is 1: x itself is the only double within glibc's bound on
// pow's error (under 1 ulp) of the exact x^1, so pow returns it.
double power(double x, double e) {
  return e == 1.0 ? x : std::pow(x, e);
}

// getimpedance (engine_core_constraint.c): the impedance at `pos` and its derivative.
void impedance(const double solimp[5], double pos, double margin, double& imp, double& imp_p) {
  if (solimp[0] == solimp[1] || solimp[2] <= mjMINVAL) {
    imp = 0.5 * (solimp[0] + solimp[1]);
    imp_p = 0;
    return;
  }
  double x = (pos - margin) / solimp[2];
  double sgn = 1;
  if (x < 0) {
    x = -x;
    sgn = -1;
  }
  if (x >= 1 || x <= 0) {
    imp = x >= 1 ? solimp[1] : solimp[0];
    imp_p = 0;
    return;
  }
  double y, y_p;
  if (solimp[4] == 1) {
    y = x;
    y_p = 1;
  } else if (x <= solimp[3]) {
    const double a = 1 / power(solimp[3], solimp[4] - 1);
    y = a * power(x, solimp[4]);
    y_p = solimp[4] * a * power(x, solimp[4] - 1);
  } else {
    const double b = 1 / power(1 - solimp[3], solimp[4] - 1);
    y = 1 - b * power(1 - x, solimp[4]);
    y_p = solimp[4] * b * power(1 - x, solimp[4] - 1);
  }
  imp = solimp[0] + y * (solimp[1] - solimp[0]);
  imp_p = y_p * sgn * (solimp[1] - solimp[0]) / solimp[2];
}

// getsolparam for a contact: its solref and solimp, made safe as MuJoCo makes them (the solref
// format is not mixed: contact_rows refused that).
void contact_solparam(const mjModel* m, const mjContact& c, double solref[mjNREF],
                      double solimp[mjNIMP]) {
  for (int k = 0; k < mjNREF; ++k) solref[k] = c.solref[k];
  for (int k = 0; k < mjNIMP; ++k) solimp[k] = c.solimp[k];
  if (!mjDISABLED(mjDSBL_REFSAFE) && solref[0] > 0) {
    solref[0] = mju_max(solref[0], 2 * m->opt.timestep);
  }
  solimp[0] = mju_min(mjMAXIMP, mju_max(mjMINIMP, solimp[0]));
  solimp[1] = mju_min(mjMAXIMP, mju_max(mjMINIMP, solimp[1]));
  solimp[2] = mju_max(0, solimp[2]);
  solimp[3] = mju_min(mjMAXIMP, mju_max(mjMINIMP, solimp[3]));
  solimp[4] = mju_max(1, solimp[4]);
}

// MuJoCo's mju_mulMatMat(jac, frame, jacdif, rows, 3, nv): each row of `jac` the sum, in k's
// order, of the rows k of `jacdif` whose frame coefficient is not zero, from a row of zeros. NV > 0
// fixes nv at compile time (the loops unroll), 0 takes it at run time.
template <int NV>
void rotate(const double* jacdif, const double* frame, int rows, int nv_at_run_time, double* jac) {
  const int nv = NV > 0 ? NV : nv_at_run_time;
  for (int r = 0; r < rows; ++r) {
    double* out = jac + r * nv;
    for (int j = 0; j < nv; ++j) out[j] = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double f = frame[3 * r + k];
      if (f == 0.0) continue;
      const double* in = jacdif + k * nv;
      for (int j = 0; j < nv; ++j) out[j] += in[j] * f;
    }
  }
}

// One contact's rows (mj_instantiateContact's Jacobian and mj_addConstraint's copy), its
// diagApprox and its impedance (mj_diagApprox, mj_makeImpedance's first loop).
void add_contact(const mjModel* m, mjData* d, int id) {
  mjContact& c = d->contact[id];
  const int b1 = m->geom_bodyid[c.geom1], b2 = m->geom_bodyid[c.geom2];
  // mj_mergeChainSimple: the lower body's degrees of freedom, then the higher's.
  const int lo = b1 < b2 ? b1 : b2, hi = b1 < b2 ? b2 : b1;
  const int n_lo = m->body_dofnum[lo], n_hi = m->body_dofnum[hi], nv = n_lo + n_hi;
  if (nv == 0) {
    c.efc_address = -1;
    c.exclude = 4;
    return;
  }
  // jacdif (3 x nv), then rotated into the contact's frame.
  double jacdif[3 * kMaxPairDofs], jac[3 * kMaxPairDofs];
  body_jacobian(m, d, jacdif, c.pos, b1, false, nv, b1 < b2 ? 0 : m->body_dofnum[b2]);
  body_jacobian(m, d, jacdif, c.pos, b2, true, nv, b2 < b1 ? 0 : m->body_dofnum[b1]);
  const int rows = c.dim;  // 1 or 3 (contact_rows)
  switch (nv) {  // two free bodies (items, an item on the pallet); the pallet on the belt's slides
    case 12:
      rotate<12>(jacdif, c.frame, rows, 12, jac);
      break;
    case 8:
      rotate<8>(jacdif, c.frame, rows, 8, jac);
      break;
    default:
      rotate<0>(jacdif, c.frame, rows, nv, jac);
  }

  const int first = d->nefc;
  c.efc_address = first;
  const int type = rows == 1 ? mjCNSTR_CONTACT_FRICTIONLESS : mjCNSTR_CONTACT_ELLIPTIC;
  const double tran = m->body_invweight0[2 * b1] + m->body_invweight0[2 * b2];
  for (int r = 0; r < rows; ++r) {
    const int row = first + r;
    const int adr = row ? d->efc_J_rowadr[row - 1] + d->efc_J_rownnz[row - 1] : 0;
    d->efc_J_rowadr[row] = adr;
    d->efc_J_rownnz[row] = nv;
    for (int j = 0; j < n_lo; ++j) d->efc_J_colind[adr + j] = m->body_dofadr[lo] + j;
    for (int j = 0; j < n_hi; ++j) d->efc_J_colind[adr + n_lo + j] = m->body_dofadr[hi] + j;
    for (int j = 0; j < nv; ++j) d->efc_J[adr + j] = jac[r * nv + j];
    d->efc_pos[row] = r == 0 ? c.dist : 0.0;
    d->efc_margin[row] = r == 0 ? c.includemargin : 0.0;
    d->efc_frictionloss[row] = 0.0;
    d->efc_type[row] = type;
    d->efc_id[row] = id;
    d->efc_diagApprox[row] = tran;  // rows below 3 are translational
  }
  d->nefc += rows;

  double solref[mjNREF], solimp[mjNIMP], imp, imp_p;
  contact_solparam(m, c, solref, solimp);
  impedance(solimp, d->efc_pos[first], d->efc_margin[first], imp, imp_p);
  const double k_normal = solref[0] > 0
                              ? 1 / mju_max(mjMINVAL, solimp[1] * solimp[1] * solref[0] *
                                                          solref[0] * solref[1] * solref[1])
                              : -solref[0] / mju_max(mjMINVAL, solimp[1] * solimp[1]);
  const double b = solref[1] > 0 ? 2 / mju_max(mjMINVAL, solimp[1] * solref[0])
                                 : -solref[1] / mju_max(mjMINVAL, solimp[1]);
  for (int r = 0; r < rows; ++r) {
    const int row = first + r;
    d->efc_R[row] = mju_max(mjMINVAL, (1 - imp) * d->efc_diagApprox[row] / imp);
    double* kbip = d->efc_KBIP + 4 * row;
    kbip[0] = type == mjCNSTR_CONTACT_ELLIPTIC && r > 0 ? 0 : k_normal;
    kbip[1] = b;
    kbip[2] = imp;
    kbip[3] = imp_p;
  }
}

}  // namespace

bool contact_constraints_apply(const mjModel* m) {
  if (!sparse_jacobian(m) || m->opt.cone != mjCONE_ELLIPTIC) return false;
  for (int i = 0; i < m->neq; ++i) {
    if (m->eq_active[i]) return false;
  }
  for (int i = 0; i < m->njnt; ++i) {
    if (m->jnt_limited[i]) return false;
  }
  for (int i = 0; i < m->nv; ++i) {
    if (m->dof_frictionloss[i] > 0) return false;
  }
  for (int i = 0; i < m->ntendon; ++i) {
    if (m->tendon_limited[i] || m->tendon_frictionloss[i] > 0) return false;
  }
  return true;
}

bool make_contact_constraints(const mjModel* m, mjData* d) {
  if (mjDISABLED(mjDSBL_CONSTRAINT) || m->njmax == 0) {
    d->ne = d->nf = d->nefc = 0;
    return true;
  }
  const bool contacts = !mjDISABLED(mjDSBL_CONTACT);
  if (contacts) {
    int rows = 0;
    for (int i = 0; i < d->ncon; ++i) {
      if (d->contact[i].exclude) continue;
      const int n = contact_rows(m, d->contact[i]);
      if (n == 0) return false;
      rows += n;
    }
    if (rows > m->njmax) return false;
  }

  d->ne = d->nf = d->nefc = 0;
  if (contacts) {
    for (int i = 0; i < d->ncon; ++i) {
      if (!d->contact[i].exclude) add_contact(m, d, i);
    }
  }
  d->maxuse_con = std::max(d->maxuse_con, d->ncon);
  d->maxuse_efc = std::max(d->maxuse_efc, d->nefc);
  const int nefc = d->nefc;
  if (nefc == 0) return true;

  // mju_superSparse of J: how many following rows share each row's columns.
  int* super = d->efc_J_rowsuper;
  for (int r = 0; r + 1 < nefc; ++r) {
    const int* a = d->efc_J_colind + d->efc_J_rowadr[r];
    const int* b = d->efc_J_colind + d->efc_J_rowadr[r + 1];
    super[r] =
        d->efc_J_rownnz[r] == d->efc_J_rownnz[r + 1] && std::equal(a, a + d->efc_J_rownnz[r], b);
  }
  super[nefc - 1] = 0;
  for (int r = nefc - 2; r >= 0; --r) {
    if (super[r]) super[r] += super[r + 1];
  }

  // mj_makeImpedance's second loop: the friction rows' R from the normal's, the cone's mu.
  double* R = d->efc_R;
  for (int i = 0; i < nefc; ++i) {
    if (d->efc_type[i] != mjCNSTR_CONTACT_ELLIPTIC) continue;
    mjContact& c = d->contact[d->efc_id[i]];
    R[i + 1] = R[i] / mju_max(mjMINVAL, m->opt.impratio);
    c.mu = c.friction[0] * std::sqrt(R[i + 1] / R[i]);
    for (int j = 1; j < c.dim - 1; ++j) {
      R[i + j + 1] = R[i + 1] * c.friction[0] * c.friction[0] / (c.friction[j] * c.friction[j]);
    }
    i += c.dim - 1;
  }
  for (int i = 0; i < nefc; ++i) d->efc_D[i] = 1 / R[i];
  for (int i = 0; i < nefc; ++i) {
    d->efc_diagApprox[i] = R[i] * d->efc_KBIP[4 * i + 2] / (1 - d->efc_KBIP[4 * i + 2]);
  }
  return true;
}

}  // namespace pb
