#include "fem/material.hpp"

#include <cmath>

#include "core/error.hpp"

namespace softcut::fem {

void check_material(const Material& mat, const std::string& where) {
  if (!(std::isfinite(mat.young) && mat.young > 0))
    fail(where, ": Young's modulus must be a positive number of pascals, got ", mat.young);
  if (!(mat.poisson > -1.0 && mat.poisson < 0.5))
    fail(where, ": Poisson's ratio must lie in (-1, 0.5), got ", mat.poisson,
         " (0.5 is incompressible and makes linear tets lock)");
}

Eigen::Matrix<double, 6, 6> elasticity_matrix(const Material& mat) {
  const double E = mat.young, nu = mat.poisson;
  const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
  const double mu = E / (2 * (1 + nu));
  Eigen::Matrix<double, 6, 6> D = Eigen::Matrix<double, 6, 6>::Zero();
  D.topLeftCorner<3, 3>().setConstant(lambda);
  D.topLeftCorner<3, 3>().diagonal().array() += 2 * mu;
  D.bottomRightCorner<3, 3>().diagonal().setConstant(mu);
  return D;
}

}  // namespace softcut::fem
