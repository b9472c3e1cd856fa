// SPDX-License-Identifier: MIT
#include "core/physics/block_cholesky.hpp"

#include <Eigen/Dense>
#include <Eigen/OrderingMethods>
#include <Eigen/SparseCore>
#include <algorithm>
#include <array>

namespace pb {

bool BlockCholesky::analyse(const std::vector<int>& first, const std::vector<int>& size,
                            const std::vector<std::vector<int>>& couples) {
  const int n = static_cast<int>(first.size());
  groups_.clear();
  values_.clear();
  unknowns_ = 0;  // (position() holds nothing until the analysis succeeds)
  if (size.size() != first.size() || couples.size() != first.size()) return false;
  int unknowns = 0;
  for (int g = 0; g < n; ++g) {
    if (size[g] <= 0 || first[g] < 0) return false;
    unknowns = std::max(unknowns, first[g] + size[g]);
  }
  group_of_.assign(unknowns, -1);
  for (int g = 0; g < n; ++g) {
    for (int u = first[g]; u < first[g] + size[g]; ++u) {
      if (group_of_[u] >= 0) return false;
      group_of_[u] = g;
    }
  }
  if (std::count(group_of_.begin(), group_of_.end(), -1) > 0) return false;

  // The groups' graph, both ways round, and its fill-reducing order (AMD).
  std::vector<std::vector<int>> adjacent(n);
  std::vector<Eigen::Triplet<double, int>> entries;
  for (int g = 0; g < n; ++g) {
    entries.emplace_back(g, g, 1.0);
    for (int h : couples[g]) {
      if (h < 0 || h >= n) return false;
      if (h == g) continue;
      adjacent[g].push_back(h);
      adjacent[h].push_back(g);
      entries.emplace_back(g, h, 1.0);
      entries.emplace_back(h, g, 1.0);
    }
  }
  Eigen::SparseMatrix<double, Eigen::ColMajor, int> graph(n, n);
  graph.setFromTriplets(entries.begin(), entries.end());
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> order;
  Eigen::AMDOrdering<int>()(graph, order);  // order.indices()[k]: the k-th group eliminated
  rank_.assign(n, 0);
  for (int k = 0; k < n; ++k) rank_[order.indices()[k]] = k;

  // The factor's column structure by elimination: a group's column holds the later groups it
  // couples to, and whatever its children in the elimination tree hold below it.
  groups_.resize(n);
  std::vector<std::vector<int>> children(n);
  for (int k = 0; k < n; ++k) {
    const int g = order.indices()[k];
    Group& col = groups_[k];
    col.first = first[g];
    col.size = size[g];
    std::vector<int>& below = col.below;
    for (int h : adjacent[g]) {
      if (rank_[h] > k) below.push_back(rank_[h]);
    }
    for (int c : children[k]) {
      for (int r : groups_[c].below) {
        if (r > k) below.push_back(r);
      }
    }
    std::sort(below.begin(), below.end());
    below.erase(std::unique(below.begin(), below.end()), below.end());
    if (!below.empty()) children[below.front()].push_back(k);
  }
  // Every block is width_ x width_ (a smaller group padded with unknowns of its own that nothing
  // couples to, their diagonal 1), so that the arithmetic has one fixed size.
  width_ = 0;
  for (const Group& col : groups_) width_ = std::max(width_, col.size);
  if (width_ <= kWidth) width_ = kWidth;
  const int square = width_ * width_;
  int at = 0;
  for (Group& col : groups_) {
    col.diagonal = at;
    at += square;
    col.offsets.clear();
    for (std::size_t a = 0; a < col.below.size(); ++a) {
      col.offsets.push_back(at);
      at += square;
    }
  }
  values_.assign(at, 0.0);
  padded_.assign(groups_.size() * width_, 0.0);
  unknowns_ = unknowns;
  return true;
}

int BlockCholesky::block(int i, int j) const {
  const Group& col = groups_[j];
  const auto it = std::lower_bound(col.below.begin(), col.below.end(), i);
  if (it == col.below.end() || *it != i) return -1;
  return col.offsets[it - col.below.begin()];
}

int BlockCholesky::position(int r, int c) const {
  if (r < 0 || c < 0 || r >= unknowns_ || c >= unknowns_) return -1;
  int i = rank_[group_of_[r]], j = rank_[group_of_[c]];
  if (i == j && r < c) return -1;
  if (i < j) {
    std::swap(i, j);
    std::swap(r, c);
  }
  const int at = i == j ? groups_[j].diagonal : block(i, j);
  if (at < 0) return -1;
  return at + (r - groups_[i].first) + (c - groups_[j].first) * width_;
}

bool BlockCholesky::positions(const int* cols, int k, std::vector<int>& out) const {
  // Each column's group (its rank, by its index in `ranks`) and place in that group, found once;
  // then each pair of the block's groups (a contact block spans two) is looked up once.
  constexpr int kMaxCols = 32, kMaxGroups = 4;
  std::array<int, kMaxCols> group{}, place{};
  std::array<int, kMaxGroups> ranks{};
  int n = 0;
  bool tabled = k <= kMaxCols;
  for (int x = 0; x < k && tabled; ++x) {
    const int u = cols[x];
    group[x] = -1;
    if (u < 0 || u >= unknowns_) continue;
    const int r = rank_[group_of_[u]];
    int g = 0;
    while (g < n && ranks[g] != r) ++g;
    if (g == kMaxGroups) {
      tabled = false;
      break;
    }
    if (g == n) ranks[n++] = r;
    group[x] = g;
    place[x] = u - groups_[r].first;
  }
  bool held = true;
  if (!tabled) {  // wider than the table (no contact block is): entry by entry
    for (int y = 0; y < k; ++y) {
      for (int x = y; x < k; ++x) {
        out.push_back(position(cols[x], cols[y]));
        held = held && out.back() >= 0;
      }
    }
    return held;
  }
  std::array<std::array<int, kMaxGroups>, kMaxGroups> base{};  // (-1: the factor holds none)
  for (int a = 0; a < n; ++a) {
    for (int b = 0; b <= a; ++b) {
      const int i = std::max(ranks[a], ranks[b]), j = std::min(ranks[a], ranks[b]);
      base[a][b] = base[b][a] = i == j ? groups_[j].diagonal : block(i, j);
    }
  }
  for (int y = 0; y < k; ++y) {
    for (int x = y; x < k; ++x) {
      const int gx = group[x], gy = group[y];
      int at = -1;  // as position(cols[x], cols[y])
      if (gx >= 0 && gy >= 0 && base[gx][gy] >= 0 && (gx != gy || cols[x] >= cols[y])) {
        const bool swapped = ranks[gx] < ranks[gy];
        at = base[gx][gy] + (swapped ? place[y] + place[x] * width_ : place[x] + place[y] * width_);
      }
      out.push_back(at);
      held = held && at >= 0;
    }
  }
  return held;
}

// The factorization and the solve, every block S x S: kWidth unrolled, or Eigen::Dynamic (a
// group wider than kWidth; then `w` wide).
template <int S>
struct BlockKernels {
  using Square = Eigen::Matrix<double, S, S>;
  using Block = Eigen::Map<Square>;
  using ConstBlock = Eigen::Map<const Square>;
  using Segment = Eigen::Map<Eigen::Matrix<double, S, 1>>;

