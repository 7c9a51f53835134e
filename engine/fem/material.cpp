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
  // Tensor components within +-kMaxInitialStrain: the engineering shears
  // stored here (gamma = 2 eps) within twice that; messages name the tensor value.
  static const char* const kNames[6] = {"xx", "yy", "zz", "yz", "zx", "xy"};
  for (int k = 0; k < 6; ++k) {
    const double e = k < 3 ? mat.initial_strain[size_t(k)] : 0.5 * mat.initial_strain[size_t(k)];
    if (!(std::isfinite(e) && std::abs(e) <= kMaxInitialStrain))
      fail(where, ": initial strain component eps_", kNames[k], " must be a finite number within +-", kMaxInitialStrain,
           " (a small-strain model), got ", e);
  }
}

bool has_initial_strain(const Material& mat) {
  for (double e : mat.initial_strain)
    if (e != 0) return true;
  return false;
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
