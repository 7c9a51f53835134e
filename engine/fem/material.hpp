#pragma once
// Isotropic linear elastic material (small strain), SI units.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "mesh/tet_mesh.hpp"

namespace softcut::fem {

// The constitutive law of a tet (fem/hyperelastic.hpp):
//   linear        the paper's small-strain elasticity, K u = f (default)
//   corotational  linear elasticity in each tet's rotated frame: exact under
//                 large rotations, moderate strains (SOFA's default)
//   neohookean    compressible neo-Hooke (CalculiX's NEO HOOKE form), for
//                 large stretch
// Only operational tets (or every tet of a whole-body solve) use a nonlinear
// law; the condensed region is linear by construction. 64-bit so Material
// has no padding (its bytes key the precompute cache).
enum class MaterialModel : std::int64_t { linear, corotational, neohookean };
const char* to_string(MaterialModel m);
// The names users write: "linear", "corotational", "neohookean". Throws
// softcut::Error naming the accepted values (with a did-you-mean).
MaterialModel parse_material_model(std::string_view text);

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
  // Body force per unit rest volume, N/m^3 (gravity: density x g), a dead
  // load: each tet gives V b / 4 to its corners. Split tets inherit it.
  std::array<double, 3> body_force{};
  MaterialModel model = MaterialModel::linear;
};
static_assert(sizeof(Material) == 12 * sizeof(double), "Material's bytes key the precompute cache: no padding");

// True when any component of the initial strain is nonzero.
bool has_initial_strain(const Material& mat);
// True when the body force is nonzero.
bool has_body_force(const Material& mat);

// Throws softcut::Error naming `where` unless E > 0 (finite), -1 < nu < 0.5
// and every initial-strain tensor component (eps_xy = gamma_xy / 2) is finite
// with |value| <= kMaxInitialStrain.
// Linear (small-strain) elasticity stops meaning anything well below this.
constexpr double kMaxInitialStrain = 0.5;
constexpr double kMaxBodyForce = 1e7;  // N/m^3
void check_material(const Material& mat, const std::string& where);

// Voigt elasticity matrix D (6x6), strain order [xx yy zz yz zx xy] with
// engineering shear strains (gamma = 2 eps), stress in Pa.
Eigen::Matrix<double, 6, 6> elasticity_matrix(const Material& mat);

}  // namespace softcut::fem
