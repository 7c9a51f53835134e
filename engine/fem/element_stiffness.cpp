#include "fem/element_stiffness.hpp"

#include <Eigen/LU>

namespace softcut::fem {

Mat6x12 strain_displacement(const TetCorners& X, double* volume) {
  Eigen::Matrix3d J;  // columns: edges from node 0
  for (int k = 0; k < 3; ++k) J.col(k) = (X.row(k + 1) - X.row(0)).transpose();
  if (volume) *volume = J.determinant() / 6.0;
  // Shape-function gradients: rows of J^{-1} for nodes 1..3, node 0 = -sum.
  const Eigen::Matrix3d Jinv = J.inverse();
  Eigen::Matrix<double, 4, 3> G;
  G.bottomRows<3>() = Jinv;
  G.row(0) = -Jinv.colwise().sum();
  Mat6x12 B = Mat6x12::Zero();
  for (int a = 0; a < 4; ++a) {
    const double gx = G(a, 0), gy = G(a, 1), gz = G(a, 2);
    const int c = 3 * a;
    B(0, c + 0) = gx;
    B(1, c + 1) = gy;
    B(2, c + 2) = gz;
    B(3, c + 1) = gz;  // gamma_yz = du_y/dz + du_z/dy
    B(3, c + 2) = gy;
    B(4, c + 0) = gz;  // gamma_zx = du_z/dx + du_x/dz
    B(4, c + 2) = gx;
    B(5, c + 0) = gy;  // gamma_xy = du_x/dy + du_y/dx
    B(5, c + 1) = gx;
  }
  return B;
}

Mat12 element_stiffness(const TetCorners& X, const Material& mat) {
  double V = 0;
  const Mat6x12 B = strain_displacement(X, &V);
  const Mat12 K = V * (B.transpose() * elasticity_matrix(mat) * B);
  return 0.5 * (K + K.transpose());  // exact symmetry for the Cholesky factor
}

TetCorners tet_corners(const mesh::TetMesh& m, int t) {
  TetCorners X;
  for (int k = 0; k < 4; ++k) X.row(k) = m.nodes.row(m.tets(t, k));
  return X;
}

}  // namespace softcut::fem
