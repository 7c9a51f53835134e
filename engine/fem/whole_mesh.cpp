#include "fem/whole_mesh.hpp"

#include "core/error.hpp"
#include "core/timer.hpp"
#include "fem/anchoring.hpp"

namespace softcut::fem {

namespace {

// (rows.size()) from a field (nnode x 3) or zero when the field is empty.
Eigen::VectorXd restrict_field(const Eigen::MatrixX3d& field, const DofMap& map, int nnode, const char* what) {
  if (field.size() == 0) return Eigen::VectorXd::Zero(map.size());
  if (field.rows() != nnode) fail("whole-mesh system: ", what, " have ", field.rows(), " rows for ", nnode, " nodes");
  return restrict_vector(flatten(field), map);
}

}  // namespace

WholeMesh::WholeMesh(const mesh::TetMesh& m, const std::vector<Material>& tet_material,
                     const std::vector<char>& node_fixed)
    : nnode_(m.num_nodes()), node_fixed_(node_fixed) {
  const Timer t;
  if (int(node_fixed.size()) != nnode_)
    fail("whole-mesh system: node_fixed has ", node_fixed.size(), " entries for ", nnode_, " nodes");
  const std::vector<char> used = mesh::referenced_nodes(m);
  std::vector<char> free(used.size()), fixed(used.size());
  for (size_t v = 0; v < used.size(); ++v) free[v] = used[v] && !node_fixed[v], fixed[v] = used[v] && node_fixed[v];
  map_ = make_dof_map(free);
  fixed_ = make_dof_map(fixed);
  const SparseMatrix K = assemble_stiffness(m, tet_material);
  K_ = restrict_matrix(K, map_);
  if (fixed_.size() > 0) K_fp_ = restrict_matrix(K, map_, fixed_), K_pp_ = restrict_matrix(K, fixed_);
  if (any_element_load(tet_material)) {
    const Eigen::VectorXd f0 = flatten(element_loads(m, tet_material));
    f0_ = restrict_vector(f0, map_);
    f0_p_ = restrict_vector(f0, fixed_);
  }
  assemble_ms_ = t.ms();
}

Eigen::VectorXd WholeMesh::load(const Eigen::MatrixX3d& forces, const Eigen::MatrixX3d& prescribed) const {
  if (forces.rows() != nnode_) fail("whole-mesh system: forces have ", forces.rows(), " rows for ", nnode_, " nodes");
  Eigen::VectorXd f = restrict_vector(flatten(forces), map_);
  if (f0_.size() > 0) f += f0_;
  if (prescribed.size() > 0 && fixed_.size() > 0) f -= K_fp_ * restrict_field(prescribed, fixed_, nnode_, "prescribed displacements");
  return f;
}

Eigen::MatrixX3d WholeMesh::field(const Eigen::VectorXd& x, const Eigen::MatrixX3d& prescribed) const {
  Eigen::MatrixX3d u = unflatten(expand_vector(x, map_, nnode_));
  if (prescribed.size() == 0) return u;
  if (prescribed.rows() != nnode_)
    fail("whole-mesh system: prescribed displacements have ", prescribed.rows(), " rows for ", nnode_, " nodes");
  for (int v = 0; v < nnode_; ++v)
    if (node_fixed_[size_t(v)]) u.row(v) = prescribed.row(v);
  return u;
}

Eigen::MatrixX3d WholeMesh::reactions(const Eigen::MatrixX3d& u, const Eigen::MatrixX3d& forces) const {
  if (u.rows() != nnode_) fail("whole-mesh system: a field of ", u.rows(), " rows for ", nnode_, " nodes");
  if (forces.rows() != nnode_) fail("whole-mesh system: forces have ", forces.rows(), " rows for ", nnode_, " nodes");
  if (fixed_.size() == 0) return Eigen::MatrixX3d::Zero(nnode_, 3);
  const Eigen::VectorXd uf = flatten(u);
  Eigen::VectorXd r = K_fp_.transpose() * restrict_vector(uf, map_) + K_pp_ * restrict_vector(uf, fixed_) -
                      restrict_vector(flatten(forces), fixed_);
  if (f0_p_.size() > 0) r -= f0_p_;
  return unflatten(expand_vector(r, fixed_, nnode_));
}

WholeMeshSolver::WholeMeshSolver(const mesh::TetMesh& m, const std::vector<Material>& tet_material,
                                 const std::vector<char>& node_fixed, const std::string& what, double max_bytes)
    : sys_(m, tet_material, node_fixed) {
  const Timer t;
  if (sys_.dofs().size() > 0) factor_.factor(sys_.K(), what, max_bytes);
  factor_ms_ = t.ms();
}

Eigen::MatrixX3d WholeMeshSolver::solve(const Eigen::MatrixX3d& forces, solve::SolveWorkspace& ws,
                                        const Eigen::MatrixX3d& prescribed, double* relative_residual) const {
  const Eigen::VectorXd f = sys_.load(forces, prescribed);
  const bool loaded = f.squaredNorm() > 0;
  Eigen::VectorXd x = Eigen::VectorXd::Zero(f.size());
  if (loaded) factor_.solve_into(f, x, ws);
  if (relative_residual) *relative_residual = loaded ? (f - sys_.K() * x).norm() / f.norm() : 0.0;
  return sys_.field(x, prescribed);
}

Eigen::MatrixXd WholeMeshSolver::unit_responses(const std::vector<int>& nodes, solve::SolveWorkspace& ws) const {
  const DofMap& map = sys_.dofs();
  Eigen::MatrixXd E = Eigen::MatrixXd::Zero(map.size(), Eigen::Index(3 * nodes.size()));
  for (size_t j = 0; j < nodes.size(); ++j)
    for (int a = 0; a < 3; ++a) {
      const int n = nodes[j];
      const int dof = n >= 0 && n < sys_.num_nodes() ? map.reduced[size_t(3 * n + a)] : -1;
      if (dof < 0) fail("unit_responses: node ", n, " is fixed or in no tetrahedron");
      E(dof, Eigen::Index(3 * j + a)) = 1.0;
    }
  const Eigen::MatrixXd X = factor_.solve(E, ws);
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(3 * Eigen::Index(sys_.num_nodes()), E.cols());
  for (Eigen::Index c = 0; c < E.cols(); ++c) out.col(c) = expand_vector(X.col(c), map, sys_.num_nodes());
  return out;
}

Eigen::MatrixX3d solve_whole_mesh(const mesh::TetMesh& m, const std::vector<Material>& tet_material,
                                  const std::vector<char>& node_fixed, const Eigen::MatrixX3d& forces) {
  solve::SolveWorkspace ws;
  return WholeMeshSolver(m, tet_material, node_fixed, "monolithic stiffness matrix").solve(forces, ws);
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

namespace {

constexpr const char* kWho = "static solve";

void require_finite_rows(const Eigen::MatrixX3d& a, const char* what, const std::vector<int>* ids) {
  for (Eigen::Index i = 0; i < a.rows(); ++i)
    if (!a.row(i).allFinite())
      fail(kWho, ": the ", what, " of node ", ids ? (*ids)[size_t(i)] : int(i), " is not finite (", a(i, 0), ", ",
           a(i, 1), ", ", a(i, 2), "); give finite values");
}

}  // namespace

StaticSolution solve_static(const mesh::TetMesh& m, const std::vector<Material>& tet_material,
                            const StaticProblem& p, const StaticOptions& opt) {
  const int nn = m.num_nodes();
  const Eigen::MatrixX3d f = p.forces.size() == 0 ? Eigen::MatrixX3d(Eigen::MatrixX3d::Zero(nn, 3)) : p.forces;
  if (f.rows() != nn) fail(kWho, ": forces have ", f.rows(), " rows, but the mesh has ", nn, " nodes");
  require_finite_rows(f, "force", nullptr);
  const size_t nfix = p.fixed_nodes.size();
  if (p.fixed_displacement.size() != 0 && size_t(p.fixed_displacement.rows()) != nfix)
    fail(kWho, ": ", p.fixed_displacement.rows(), " prescribed displacements for ", nfix,
         " fixed nodes; give one row per fixed node or none (zero)");
  if (p.fixed_displacement.size() != 0) require_finite_rows(p.fixed_displacement, "prescribed displacement", &p.fixed_nodes);

  Eigen::MatrixX3d prescribed = Eigen::MatrixX3d::Zero(nn, 3);
  std::vector<char> fixed(size_t(nn), 0);
  for (size_t k = 0; k < nfix; ++k) {
    const int id = p.fixed_nodes[k];
    if (id < 0 || id >= nn) fail(kWho, ": fixed node ", id, " is out of range 0..", nn - 1);
    if (fixed[size_t(id)]) fail(kWho, ": node ", id, " is listed twice among the fixed nodes; list it once");
    fixed[size_t(id)] = 1;
    if (p.fixed_displacement.size() != 0) prescribed.row(id) = p.fixed_displacement.row(Eigen::Index(k));
  }
  // Topology first: it validates the tet node ids and names a floating part
  // before any expensive work.
  const Parts parts = connected_parts(m);
  for (int i = 0; i < nn; ++i)
    if (parts.node_part[size_t(i)] < 0 && !f.row(i).isZero(0))
      fail(kWho, ": node ", i, " carries a force (", f(i, 0), ", ", f(i, 1), ", ", f(i, 2),
           ") N but belongs to no tetrahedron, so the load would be lost; move the load to a node of the body");
  check_anchored(m, {}, fixed, kWho);

  const WholeMesh sys(m, tet_material, fixed);
  const Eigen::VectorXd b = sys.load(f, prescribed);
  StaticSolution sol;
  sol.free_dofs = sys.dofs().size();
  Eigen::VectorXd x = Eigen::VectorXd::Zero(sol.free_dofs);
  if (sol.free_dofs > 0) {
    if (opt.backend == StaticBackend::cholmod) {
      solve::SolveWorkspace ws;
      solve::Cholesky(sys.K(), kWho).solve_into(b, x, ws);
    } else {
      solve::BlockJacobi pre(sys.K());
      pre.finalize();
      const solve::CgResult r = solve::pcg(solve::sparse_operator(sys.K()), pre.as_operator(), b, x, opt.cg);
      sol.cg_iterations = r.iterations;
      sol.cg_relative_residual = r.relative_residual;
      if (!r.converged)
        fail(kWho, ": conjugate gradient stopped after ", r.iterations, " iterations at relative residual ",
             r.relative_residual, " (tolerance ", opt.cg.tolerance,
             "); raise the iteration cap, loosen the tolerance or use the cholmod backend");
    }
  }
  if (!x.allFinite()) fail(kWho, ": the solution is not finite; the stiffness matrix is numerically singular");
  sol.displacement = sys.field(x, prescribed);
  sol.reaction = sys.reactions(sol.displacement, f);
  return sol;
}

}  // namespace softcut::fem
