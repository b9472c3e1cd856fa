// SPDX-License-Identifier: MIT
// The block factorization against Eigen's dense one on the same symmetric positive definite
// matrices: a chain and a ring of bodies (fill), groups of six (free bodies), of two (the belt's
// slides) and of seven (wider than the unrolled blocks), and what it refuses.
#include "core/physics/block_cholesky.hpp"

#include <QtTest>

#include <Eigen/Dense>
#include <numeric>
#include <random>
#include <vector>

using namespace pb;

namespace {

struct Problem {
  std::vector<int> first, size;
  std::vector<std::vector<int>> couples;
  Eigen::MatrixXd matrix;  // dense, with the couplings' pattern
};

// Groups of `sizes`, consecutive unknowns; group g coupled to g + 1 (and the last to the first when
// `ring`), and every group to group 0 when `hub` (a pallet under its cartons). Diagonally dominant.
Problem make(const std::vector<int>& sizes, bool ring, bool hub, unsigned seed) {
  Problem p;
  int n = 0;
  for (int s : sizes) {
    p.first.push_back(n);
    p.size.push_back(s);
    n += s;
  }
  const int groups = static_cast<int>(sizes.size());
  p.couples.resize(groups);
  for (int g = 0; g + 1 < groups; ++g) p.couples[g].push_back(g + 1);
  if (ring && groups > 2) p.couples[0].push_back(groups - 1);
  if (hub) {
    for (int g = 2; g < groups; ++g) p.couples[g].push_back(0);  // listed the other way round
  }
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  p.matrix = Eigen::MatrixXd::Zero(n, n);
  auto fill = [&](int g, int h) {
    for (int r = 0; r < sizes[g]; ++r) {
      for (int c = 0; c < sizes[h]; ++c) {
        const double v = u(rng);
        p.matrix(p.first[g] + r, p.first[h] + c) += v;
        p.matrix(p.first[h] + c, p.first[g] + r) += v;
      }
    }
  };
  for (int g = 0; g < groups; ++g) {
    fill(g, g);
    for (int h : p.couples[g]) fill(g, h);
  }
  for (int i = 0; i < n; ++i) p.matrix(i, i) = std::abs(p.matrix(i, i)) + 2.0 * n;
  return p;
}

// Sets `f`'s values from the matrix through position(), as the constraint solve assembles.
bool load(BlockCholesky& f, const Problem& p) {
  std::fill(f.values(), f.values() + f.value_count(), 0.0);
  const int n = static_cast<int>(p.matrix.rows());
  for (int c = 0; c < n; ++c) {
    for (int r = c; r < n; ++r) {
      if (p.matrix(r, c) == 0.0) continue;
      const int at = f.position(r, c);
      if (at < 0) return false;
      f.values()[at] = p.matrix(r, c);
    }
  }
  return true;
}

double solve_error(const Problem& p) {
  BlockCholesky f;
  if (!f.analyse(p.first, p.size, p.couples) || !load(f, p) || !f.factorize()) return 1.0;
  const int n = static_cast<int>(p.matrix.rows());
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::VectorXd b(n);
  for (int i = 0; i < n; ++i) b[i] = u(rng);
  Eigen::VectorXd x(n);
  f.solve(b.data(), x.data());
  const Eigen::VectorXd expected = p.matrix.llt().solve(b);
  return (x - expected).norm() / expected.norm();
}

}  // namespace

class BlockCholeskyTest : public QObject {
  Q_OBJECT

 private slots:
  void solvesAChainOfFreeBodies() {
    QVERIFY(solve_error(make({6, 6, 6, 6, 6}, false, false, 1)) < 1e-12);
  }

  void solvesARingWithItsFill() {
    QVERIFY(solve_error(make({6, 6, 6, 6, 6, 6, 6, 6}, true, false, 2)) < 1e-12);
  }

  void solvesABeltsTwoSlidesBesideFreeBodies() {
    QVERIFY(solve_error(make({2, 6, 6, 6, 6, 6}, false, true, 3)) < 1e-12);
  }

  void solvesGroupsWiderThanSix() {
    QVERIFY(solve_error(make({7, 6, 3, 6, 1}, true, true, 4)) < 1e-12);
  }

