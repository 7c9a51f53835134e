#include "fem/whole_mesh.hpp"

#include "core/error.hpp"
#include "core/timer.hpp"

namespace softcut::fem {

WholeMesh::WholeMesh(const mesh::TetMesh& m, const std::vector<Material>& tet_material,
                     const std::vector<char>& node_fixed)
    : nnode_(m.num_nodes()) {
  const Timer t;
  if (int(node_fixed.size()) != nnode_)
    fail("whole-mesh system: node_fixed has ", node_fixed.size(), " entries for ", nnode_, " nodes");
  const std::vector<char> used = mesh::referenced_nodes(m);
  std::vector<char> free(used.size());
  for (size_t v = 0; v < used.size(); ++v) free[v] = used[v] && !node_fixed[v];
  map_ = make_dof_map(free);
  K_ = restrict_matrix(assemble_stiffness(m, tet_material), map_);
  if (any_initial_strain(tet_material)) f0_ = restrict_vector(flatten(initial_strain_forces(m, tet_material)), map_);
  assemble_ms_ = t.ms();
}

Eigen::VectorXd WholeMesh::load(const Eigen::MatrixX3d& forces) const {
  if (forces.rows() != nnode_) fail("whole-mesh system: forces have ", forces.rows(), " rows for ", nnode_, " nodes");
  Eigen::VectorXd f = restrict_vector(flatten(forces), map_);
  if (f0_.size() > 0) f += f0_;
  return f;
}

Eigen::MatrixX3d WholeMesh::field(const Eigen::VectorXd& x) const { return unflatten(expand_vector(x, map_, nnode_)); }

WholeMeshSolver::WholeMeshSolver(const mesh::TetMesh& m, const std::vector<Material>& tet_material,
                                 const std::vector<char>& node_fixed, const std::string& what, double max_bytes)
    : sys_(m, tet_material, node_fixed) {
  const Timer t;
  if (sys_.dofs().size() > 0) factor_.factor(sys_.K(), what, max_bytes);
  factor_ms_ = t.ms();
}

Eigen::MatrixX3d WholeMeshSolver::solve(const Eigen::MatrixX3d& forces, double* relative_residual) const {
  const Eigen::VectorXd f = sys_.load(forces);
  const bool loaded = f.squaredNorm() > 0;
  const Eigen::VectorXd x = loaded ? factor_.solve(f) : Eigen::VectorXd::Zero(f.size());
  if (relative_residual) *relative_residual = loaded ? (f - sys_.K() * x).norm() / f.norm() : 0.0;
  return sys_.field(x);
}

Eigen::MatrixXd WholeMeshSolver::unit_responses(const std::vector<int>& nodes) const {
  const DofMap& map = sys_.dofs();
  Eigen::MatrixXd E = Eigen::MatrixXd::Zero(map.size(), Eigen::Index(3 * nodes.size()));
  for (size_t j = 0; j < nodes.size(); ++j)
    for (int a = 0; a < 3; ++a) {
      const int n = nodes[j];
      const int dof = n >= 0 && n < sys_.num_nodes() ? map.reduced[size_t(3 * n + a)] : -1;
      if (dof < 0) fail("unit_responses: node ", n, " is fixed or in no tetrahedron");
      E(dof, Eigen::Index(3 * j + a)) = 1.0;
    }
  const Eigen::MatrixXd X = factor_.solve(E);
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(3 * Eigen::Index(sys_.num_nodes()), E.cols());
  for (Eigen::Index c = 0; c < E.cols(); ++c) out.col(c) = expand_vector(X.col(c), map, sys_.num_nodes());
  return out;
}

Eigen::MatrixX3d solve_whole_mesh(const mesh::TetMesh& m, const std::vector<Material>& tet_material,
                                  const std::vector<char>& node_fixed, const Eigen::MatrixX3d& forces) {
  return WholeMeshSolver(m, tet_material, node_fixed, "monolithic stiffness matrix").solve(forces);
}

Eigen::MatrixX3d solve_whole_mesh_cg(const mesh::TetMesh& m, const std::vector<Material>& tet_material,
                                     const std::vector<char>& node_fixed, const Eigen::MatrixX3d& forces,
                                     const solve::CgOptions& opt, int* iterations) {
  const WholeMesh sys(m, tet_material, node_fixed);
  solve::BlockJacobi pre(sys.K());
  pre.finalize();
  Eigen::VectorXd x = Eigen::VectorXd::Zero(sys.dofs().size());
  const solve::CgResult res = solve::pcg(solve::sparse_operator(sys.K()), pre.as_operator(), sys.load(forces), x, opt);
  if (iterations) *iterations = res.iterations;
  return sys.field(x);
}

}  // namespace softcut::fem
