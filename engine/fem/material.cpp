#include "fem/material.hpp"

#include <cmath>

#include "core/error.hpp"
#include "core/suggest.hpp"

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
  for (int k = 0; k < 3; ++k)
    if (!(std::isfinite(mat.body_force[size_t(k)]) && std::abs(mat.body_force[size_t(k)]) <= kMaxBodyForce))
      fail(where, ": body force component ", "xyz"[k], " must be a finite number within +-", kMaxBodyForce,
           " N/m^3 (1000 g on water), got ", mat.body_force[size_t(k)]);
  if (mat.model != MaterialModel::linear && mat.model != MaterialModel::corotational &&
      mat.model != MaterialModel::neohookean)
    fail(where, ": unknown material model ", std::int64_t(mat.model));
}

const char* to_string(MaterialModel m) {
  switch (m) {
    case MaterialModel::linear: return "linear";
    case MaterialModel::corotational: return "corotational";
    case MaterialModel::neohookean: return "neohookean";
  }
  return "?";
}

MaterialModel parse_material_model(std::string_view text) {
  for (MaterialModel m : {MaterialModel::linear, MaterialModel::corotational, MaterialModel::neohookean})
    if (text == to_string(m)) return m;
  fail("unknown material model '", text, "'", suggest(text, {"linear", "corotational", "neohookean"}));
}

bool has_body_force(const Material& mat) {
  return mat.body_force[0] != 0 || mat.body_force[1] != 0 || mat.body_force[2] != 0;
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
