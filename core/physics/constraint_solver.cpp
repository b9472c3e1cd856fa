// SPDX-License-Identifier: MIT
#include "core/physics/constraint_solver.hpp"

#include "core/physics/block_cholesky.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <memory>
#include <vector>

namespace pb {

namespace {

// A block's rows of J, packed (collect_blocks).
using RowBlock =
    Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>;
// The commonest block: two free bodies' columns (every carton pair's contacts), assembled in
// fixed-size products (add_pair_block).
constexpr int kPairWidth = 12;
using PairRows =
    Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, kPairWidth, Eigen::RowMajor>>;

// The preconditioner is built again at the current constraint states once this many iterations
// have passed since it was built at others, and whenever an iteration improves the cost by less
// than the tolerance while it is stale (MuJoCo's stop then may mean only a stale
// preconditioner: stopping there left solves 1e-3 from converged Newton, ten times MuJoCo's CG).
// On a 96-carton brick's start-up at 0.98 of its onset: never, 250 iterations a step; every 10,
// 22; every 5, 21 with 5 factorizations; every 2 or 3, 11-15 with 5.5-5.8 (about as dear then).
// Every 2 since the pair blocks' assembly got cheaper (session 38): 105 random unwrapped
// pallets' envelopes 7 % less time than every 5, the corpora's agreement the same.
constexpr int kRefreshEvery = 2;
// ... unless at most this share of the constraint rows changed state since it was built: then
// the stop stands. Brick 96's 0.135 g curve: 1.68 -> 1.04 ms of solve a step; the corpora's
// agreement the same (limits moved within a step both ways), their CPU 12-19 % lower.
constexpr double kStopChangedRows = 0.02;

// The cost along a search line from the current point (alpha = 0): Gauss's part and each
// constraint's, as MuJoCo defines them (mj_constraintUpdate), with first and second derivatives.
struct LinePoint {
  double alpha = 0.0, cost = 0.0, slope = 0.0, curvature = 0.0;
};

// A Hessian sparsity pattern (lower triangle) and its symbolic factorization, by bodies: each
// body's degrees of freedom are one dense group of the factor (BlockCholesky).
struct Structure {
  std::vector<std::vector<int>> rows;  // per column j: the rows i >= j it holds, sorted
  BlockCholesky factor;
  bool analysed = false;

  void analyse(const mjModel* m) {
    std::vector<int> first, size, group_of(m->nv, -1);
    for (int b = 0; b < m->nbody; ++b) {
      if (m->body_dofnum[b] == 0) continue;
      for (int i = 0; i < m->body_dofnum[b]; ++i) {
        group_of[m->body_dofadr[b] + i] = static_cast<int>(first.size());
      }
      first.push_back(m->body_dofadr[b]);
      size.push_back(m->body_dofnum[b]);
    }
    std::vector<std::vector<int>> couples(first.size());
    for (int c = 0; c < m->nv; ++c) {
      for (int r : rows[c]) {
        if (group_of[r] != group_of[c]) couples[group_of[c]].push_back(group_of[r]);
      }
    }
    for (auto& g : couples) {
      std::sort(g.begin(), g.end());
      g.erase(std::unique(g.begin(), g.end()), g.end());
    }
    analysed = factor.analyse(first, size, couples);
  }
};

// A model's Hessian structures, one per set of couplings a solve's constraints made (the last
// few): a structure, its fill-reducing ordering and hence its rounding, is a function of the
// model and of the couplings of the solve's rows alone, never of what this thread solved before,
// so a solve's answer is the same bit for bit whichever thread runs it after whatever else. (The
// couplings every contact pair of the model could make instead, fixed per model, fill a brick's
// factor with its neighbours' lateral pairs, which touch rarely: brick 48's envelope 2.4x
// dearer.)
struct Pattern {
  std::vector<int> signature;  // the model's (model_signature)
  struct Cached {
    std::vector<int> couplings;  // the key: the solve's distinct column sets (couplings_key)
    Structure structure;
    long last_use = 0;
  };
  std::array<Cached, 8> cache;
  long last_use = 0;
};

// What a model's structures depend on besides the couplings: its degrees of freedom and tree.
std::vector<int> model_signature(const mjModel* m) {
  std::vector<int> sig{m->nv};
  sig.insert(sig.end(), m->dof_parentid, m->dof_parentid + m->nv);
  return sig;
}

}  // namespace

struct ConstraintSolver::Impl {
  std::array<Pattern, 4> patterns;  // the last few models this thread solved
  long uses = 0;
  int analyses = 0;
  int fallbacks = 0;

