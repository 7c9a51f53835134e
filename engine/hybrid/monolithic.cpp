#include "hybrid/monolithic.hpp"

#include "core/error.hpp"
#include "fem/assembly.hpp"
#include "fem/dof_map.hpp"
#include "solve/cholesky.hpp"

namespace softcut::hybrid {

namespace {

struct Reduced {
  fem::DofMap map;
  fem::SparseMatrix K;
  Eigen::VectorXd f;
};

Reduced reduce(const mesh::TetMesh& m, const std::vector<fem::Material>& mat, const std::vector<char>& node_fixed,
               const Eigen::MatrixX3d& forces) {
  if (int(node_fixed.size()) != m.num_nodes() || forces.rows() != m.num_nodes())
    fail("monolithic solve: node_fixed and forces need one row per node (", m.num_nodes(), ")");
  const std::vector<char> used = mesh::referenced_nodes(m);
  std::vector<char> free(used.size());
  for (size_t v = 0; v < used.size(); ++v) free[v] = used[v] && !node_fixed[v];
  Reduced r;
  r.map = fem::make_dof_map(free);
  r.K = fem::restrict_matrix(fem::assemble_stiffness(m, mat), r.map);
  // The initial strains' forces join the given ones (K u = f + f0).
  r.f = fem::restrict_vector(fem::flatten(fem::any_initial_strain(mat) ? Eigen::MatrixX3d(forces + fem::initial_strain_forces(m, mat))
                                                                          : forces),
                             r.map);
  return r;
}

}  // namespace

Eigen::MatrixX3d solve_monolithic(const mesh::TetMesh& m, const std::vector<fem::Material>& mat,
                                  const std::vector<char>& node_fixed, const Eigen::MatrixX3d& forces) {
  const Reduced r = reduce(m, mat, node_fixed, forces);
  if (r.map.size() == 0) return Eigen::MatrixX3d::Zero(m.num_nodes(), 3);
  const solve::Cholesky llt(r.K, "monolithic stiffness matrix");
  return fem::unflatten(fem::expand_vector(llt.solve(r.f), r.map, m.num_nodes()));
}

Eigen::MatrixX3d solve_monolithic_cg(const mesh::TetMesh& m, const std::vector<fem::Material>& mat,
                                     const std::vector<char>& node_fixed, const Eigen::MatrixX3d& forces,
                                     const solve::CgOptions& opt, int* iterations) {
  const Reduced r = reduce(m, mat, node_fixed, forces);
  solve::BlockJacobi pre(r.K);
  pre.finalize();
  Eigen::VectorXd x = Eigen::VectorXd::Zero(r.map.size());
  const solve::CgResult res = solve::pcg(solve::sparse_operator(r.K), pre.as_operator(), r.f, x, opt);
  if (iterations) *iterations = res.iterations;
  return fem::unflatten(fem::expand_vector(x, r.map, m.num_nodes()));
}

}  // namespace softcut::hybrid