  static bool factorize(const BlockCholesky& f, double* v, int w) {
    const auto& groups = f.groups_;
    for (const auto& col : groups) {  // the padding's diagonal
      for (int p = col.size; p < w; ++p) v[col.diagonal + p * (w + 1)] = 1.0;
    }
    for (const auto& col : groups) {
      Block diag(v + col.diagonal, w, w);
      Eigen::LLT<Eigen::Ref<Square>> llt(diag);  // in place: L in the lower triangle
      if (llt.info() != Eigen::Success) return false;
      const auto lower = diag.template triangularView<Eigen::Lower>();
      for (const int at : col.offsets) {  // L_ij = A_ij L_jj^-T
        Block lij(v + at, w, w);
        lower.transpose().template solveInPlace<Eigen::OnTheRight>(lij);
      }
      for (std::size_t a = 0; a < col.below.size(); ++a) {  // A_ik -= L_ij L_kj' (i >= k)
        const int i = col.below[a];
        const ConstBlock lij(v + col.offsets[a], w, w);
        for (std::size_t b = 0; b <= a; ++b) {
          const int k = col.below[b];
          const ConstBlock lkj(v + col.offsets[b], w, w);
          Block target(v + (i == k ? groups[k].diagonal : f.block(i, k)), w, w);
          target.noalias() -= lij.lazyProduct(lkj.transpose());
        }
      }
    }
    return true;
  }

  static void solve(const BlockCholesky& f, const double* v, double* x, int w) {
    const auto& groups = f.groups_;
    const int n = static_cast<int>(groups.size());
    for (int j = 0; j < n; ++j) {  // L y = b
      const auto& col = groups[j];
      Segment yj(x + j * w, w);
      ConstBlock(v + col.diagonal, w, w).template triangularView<Eigen::Lower>().solveInPlace(yj);
      for (std::size_t a = 0; a < col.below.size(); ++a) {
        Segment(x + col.below[a] * w, w).noalias() -=
            ConstBlock(v + col.offsets[a], w, w).lazyProduct(yj);
      }
    }
    for (int j = n - 1; j >= 0; --j) {  // L' x = y
      const auto& col = groups[j];
      Segment xj(x + j * w, w);
      for (std::size_t a = 0; a < col.below.size(); ++a) {
        xj.noalias() -= ConstBlock(v + col.offsets[a], w, w)
                            .transpose()
                            .lazyProduct(Segment(x + col.below[a] * w, w));
      }
      ConstBlock(v + col.diagonal, w, w)
          .transpose()
          .template triangularView<Eigen::Upper>()
          .solveInPlace(xj);
    }
  }
};

bool BlockCholesky::factorize() {
  return width_ == kWidth ? BlockKernels<kWidth>::factorize(*this, values_.data(), width_)
                          : BlockKernels<Eigen::Dynamic>::factorize(*this, values_.data(), width_);
}

void BlockCholesky::solve(const double* b, double* x) {
  double* y = padded_.data();
  for (std::size_t j = 0; j < groups_.size(); ++j) {
    const Group& g = groups_[j];
    std::copy(b + g.first, b + g.first + g.size, y + j * width_);
  }
  if (width_ == kWidth) {
    BlockKernels<kWidth>::solve(*this, values_.data(), y, width_);
  } else {
    BlockKernels<Eigen::Dynamic>::solve(*this, values_.data(), y, width_);
  }
  for (std::size_t j = 0; j < groups_.size(); ++j) {
    const Group& g = groups_[j];
    std::copy(y + j * width_, y + j * width_ + g.size, x + g.first);
  }
}

}  // namespace pb
