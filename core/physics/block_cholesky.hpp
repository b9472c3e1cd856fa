// SPDX-License-Identifier: MIT
// A sparse Cholesky factorization whose unknowns come in small dense groups (a body's degrees of
// freedom): its ordering, its fill and its arithmetic are per group. A step's Hessian couples a
// body's six degrees of freedom densely with each other and with those of the bodies it touches,
// so a scalar sparse factorization (Eigen's SimplicialLLT) spends its time on indices and on one
// coefficient at a time; here each update is a small dense product, and the symbolic work (the
// fill-reducing ordering, the elimination tree) is done on a graph a sixth the size.
#pragma once

#include <vector>

namespace pb {

class BlockCholesky {
 public:
  /// The structure of a symmetric matrix of `first.size()` groups of unknowns: group g is the
  /// `size[g]` consecutive unknowns from `first[g]` (together they number every unknown once);
  /// `couples[g]` lists the other groups its block row holds (either way round is enough). Orders
  /// the groups (AMD) and lays out the factor's blocks. False for groups that do not number every
  /// unknown once, a group without unknowns, or a coupling out of range.
  bool analyse(const std::vector<int>& first, const std::vector<int>& size,
               const std::vector<std::vector<int>>& couples);

  /// Where the matrix entry (r, c) of the structure goes in values(), r and c unknowns: for two
  /// groups, either way round; within one group, r >= c (only the lower triangle of a group's own
  /// block is read). -1 when the structure holds no such entry.
  int position(int r, int c) const;
  /// position() of every entry (cols[x], cols[y]), x >= y, of the dense block over the `k`
  /// unknowns `cols` (ascending), appended to `out` column by column (y, then x from y): each
  /// column's group found once and one search per pair of groups, instead of both per entry (a
  /// step maps every contact block's).
  /// False when the structure does not hold some entry (its position is -1).
  bool positions(const int* cols, int k, std::vector<int>& out) const;

  /// The values: all zeroed, then the matrix's entries set at their position(), before each
  /// factorize() (which overwrites them with the factor; the fill and the padding must be 0).
  double* values() { return values_.data(); }
  int value_count() const { return static_cast<int>(values_.size()); }

  /// L L' = the matrix held in values(); false when it is not positive definite.
  bool factorize();
  /// x = (L L')^-1 b (x and b may be the same), after factorize() succeeded.
  void solve(const double* b, double* x);

 private:
  template <int S>
  friend struct BlockKernels;
  // Blocks are at least this wide: a free body's six degrees of freedom.
  static constexpr int kWidth = 6;
  struct Group {
    int first = 0, size = 0;
    int diagonal = 0;          // offset of its own block (width_ x width_, column-major)
    std::vector<int> below;    // the later groups (in elimination order) its factor column holds
    std::vector<int> offsets;  // each one's block (width_ x width_, column-major)
  };
  std::vector<Group> groups_;  // in elimination order
  std::vector<int> rank_;      // a group's place in that order, by its index in analyse()'s lists
  std::vector<int> group_of_;  // an unknown's group (its index in analyse()'s lists)
  std::vector<double> values_;
  std::vector<double> padded_;  // solve()'s vector, a block of width_ per group, in order
  int unknowns_ = 0;
  int width_ = kWidth;  // of every block: the widest group, at least kWidth

  int block(int i, int j) const;  // offset of block (i, j), i after j in the order; -1 if none
};

}  // namespace pb
