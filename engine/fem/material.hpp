#pragma once
// Isotropic linear elastic material (small strain), SI units.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "mesh/tet_mesh.hpp"

namespace softcut::fem {

struct Material {
  double young = 3e3;     // Young's modulus E, Pa (soft tissue: 1e3 .. 1e5)
  double poisson = 0.45;  // Poisson's ratio nu, dimensionless, -1 < nu < 0.5
};

// Throws softcut::Error naming `where` unless E > 0 (finite) and -1 < nu < 0.5.
void check_material(const Material& mat, const std::string& where);

// Voigt elasticity matrix D (6x6), strain order [xx yy zz yz zx xy] with
// engineering shear strains (gamma = 2 eps), stress in Pa.
Eigen::Matrix<double, 6, 6> elasticity_matrix(const Material& mat);

}  // namespace softcut::fem