  void solvesInPlace() {
    const Problem p = make({2, 6, 6, 6}, true, true, 5);
    BlockCholesky f;
    QVERIFY(f.analyse(p.first, p.size, p.couples));
    QVERIFY(load(f, p));
    QVERIFY(f.factorize());
    Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(p.matrix.rows(), -1.0, 1.0);
    const Eigen::VectorXd expected = p.matrix.llt().solve(b);
    f.solve(b.data(), b.data());
    QVERIFY((b - expected).norm() < 1e-12 * expected.norm());
  }

  // Entries the structure does not hold have no position: an upper-triangle entry of a group's own
  // block, two groups nothing couples, an unknown out of range.
  void holdsOnlyItsStructure() {
    BlockCholesky f;
    QVERIFY(f.analyse({0, 6, 12}, {6, 6, 6}, {{1}, {}, {}}));
    QCOMPARE(f.position(0, 5), -1);
    QVERIFY(f.position(5, 0) >= 0);
    QVERIFY(f.position(6, 0) >= 0);
    QCOMPARE(f.position(0, 6), f.position(6, 0));  // either way round
    QCOMPARE(f.position(12, 0), -1);
    QCOMPARE(f.position(12, 6), -1);
    QCOMPARE(f.position(18, 0), -1);
  }

  // A dense block's positions, found once per pair of groups, are position()'s entry by entry:
  // blocks over one group, over coupled groups whichever the elimination order puts first (a hub
  // with a ring's fill, a belt's two slides, groups of 7), with and without entries the structure
  // lacks.
  void placesADenseBlockAsEntryByEntry() {
    for (const bool ring : {false, true}) {
      const Problem p = make({2, 6, 6, 7, 6, 6, 6}, ring, true, 3);
      BlockCholesky f;
      QVERIFY(f.analyse(p.first, p.size, p.couples));
      std::vector<int> every_unknown(39);
      std::iota(every_unknown.begin(), every_unknown.end(), 0);
      const std::vector<std::vector<int>> blocks = {
          {2, 3, 4, 5, 6, 7},                                  // one group
          {0, 1, 2, 3, 4, 5, 6, 7},                            // the slides and a body
          {8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20},  // 6 + 7 wide
          {0, 1, 27, 28, 29, 30, 31, 32},                      // two groups the hub couples
          {1, 3, 14, 20, 33, 37},                              // some columns of several
          {0, 3, 9, 15, 22, 28},                               // six groups (more than tabled)
          every_unknown,                                       // 39 columns (more than tabled)
          {14, 15, 33, 34},                                    // two groups nothing couples
          {7, 5, 3},                                           // not ascending
          {3, 4, 1000},                                        // out of range
      };
      for (const auto& cols : blocks) {
        std::vector<int> out{42};  // appended to
        const bool held = f.positions(cols.data(), static_cast<int>(cols.size()), out);
        bool all = true;
        std::size_t at = 1;
        for (std::size_t y = 0; y < cols.size(); ++y) {
          for (std::size_t x = y; x < cols.size(); ++x, ++at) {
            QVERIFY(at < out.size());
            QCOMPARE(out[at], f.position(cols[x], cols[y]));
            all = all && out[at] >= 0;
          }
        }
        QCOMPARE(out.size(), at);
        QCOMPARE(out.front(), 42);
        QCOMPARE(held, all);
      }
    }
  }

  void refusesAMatrixThatIsNotPositiveDefinite() {
    Problem p = make({6, 6, 6}, false, false, 8);
    p.matrix(7, 7) = -1.0;
    BlockCholesky f;
    QVERIFY(f.analyse(p.first, p.size, p.couples));
    QVERIFY(load(f, p));
    QVERIFY(!f.factorize());
  }

  void refusesGroupsThatDoNotNumberEveryUnknownOnce() {
    BlockCholesky f;
    QVERIFY(!f.analyse({0, 4}, {6, 6}, {{}, {}}));   // overlapping
    QVERIFY(!f.analyse({0, 7}, {6, 6}, {{}, {}}));   // a gap
    QVERIFY(!f.analyse({0, 6}, {6, 0}, {{}, {}}));   // an empty group
    QVERIFY(!f.analyse({0, 6}, {6, 6}, {{2}, {}}));  // a coupling out of range
    QCOMPARE(f.position(0, 0), -1);                  // and a failed analysis holds nothing
  }
};

QTEST_APPLESS_MAIN(BlockCholeskyTest)
#include "block_cholesky_test.moc"
