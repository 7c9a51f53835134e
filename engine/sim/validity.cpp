#include "sim/validity.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>

#include "sim/cutting.hpp"

namespace softcut::sim {

Validity measure_validity(const Model& m, const State& s) {
  const mesh::TetMesh& mesh = current_mesh(m, s);
  const std::vector<fem::Material>& mat = s.cut ? s.cut->tet_material : m.tet_material;
  const std::vector<char>& op = s.cut ? s.cut->operational_tet : m.partition.operational_tet;
  const bool monolithic = m.solver->backend().backend == backend::Backend::monolithic;
  const bool whole_body = m.spec.solver.whole_body;
  const bool interior = m.solver->interior_valid();
  Validity v;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    const bool operational = op[size_t(t)] != 0;
    const bool linear_law = mat[size_t(t)].model == fem::MaterialModel::linear || (!operational && !whole_body);
    if (!linear_law) continue;  // its own law carries its rotation
    const bool condensed = !operational && !monolithic;
    bool solved = true;
    for (int k = 0; k < 4 && condensed && !interior; ++k) {
      const int n = mesh.tets(t, k);
      solved = !(n < m.mesh.num_nodes() && m.partition.node_set[size_t(n)] == hybrid::NodeSet::interior);
    }
    if (!solved) continue;
    Eigen::Matrix3d Dm, Du;
    for (int k = 0; k < 3; ++k) {
      Dm.col(k) = (mesh.node(mesh.tets(t, k + 1)) - mesh.node(mesh.tets(t, 0)));
      Du.col(k) = (s.displacement.row(mesh.tets(t, k + 1)) - s.displacement.row(mesh.tets(t, 0))).transpose();
    }
    const Eigen::Matrix3d G = Du * Dm.inverse();  // grad u
    const Eigen::Matrix3d W = 0.5 * (G - G.transpose());
    const double rotation = std::asin(std::min(1.0, Eigen::Vector3d(W(2, 1), W(0, 2), W(1, 0)).norm()));
    if (condensed) {
      if (rotation > v.condensed_rotation) v.condensed_rotation = rotation, v.condensed_tet = t;
      continue;
    }
    const double strain =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(0.5 * (G + G.transpose()), Eigen::EigenvaluesOnly)
            .eigenvalues()
            .cwiseAbs()
            .maxCoeff();
    if (rotation > v.linear_rotation) v.linear_rotation = rotation, v.linear_tet = t;
    v.linear_strain = std::max(v.linear_strain, strain);
  }
  return v;
}

}  // namespace softcut::sim