  // Per solve.
  std::vector<double> jaref, jv, ma, mv, grad, pgrad, search, grad_old, pgrad_old;
  std::vector<double> quad;  // per constraint row: 0.5 D x0^2, D x0 v, 0.5 D v^2
  // Per elliptic contact's first row: U0, V0, UU, UV, VV, Dm, and its mu and dim (so that the
  // line search reads no mjContact).
  static constexpr int kConeSlots = 8;
  std::vector<double> cone;
  std::vector<int> factored_state;  // efc_state where the preconditioner was built
  // The solve's constraint blocks (collect_blocks, map_dest).
  struct Block {
    int first = 0, end = 0;              // rows
    int k = 0;                           // columns
    int cols = 0, dest = 0, packed = 0;  // offsets into the vectors below
  };
  std::vector<Block> blocks;
  std::vector<int> cols, dest, mass_dest, scratch_cols, order, key;
  std::vector<double> packed, block, hj, gathered;
  double gauss1 = 0.0, gauss2 = 0.0;  // Gauss's cost along the line: its slope and half curvature

  Pattern& pattern_for(const mjModel* m);
  void couplings_key();
  Structure& structure_for(const mjModel* m, Pattern& p);
  void collect_blocks(const mjModel* m, const mjData* d);
  void mul_j(const double* v, double* out);
  void mul_jt(int nv, const double* f, double* out);
  double constraint_update(const mjModel* m, mjData* d, const double* jar, bool forces);
  bool map_dest(const mjModel* m, const Structure& p);
  void assemble(const mjData* d, Structure& p);
  void add_pair_block(const mjData* d, const Block& b, const double* jrow);
  Eigen::Matrix<double, kPairWidth, kPairWidth> pair;  // add_pair_block's
  void precondition(const mjModel* m, mjData* d, Structure& p, bool factored, const double* in,
                    double* out);
  double update(const mjModel* m, mjData* d, const double* qacc);
  void prepare_line(const mjModel* m, const mjData* d);
  LinePoint evaluate(const mjData* d, double alpha) const;
  double line_search(const mjModel* m, mjData* d);
};

ConstraintSolver::ConstraintSolver() : impl_(std::make_unique<Impl>()) {}
ConstraintSolver::~ConstraintSolver() = default;
int ConstraintSolver::analyses() const {
  return impl_->analyses;
}
int ConstraintSolver::fallbacks() const {
  return impl_->fallbacks;
}

ConstraintSolver& thread_constraint_solver() {
  thread_local ConstraintSolver solver;
  return solver;
}

Pattern& ConstraintSolver::Impl::pattern_for(const mjModel* m) {
  ++uses;
  std::vector<int> sig = model_signature(m);
  Pattern* oldest = &patterns[0];
  for (Pattern& p : patterns) {
    if (p.signature == sig) {
      p.last_use = uses;
      return p;
    }
    if (p.last_use < oldest->last_use) oldest = &p;
  }
  Pattern& p = *oldest;
  p = Pattern{};
  p.signature = std::move(sig);
  p.last_use = uses;
  return p;
}

// The key of the solve's couplings: its blocks' distinct column sets, sorted, each as its size
// and its columns.
void ConstraintSolver::Impl::couplings_key() {
  order.resize(blocks.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  auto columns = [&](int i) {
    const int* c = cols.data() + blocks[i].cols;
    return std::pair{c, c + blocks[i].k};
  };
  std::sort(order.begin(), order.end(), [&](int x, int y) {
    const auto [a0, a1] = columns(x);
    const auto [b0, b1] = columns(y);
    return std::lexicographical_compare(a0, a1, b0, b1);
  });
  key.clear();
  for (size_t i = 0; i < order.size(); ++i) {
    const auto [c0, c1] = columns(order[i]);
    if (i > 0) {
      const auto [p0, p1] = columns(order[i - 1]);
      if (std::equal(c0, c1, p0, p1)) continue;
    }
    key.push_back(static_cast<int>(c1 - c0));
    key.insert(key.end(), c0, c1);
  }
}

// The structure of the mass matrix (each degree of freedom with its ancestors) and the solve's
// couplings (couplings_key), analysed unless one of the last few solves had the same.
Structure& ConstraintSolver::Impl::structure_for(const mjModel* m, Pattern& p) {
  couplings_key();
  Pattern::Cached* oldest = &p.cache[0];
  for (Pattern::Cached& c : p.cache) {
    if (c.structure.analysed && c.couplings == key) {
      c.last_use = uses;
      return c.structure;
    }
    if (c.last_use < oldest->last_use) oldest = &c;
  }
  const int nv = m->nv;
  Pattern::Cached& c = *oldest;
  c.couplings = key;
  c.last_use = uses;
  auto& rows = c.structure.rows;
  rows.assign(nv, {});
  for (int i = 0; i < nv; ++i) {
    for (int j = i; j >= 0; j = m->dof_parentid[j]) rows[j].push_back(i);
  }
  for (size_t at = 0; at < key.size();) {
    const int k = key[at];
    const int* set = key.data() + at + 1;
    for (int y = 0; y < k; ++y) {
      for (int x = y; x < k; ++x) rows[set[y]].push_back(set[x]);
    }
    at += 1 + static_cast<size_t>(k);
  }
  for (auto& col : rows) {
    std::sort(col.begin(), col.end());
    col.erase(std::unique(col.begin(), col.end()), col.end());
  }
  c.structure.analyse(m);
  ++analyses;
  return c.structure;
}

// The solve's constraint rows in blocks of identical columns (a contact's rows, and every
// contact of one body pair, share theirs in MuJoCo's sparse layout; a dense row's nonzeros stand
// for its columns, over all of a contact's rows), each row's coefficients packed in its block's
// column order.
void ConstraintSolver::Impl::collect_blocks(const mjModel* m, const mjData* d) {
  const int nv = m->nv, nefc = d->nefc;
  const bool sparse = mj_isSparse(m);
  blocks.clear();
  cols.clear();
  packed.clear();
  std::vector<int>& row_cols = scratch_cols;
  auto columns_of = [&](int row, int dim) {
    row_cols.clear();
    if (sparse) {
      const int* c = d->efc_J_colind + d->efc_J_rowadr[row];
      row_cols.assign(c, c + d->efc_J_rownnz[row]);
      return;
    }
    for (int c = 0; c < nv; ++c) {
      for (int r = row; r < row + dim; ++r) {
        if (d->efc_J[r * nv + c] != 0.0) {
          row_cols.push_back(c);
          break;
        }
      }
    }
  };
  for (int row = 0; row < nefc;) {
    const int dim =
        d->efc_type[row] == mjCNSTR_CONTACT_ELLIPTIC ? d->contact[d->efc_id[row]].dim : 1;
    columns_of(row, dim);
    const int k = static_cast<int>(row_cols.size());
    const bool same =
        !blocks.empty() && blocks.back().k == k &&
        std::equal(row_cols.begin(), row_cols.end(), cols.begin() + blocks.back().cols);
    if (!same) {
      Block b;
      b.first = row;
      b.k = k;
      b.cols = static_cast<int>(cols.size());
      b.packed = static_cast<int>(packed.size());
      cols.insert(cols.end(), row_cols.begin(), row_cols.end());
      blocks.push_back(b);
    }
    Block& b = blocks.back();
    const int* bc = cols.data() + b.cols;
    for (int r = row; r < row + dim; ++r) {
      if (sparse) {
        const double* v = d->efc_J + d->efc_J_rowadr[r];
        packed.insert(packed.end(), v, v + k);
      } else {
        for (int x = 0; x < k; ++x) packed.push_back(d->efc_J[r * nv + bc[x]]);
      }
    }
    row += dim;
    b.end = row;
  }
}

// out = J v, block by block: a block's rows share their columns, so v is gathered once for them
// and each row is a dense product (MuJoCo 2.2.2's sparse product gathers per coefficient, in one
// dependent chain of additions: about a sixth of a large brick's step).
void ConstraintSolver::Impl::mul_j(const double* v, double* out) {
  for (const Block& b : blocks) {
    const int k = b.k, n = b.end - b.first;
    gathered.resize(static_cast<size_t>(k));
    const int* c = cols.data() + b.cols;
    for (int x = 0; x < k; ++x) gathered[x] = v[c[x]];
    const RowBlock rows(packed.data() + b.packed, n, k);
    Eigen::Map<Eigen::VectorXd>(out + b.first, n).noalias() =
        rows * Eigen::Map<const Eigen::VectorXd>(gathered.data(), k);
  }
}

// out = J' f, block by block (mul_j's transpose).
void ConstraintSolver::Impl::mul_jt(int nv, const double* f, double* out) {
  std::fill(out, out + nv, 0.0);
  for (const Block& b : blocks) {
    const int k = b.k, n = b.end - b.first;
    gathered.resize(static_cast<size_t>(k));
    const RowBlock rows(packed.data() + b.packed, n, k);
    Eigen::Map<Eigen::VectorXd>(gathered.data(), k).noalias() =
        rows.transpose() * Eigen::Map<const Eigen::VectorXd>(f + b.first, n);
    const int* c = cols.data() + b.cols;
    for (int x = 0; x < k; ++x) out[c[x]] += gathered[x];
  }
}

// MuJoCo's mj_constraintUpdate at jar = J qacc - aref: each row's state and force, and the
// constraints' cost (returned); with `forces`, also each cone contact's Hessian (contact.H) and
// qfrc_constraint = J' efc_force (mul_jt). The same zones and formulas as MuJoCo's (its
// documentation's "Computation": the elliptic cone's top, middle and bottom zones, and its middle
// zone's Hessian in the cone's own coordinates), here so that J' f is the blocked product.
double ConstraintSolver::Impl::constraint_update(const mjModel* m, mjData* d, const double* jar,
                                                 bool forces) {
  const int ne = d->ne, nf = d->nf, nefc = d->nefc;
  const double *D = d->efc_D, *R = d->efc_R, *floss = d->efc_frictionloss;
  double* force = d->efc_force;
  int* state = d->efc_state;
  double cost = 0.0;
  for (int i = 0; i < nefc; ++i) force[i] = -D[i] * jar[i];
  for (int i = 0; i < ne; ++i) {
    cost += 0.5 * D[i] * jar[i] * jar[i];
    state[i] = mjCNSTRSTATE_QUADRATIC;
  }
  for (int i = ne; i < ne + nf; ++i) {
    const double bound = R[i] * floss[i];
    if (jar[i] <= -bound) {
      cost += -0.5 * bound * floss[i] - floss[i] * jar[i];
      force[i] = floss[i];
      state[i] = mjCNSTRSTATE_LINEARNEG;
    } else if (jar[i] >= bound) {
      cost += -0.5 * bound * floss[i] + floss[i] * jar[i];
      force[i] = -floss[i];
      state[i] = mjCNSTRSTATE_LINEARPOS;
    } else {
      cost += 0.5 * D[i] * jar[i] * jar[i];
      state[i] = mjCNSTRSTATE_QUADRATIC;
    }
  }
  for (int i = ne + nf; i < nefc;) {
    if (d->efc_type[i] != mjCNSTR_CONTACT_ELLIPTIC) {  // a non-negative row
      if (jar[i] >= 0.0) {
        force[i] = 0.0;
        state[i] = mjCNSTRSTATE_SATISFIED;
      } else {
        cost += 0.5 * D[i] * jar[i] * jar[i];
        state[i] = mjCNSTRSTATE_QUADRATIC;
      }
      ++i;
      continue;
    }
    mjContact& con = d->contact[d->efc_id[i]];
    const int dim = con.dim;
    const double mu = con.mu;
    // In the cone's own coordinates: U = (mu jar_n, friction_j jar_j).
    std::array<double, 6> u{};
    u[0] = jar[i] * mu;
    double t2 = 0.0;
    for (int j = 1; j < dim; ++j) {
      u[j] = jar[i + j] * con.friction[j - 1];
      t2 += u[j] * u[j];
    }
    const double n = u[0], t = std::sqrt(t2);
    int zone;
    if (n >= mu * t || (t <= 0.0 && n >= 0.0)) {
      zone = mjCNSTRSTATE_SATISFIED;
      std::fill(force + i, force + i + dim, 0.0);
    } else if (mu * n + t <= 0.0 || (t <= 0.0 && n < 0.0)) {
      zone = mjCNSTRSTATE_QUADRATIC;
      for (int j = 0; j < dim; ++j) cost += 0.5 * D[i + j] * jar[i + j] * jar[i + j];
    } else {
      zone = mjCNSTRSTATE_CONE;
      const double dm = D[i] / (mu * mu * (1.0 + mu * mu)), gap = n - mu * t;
      cost += 0.5 * dm * gap * gap;
      force[i] = -dm * gap * mu;
      for (int j = 1; j < dim; ++j) force[i + j] = -force[i] / t * u[j] * con.friction[j - 1];
      if (forces) {
        // d2 cost / d jar2 = diag(s) Hu diag(s), s = (mu, friction): Hu's first row (1, -mu/t U'),
        // its tangent block mu n / t^3 U U' + (mu^2 - mu n / t) I, scaled by dm.
        double* h = con.H;
        auto scale = [&](int x) { return x == 0 ? mu : con.friction[x - 1]; };
        for (int x = 0; x < dim; ++x) {
          for (int y = x; y < dim; ++y) {
            double v;
            if (x == 0) {
              v = y == 0 ? 1.0 : -mu / t * u[y];
            } else {
              v = mu * n / (t * t * t) * u[x] * u[y] + (x == y ? mu * mu - mu * n / t : 0.0);
            }
            h[x * dim + y] = h[y * dim + x] = dm * scale(x) * scale(y) * v;
          }
        }
      }
    }
    std::fill(state + i, state + i + dim, zone);
    i += dim;
  }
  if (forces) mul_jt(m->nv, force, d->qfrc_constraint);
  return cost;
}

// Where each block's lower triangle, and each mass matrix entry, lands in `p`'s values.
// False if the structure does not hold one (it holds every entry its rows name; then the solve
// preconditions with the mass matrix rather than write out of place).
bool ConstraintSolver::Impl::map_dest(const mjModel* m, const Structure& p) {
  bool held = true;
  auto find = [&](int r, int c) {  // (r >= c)
    const int at = p.factor.position(r, c);
    held = held && at >= 0;
    return at;
  };
  mass_dest.clear();
  for (int i = 0; i < m->nv; ++i) {
    for (int j = i; j >= 0; j = m->dof_parentid[j]) mass_dest.push_back(find(i, j));
  }
  dest.clear();
  for (Block& b : blocks) {
    b.dest = static_cast<int>(dest.size());
    held = p.factor.positions(cols.data() + b.cols, b.k, dest) && held;
  }
  return held;
}

// H = M + sum over quadratic rows of D J_i' J_i + sum over cone contacts of J_c' H_c J_c, at the
// states (and cone Hessians) constraint_update left in d, into the pattern's values.
void ConstraintSolver::Impl::assemble(const mjData* d, Structure& p) {
  double* values = p.factor.values();
  std::fill(values, values + p.factor.value_count(), 0.0);
  for (size_t i = 0, n = mass_dest.size(); i < n; ++i) values[mass_dest[i]] += d->qM[i];
  for (const Block& b : blocks) {
    const int k = b.k;
    const double* jrow = packed.data() + b.packed;
    const int* to = dest.data() + b.dest;
    if (k == kPairWidth) {  // two free bodies: fixed-size products
      add_pair_block(d, b, jrow);
      for (int c = 0; c < k; ++c) {
        for (int r = c; r < k; ++r) values[*to++] += pair(r, c);
      }
      continue;
    }
    block.assign(static_cast<size_t>(k) * k, 0.0);  // lower triangle, column by column
    for (int row = b.first; row < b.end;) {
      const bool elliptic = d->efc_type[row] == mjCNSTR_CONTACT_ELLIPTIC;
      const int dim = elliptic ? d->contact[d->efc_id[row]].dim : 1;
      const int state = d->efc_state[row];
      if (elliptic && state == mjCNSTRSTATE_CONE) {
        // block += J_c' (H_c J_c)
        const mjtNum* hc = d->contact[d->efc_id[row]].H;
        hj.assign(static_cast<size_t>(dim) * k, 0.0);
        for (int x = 0; x < dim; ++x) {
          for (int y = 0; y < dim; ++y) {
            const double h = hc[x * dim + y];
            const double* jy = jrow + y * k;
            double* out = hj.data() + x * k;
            for (int c = 0; c < k; ++c) out[c] += h * jy[c];
          }
        }
        for (int x = 0; x < dim; ++x) {
          const double* jx = jrow + x * k;
          const double* hx = hj.data() + x * k;
          for (int c = 0; c < k; ++c) {
            const double hv = hx[c];
            double* col = block.data() + c * k;
            for (int r = c; r < k; ++r) col[r] += jx[r] * hv;
          }
        }
      } else if (state == mjCNSTRSTATE_QUADRATIC) {
        for (int x = 0; x < dim; ++x) {
          const double* jx = jrow + x * k;
          const double w = d->efc_D[row + x];
          for (int c = 0; c < k; ++c) {
            const double wc = w * jx[c];
            if (wc == 0.0) continue;
            double* col = block.data() + c * k;
            for (int r = c; r < k; ++r) col[r] += jx[r] * wc;
          }
        }
      }
      jrow += dim * k;
      row += dim;
    }
    for (int c = 0; c < k; ++c) {
      const double* col = block.data() + c * k;
      for (int r = c; r < k; ++r) values[*to++] += col[r];
    }
  }
}

// pair = J' W J over a block of two free bodies' columns, W each contact's weights: its cone
// Hessian in the cone's middle zone, D on its quadratic rows, none where it is satisfied. Row by
// row, J_x' (W J)_x, as assemble's generic path sums them (the same roundings, bit for bit), in
// fixed-size products the compiler unrolls and vectorises.
void ConstraintSolver::Impl::add_pair_block(const mjData* d, const Block& b, const double* jrow) {
  using Row = Eigen::Matrix<double, 1, kPairWidth>;
  pair.setZero();
  for (int row = b.first; row < b.end;) {
    const bool elliptic = d->efc_type[row] == mjCNSTR_CONTACT_ELLIPTIC;
    const int dim = elliptic ? d->contact[d->efc_id[row]].dim : 1;
    const int state = d->efc_state[row];
    if (elliptic && state == mjCNSTRSTATE_CONE) {
      const PairRows j(jrow, dim, kPairWidth);
      const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>
          h(d->contact[d->efc_id[row]].H, dim, dim);
      for (int x = 0; x < dim; ++x) {
        Row row_x = h(x, 0) * j.row(0);  // (H J)_x, summed over y in order
        for (int y = 1; y < dim; ++y) row_x += h(x, y) * j.row(y);
        pair.noalias() += j.row(x).transpose().lazyProduct(row_x);
      }
    } else if (state == mjCNSTRSTATE_QUADRATIC) {
      for (int x = 0; x < dim; ++x) {
        const Eigen::Map<const Row> j(jrow + x * kPairWidth);
        pair.noalias() += j.transpose().lazyProduct(d->efc_D[row + x] * j);
      }
    }
    jrow += dim * kPairWidth;
    row += dim;
  }
}

// out = P^-1 in, P the factored Hessian; M^-1 in where it could not be factored.
void ConstraintSolver::Impl::precondition(const mjModel* m, mjData* d, Structure& p, bool factored,
                                          const double* in, double* out) {
  if (!factored) {
    mj_solveM(m, d, out, in, 1);
    return;
  }
  p.factor.solve(in, out);
}

// constraint_update at qacc (jaref current), plus Gauss's cost; the gradient of the total.
double ConstraintSolver::Impl::update(const mjModel* m, mjData* d, const double* qacc) {
  double cost = constraint_update(m, d, jaref.data(), true);
  for (int i = 0; i < m->nv; ++i) {
    const double r = ma[i] - d->qfrc_smooth[i];
    cost += 0.5 * r * (qacc[i] - d->qacc_smooth[i]);
    grad[i] = r - d->qfrc_constraint[i];
  }
  return cost;
}

// Per-row coefficients of the cost along `search` (Mv and Jv computed).
void ConstraintSolver::Impl::prepare_line(const mjModel* m, const mjData* d) {
  const int nv = m->nv, nefc = d->nefc;
  gauss1 = 0.0;
  gauss2 = 0.0;
  for (int i = 0; i < nv; ++i) {
    gauss1 += search[i] * (ma[i] - d->qfrc_smooth[i]);
    gauss2 += 0.5 * search[i] * mv[i];
  }
  for (int i = 0; i < nefc; ++i) {
    const double w = d->efc_D[i];
    quad[3 * i] = 0.5 * w * jaref[i] * jaref[i];
    quad[3 * i + 1] = w * jaref[i] * jv[i];
    quad[3 * i + 2] = 0.5 * w * jv[i] * jv[i];
  }
  for (int i = 0; i < nefc;) {
    if (d->efc_type[i] != mjCNSTR_CONTACT_ELLIPTIC) {
      ++i;
      continue;
    }
    const mjContact& c = d->contact[d->efc_id[i]];
    double* e = &cone[kConeSlots * i];
    e[0] = jaref[i] * c.mu;
    e[1] = jv[i] * c.mu;
    e[2] = e[3] = e[4] = 0.0;
    for (int j = 1; j < c.dim; ++j) {
      const double u = jaref[i + j] * c.friction[j - 1], v = jv[i + j] * c.friction[j - 1];
      e[2] += u * u;
      e[3] += u * v;
      e[4] += v * v;
    }
    e[5] = d->efc_D[i] / (c.mu * c.mu * (1.0 + c.mu * c.mu));
    e[6] = c.mu;
    e[7] = c.dim;
    i += c.dim;
  }
}

LinePoint ConstraintSolver::Impl::evaluate(const mjData* d, double alpha) const {
  // Quadratic pieces are summed as polynomials in alpha; the cone's middle zone directly. The
  // cost is relative to Gauss's at alpha = 0.
  double q0 = 0.0, q1 = gauss1, q2 = gauss2;
  double cost = 0.0, slope = 0.0, curvature = 0.0;
  auto add = [&](int i) {
    q0 += quad[3 * i];
    q1 += quad[3 * i + 1];
    q2 += quad[3 * i + 2];
  };
  const int ne = d->ne, nf = d->nf, nefc = d->nefc;
  for (int i = 0; i < ne; ++i) add(i);
  for (int i = ne; i < ne + nf; ++i) {
    const double x = jaref[i] + alpha * jv[i];
    const double f = d->efc_frictionloss[i], bound = d->efc_R[i] * f;
    if (x > -bound && x < bound) {
      add(i);
    } else {  // linear: f |x| - f bound / 2
      const double sign = x <= -bound ? -1.0 : 1.0;
      q0 += f * (sign * jaref[i] - 0.5 * bound);
      q1 += f * sign * jv[i];
    }
  }
  for (int i = ne + nf; i < nefc;) {
    if (d->efc_type[i] != mjCNSTR_CONTACT_ELLIPTIC) {
      if (jaref[i] + alpha * jv[i] < 0.0) add(i);
      ++i;
      continue;
    }
    const double* e = &cone[kConeSlots * i];
    const double mu = e[6];
    const int dim = static_cast<int>(e[7]);
    const double n = e[0] + alpha * e[1];
    const double t2 = e[2] + alpha * (2.0 * e[3] + alpha * e[4]);
    if (t2 <= 0.0) {
      if (n < 0.0) {
        for (int j = 0; j < dim; ++j) add(i + j);
      }
    } else {
      const double t = std::sqrt(t2);
      if (n >= mu * t) {
        // top zone: no force
      } else if (mu * n + t <= 0.0) {
        for (int j = 0; j < dim; ++j) add(i + j);
      } else {
        const double t1 = (e[3] + alpha * e[4]) / t;
        const double tt = e[4] / t - (e[3] + alpha * e[4]) * t1 / t2;
        const double gap = n - mu * t, gap1 = e[1] - mu * t1;
        cost += 0.5 * e[5] * gap * gap;
        slope += e[5] * gap * gap1;
        curvature += e[5] * (gap1 * gap1 - gap * mu * tt);
      }
    }
    i += dim;
  }
  LinePoint p;
  p.alpha = alpha;
  p.cost = cost + q0 + alpha * (q1 + alpha * q2);
  p.slope = slope + q1 + 2.0 * alpha * q2;
  p.curvature = std::max(curvature + 2.0 * q2, mjMINVAL);
  return p;
}

// The step along `search` that minimises the cost: Newton's steps on the line's convex cost,
// bisection where one would leave the bracket. Returns 0 when no step lowers the cost.
double ConstraintSolver::Impl::line_search(const mjModel* m, mjData* d) {
  const int nv = m->nv;
  double norm = 0.0;
  for (int i = 0; i < nv; ++i) norm += search[i] * search[i];
  norm = std::sqrt(norm);
  if (norm < mjMINVAL) return 0.0;
  // MuJoCo's: the line's slope is small enough at this fraction of the tolerance, scaled.
  const double slope_tol = m->opt.tolerance * 0.01 * norm * m->stat.meaninertia * std::max(1, nv);
  mj_mulM(m, d, mv.data(), search.data());
  mul_j(search.data(), jv.data());
  prepare_line(m, d);
  const LinePoint p0 = evaluate(d, 0.0);
  if (p0.slope >= -slope_tol) return 0.0;  // not a descent (or converged along it)
  LinePoint lo = p0, hi;
  bool bracketed = false;
  LinePoint best = p0;
  double alpha = -p0.slope / p0.curvature;
  for (int k = 0; k < 50; ++k) {
    const LinePoint p = evaluate(d, alpha);
    if (p.cost < best.cost) best = p;
    if (std::abs(p.slope) < slope_tol) break;
    if (p.slope < 0.0) {
      lo = p;
    } else {
      hi = p;
      bracketed = true;
    }
    double next = p.alpha - p.slope / p.curvature;
    if (bracketed && !(next > lo.alpha && next < hi.alpha)) next = 0.5 * (lo.alpha + hi.alpha);
    if (next == p.alpha) break;
    alpha = next;
  }
  return best.alpha;
}

void ConstraintSolver::solve(const mjModel* m, mjData* d) {
  Impl& s = *impl_;
  const auto started = mjcb_time ? mjcb_time() : 0.0;
  const int nv = m->nv, nefc = d->nefc;
  if (nefc == 0) {
    mju_copy(d->qacc, d->qacc_smooth, nv);
    mju_copy(d->qacc_warmstart, d->qacc_smooth, nv);
    mju_zero(d->qfrc_constraint, nv);
    d->solver_iter = 0;
    return;
  }
  for (auto* v : {&s.ma, &s.mv, &s.grad, &s.pgrad, &s.search, &s.grad_old, &s.pgrad_old}) {
    v->resize(nv);
  }
  s.jaref.resize(nefc);
  s.jv.resize(nefc);
  s.quad.resize(3 * static_cast<size_t>(nefc));
  s.cone.resize(Impl::kConeSlots * static_cast<size_t>(nefc));

  // J's rows in blocks of shared columns (J is the step's: fixed while it is solved).
  s.collect_blocks(m, d);

  // efc_b = J qacc_smooth - aref; the start is the better of the warm start and qacc_smooth.
  s.mul_j(d->qacc_smooth, d->efc_b);
  mju_subFrom(d->efc_b, d->efc_aref, nefc);
  mju_copy(d->qacc, d->qacc_smooth, nv);
  bool from_smooth = true;
  if (!mjDISABLED(mjDSBL_WARMSTART)) {
    s.mul_j(d->qacc_warmstart, s.jaref.data());
    mju_subFrom(s.jaref.data(), d->efc_aref, nefc);
    double warm = s.constraint_update(m, d, s.jaref.data(), false);
    mj_mulM(m, d, s.ma.data(), d->qacc_warmstart);
    for (int i = 0; i < nv; ++i) {
      warm += 0.5 * (s.ma[i] - d->qfrc_smooth[i]) * (d->qacc_warmstart[i] - d->qacc_smooth[i]);
    }
    const double smooth = s.constraint_update(m, d, d->efc_b, false);
    if (warm <= smooth) {
      mju_copy(d->qacc, d->qacc_warmstart, nv);
      from_smooth = false;
    }
  }
  if (from_smooth) {
    // The start is qacc_smooth (its J qacc - aref is efc_b); otherwise jaref and ma are the warm
    // start's already.
    mju_copy(s.jaref.data(), d->efc_b, nefc);
    mj_mulM(m, d, s.ma.data(), d->qacc);
  }

  // The preconditioner: the Hessian at the constraint states of the point it is built at.
  Pattern& pattern = s.pattern_for(m);
  Structure& p = s.structure_for(m, pattern);
  const bool mapped = p.analysed && s.map_dest(m, p);
  bool factored = false;
  std::vector<int>& factored_state = s.factored_state;
  auto refactor = [&] {
    factored = false;
    if (mapped) {
      s.assemble(d, p);
      factored = p.factor.factorize();
    }
    if (!factored) ++s.fallbacks;
    factored_state.assign(d->efc_state, d->efc_state + nefc);
  };

  int since_factor = 0;
  // The preconditioner built here, and the search restarted along its Newton direction.
  auto restart = [&] {
    refactor();
    since_factor = 0;
    s.precondition(m, d, p, factored, s.grad.data(), s.pgrad.data());
    for (int i = 0; i < nv; ++i) s.search[i] = -s.pgrad[i];
  };

  double cost = s.update(m, d, d->qacc);
  restart();

  const double scale = 1.0 / (m->stat.meaninertia * std::max(1, nv));
  int iter = 0;
  while (iter < m->opt.iterations) {
    const double alpha = s.line_search(m, d);
    if (alpha == 0.0) {
      // No step lowers the cost along this direction: done, unless the preconditioner was built
      // at other constraint states (then once more along its fresh Newton direction).
      if (since_factor == 0 || !factored) break;
      restart();
      continue;
    }
    mju_addToScl(d->qacc, s.search.data(), alpha, nv);
    mju_addToScl(s.ma.data(), s.mv.data(), alpha, nv);
    mju_addToScl(s.jaref.data(), s.jv.data(), alpha, nefc);
    std::swap(s.grad, s.grad_old);
    std::swap(s.pgrad, s.pgrad_old);
    const double old_cost = cost;
    cost = s.update(m, d, d->qacc);
    ++iter;
    ++since_factor;
    const double improvement = (old_cost - cost) * scale;
    const double gradient = mju_norm(s.grad.data(), nv) * scale;
    if (gradient < m->opt.tolerance) break;
    int changed = 0;
    if (factored) {
      for (int i = 0; i < nefc; ++i) changed += factored_state[i] != d->efc_state[i];
    }
    const bool stale = changed > 0;
    const bool small = improvement < m->opt.tolerance;
    if (small && changed <= kStopChangedRows * nefc) break;
    if (stale && (small || since_factor >= kRefreshEvery)) {
      restart();
      continue;
    }
    s.precondition(m, d, p, factored, s.grad.data(), s.pgrad.data());
    // Polak-Ribiere, restarted when it turns negative or stops descending.
    double num = 0.0, den = 0.0;
    for (int i = 0; i < nv; ++i) {
      num += s.grad[i] * (s.pgrad[i] - s.pgrad_old[i]);
      den += s.grad_old[i] * s.pgrad_old[i];
    }
    const double beta = std::max(0.0, num / std::max(mjMINVAL, den));
    double descent = 0.0;
    for (int i = 0; i < nv; ++i) {
      s.search[i] = -s.pgrad[i] + beta * s.search[i];
      descent += s.search[i] * s.grad[i];
    }
    if (descent >= 0.0) {
      for (int i = 0; i < nv; ++i) s.search[i] = -s.pgrad[i];
    }
  }
  d->solver_iter = iter;
  d->solver_nnz = 0;
  mju_copy(d->qacc_warmstart, d->qacc, nv);
  if (mjcb_time) {
    d->timer[mjTIMER_CONSTRAINT].duration += mjcb_time() - started;
    d->timer[mjTIMER_CONSTRAINT].number++;
  }
}

}  // namespace pb
