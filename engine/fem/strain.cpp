#include "fem/strain.hpp"

#include "core/error.hpp"
#include "fem/element_stiffness.hpp"

namespace softcut::fem {

StrainField element_strains(const mesh::TetMesh& m, const Eigen::MatrixX3d& u) {
  if (u.rows() != m.num_nodes())
    fail("element_strains: displacement field has ", u.rows(), " rows for ", m.num_nodes(), " nodes");
  StrainField eps(m.num_tets(), 6);
  for (int t = 0; t < m.num_tets(); ++t) {
    Eigen::Matrix<double, 12, 1> ue;
    for (int k = 0; k < 4; ++k) ue.segment<3>(3 * k) = u.row(m.tets(t, k)).transpose();
    eps.row(t) = (strain_displacement(tet_corners(m, t)) * ue).transpose();
  }
  return eps;
}

StrainField element_stresses(const mesh::TetMesh& m, const std::vector<Material>& tet_material,
                             const Eigen::MatrixX3d& u) {
  if (int(tet_material.size()) != m.num_tets())
    fail("element_stresses: ", tet_material.size(), " materials for ", m.num_tets(), " tetrahedra");
  StrainField sig = element_strains(m, u);
  for (int t = 0; t < m.num_tets(); ++t) {
    const Material& mat = tet_material[size_t(t)];
    const Eigen::Matrix<double, 6, 1> eps0 = Eigen::Map<const Eigen::Matrix<double, 6, 1>>(mat.initial_strain.data());
    sig.row(t) = (elasticity_matrix(mat) * (sig.row(t).transpose() - eps0)).transpose();
  }
  return sig;
}

}  // namespace softcut::fem
