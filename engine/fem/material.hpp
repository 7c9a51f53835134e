#pragma once
// Isotropic linear elastic material (small strain), SI units.
#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "mesh/tet_mesh.hpp"

namespace softcut::fem {

struct Material {
  double young = 3e3;     // Young's modulus E, Pa (soft tissue: 1e3 .. 1e5)
  double poisson = 0.45;  // Poisson's ratio nu, dimensionless, -1 < nu < 0.5
  // Initial strain eps0 (paper Sec. 5), Voigt [xx yy zz yz zx xy] with
  // engineering shears (gamma = 2 eps), dimensionless: the stress is
  // D (eps - eps0), so a body held at its rest shape with eps0 < 0 is under
  // tension (the tissue would shrink if freed) and a cut through it gapes.
  // A plain array keeps Material trivially copyable (the precompute cache
  // hashes its bytes). Split tets inherit it with the rest of the material.
  std::array<double, 6> initial_strain{};
};

// True when any component of the initial strain is nonzero.
bool has_initial_strain(const Material& mat);

// Throws softcut::Error naming `where` unless E > 0 (finite), -1 < nu < 0.5
// and every initial-strain tensor component (eps_xy = gamma_xy / 2) is finite
// with |value| <= kMaxInitialStrain.
// Linear (small-strain) elasticity stops meaning anything well below this.
constexpr double kMaxInitialStrain = 0.5;
void check_material(const Material& mat, const std::string& where);

// Voigt elasticity matrix D (6x6), strain order [xx yy zz yz zx xy] with
// engineering shear strains (gamma = 2 eps), stress in Pa.
Eigen::Matrix<double, 6, 6> elasticity_matrix(const Material& mat);

}  // namespace softcut::fem
