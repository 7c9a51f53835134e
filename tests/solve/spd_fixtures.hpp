#pragma once
// Symmetric positive definite test matrices with 3x3 node blocks, built
// without the fem stage (test_solve links only softcut_solve).
#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <random>
#include <vector>

namespace softcut::test {

// Elasticity-like operator on an n^3 grid of nodes: each grid edge (i, j)
// adds (e_i - e_j)(e_i - e_j)^T (x) S_ij with S_ij random SPD 3x3 (weights
// spanning `contrast`), and nodes of the face x = 0 get their blocks raised
// by the identity times the mean weight (a clamp), which makes it definite.
inline Eigen::SparseMatrix<double> grid_spd(int n, unsigned seed, double contrast = 100) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Eigen::Triplet<double>> trip;
  auto id = [n](int i, int j, int k) { return i + n * (j + n * k); };
  auto add_block = [&](int a, int b, const Eigen::Matrix3d& S) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) trip.emplace_back(3 * a + r, 3 * b + c, S(r, c));
  };
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const int a = id(i, j, k);
        if (i == 0) add_block(a, a, Eigen::Matrix3d::Identity() * std::sqrt(contrast));
        for (int axis = 0; axis < 3; ++axis) {
          int c[3] = {i, j, k};
          if (++c[axis] >= n) continue;
          const int b = id(c[0], c[1], c[2]);
          Eigen::Matrix3d M;
          for (int e = 0; e < 9; ++e) M(e) = u(rng) - 0.5;
          const Eigen::Matrix3d S = std::pow(contrast, u(rng)) * (M * M.transpose() + 0.3 * Eigen::Matrix3d::Identity());
          add_block(a, a, S);
          add_block(b, b, S);
          add_block(a, b, -S);
          add_block(b, a, -S);
        }
      }
  Eigen::SparseMatrix<double> A(3 * n * n * n, 3 * n * n * n);
  A.setFromTriplets(trip.begin(), trip.end());
  return A;
}

}  // namespace softcut::test
