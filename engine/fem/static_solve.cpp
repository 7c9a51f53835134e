#include "fem/static_solve.hpp"

#include <cmath>

#include "core/error.hpp"
#include "core/timer.hpp"
#include "fem/anchoring.hpp"
#include "fem/assembly.hpp"
#include "fem/dof_map.hpp"
#include "fem/element_stiffness.hpp"
#include "solve/cholesky.hpp"

namespace softcut::fem {

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

  StaticSolution sol;
  sol.displacement = Eigen::MatrixX3d::Zero(nn, 3);
  std::vector<char> fixed(size_t(nn), 0);
  for (size_t k = 0; k < nfix; ++k) {
    const int id = p.fixed_nodes[k];
    if (id < 0 || id >= nn) fail(kWho, ": fixed node ", id, " is out of range 0..", nn - 1);
    if (fixed[size_t(id)]) fail(kWho, ": node ", id, " is listed twice among the fixed nodes; list it once");
    fixed[size_t(id)] = 1;
    if (p.fixed_displacement.size() != 0) sol.displacement.row(id) = p.fixed_displacement.row(Eigen::Index(k));
  }

  // Topology first: it validates the tet node ids and names a floating part
  // before any expensive work.
  const Parts parts = connected_parts(m);
  std::vector<char> free_node(size_t(nn), 0), fixed_in(size_t(nn), 0);
  for (int i = 0; i < nn; ++i) {
    const bool used = parts.node_part[size_t(i)] >= 0;
    if (!used && !f.row(i).isZero(0))
      fail(kWho, ": node ", i, " carries a force (", f(i, 0), ", ", f(i, 1), ", ", f(i, 2),
           ") N but belongs to no tetrahedron, so the load would be lost; move the load to a node of the body");
    free_node[size_t(i)] = used && !fixed[size_t(i)];
    fixed_in[size_t(i)] = used && fixed[size_t(i)];
  }
  check_anchored(m, {}, fixed, kWho);

  Timer timer;
  const SparseMatrix K = assemble_stiffness(m, tet_material);
  const DofMap fm = make_dof_map(free_node), cm = make_dof_map(fixed_in);
  const SparseMatrix Kff = restrict_matrix(K, fm);
  const Eigen::VectorXd u_all = flatten(sol.displacement);
  // Loads: the given forces plus the initial strains' equivalent forces.
  const Eigen::VectorXd f_all =
      any_initial_strain(tet_material) ? Eigen::VectorXd(flatten(f + initial_strain_forces(m, tet_material)))
                                       : Eigen::VectorXd(flatten(f));
  const Eigen::VectorXd b = restrict_vector(f_all, fm) - restrict_matrix(K, fm, cm) * restrict_vector(u_all, cm);
  sol.assemble_seconds = timer.seconds();
  sol.free_dofs = fm.size();

  timer.reset();
  Eigen::VectorXd x = Eigen::VectorXd::Zero(fm.size());
  if (fm.size() > 0) {
    if (opt.backend == StaticBackend::cholmod) {
      x = solve::Cholesky(Kff, kWho).solve(b);
    } else {
      solve::BlockJacobi pre(Kff);
      pre.finalize();
      const solve::CgResult r = solve::pcg(solve::sparse_operator(Kff), pre.as_operator(), b, x, opt.cg);
      sol.cg_iterations = r.iterations;
      sol.cg_relative_residual = r.relative_residual;
      if (!r.converged)
        fail(kWho, ": conjugate gradient stopped after ", r.iterations, " iterations at relative residual ",
             r.relative_residual, " (tolerance ", opt.cg.tolerance,
             "); raise the iteration cap, loosen the tolerance or use the cholmod backend");
    }
  }
  sol.solve_seconds = timer.seconds();
  if (!x.allFinite()) fail(kWho, ": the solution is not finite; the stiffness matrix is numerically singular");

  Eigen::VectorXd u_full = u_all;
  for (int i = 0; i < fm.size(); ++i) u_full(fm.global[size_t(i)]) = x(i);
  sol.displacement = unflatten(u_full);
  const Eigen::VectorXd r = K * u_full - f_all;
  sol.reaction = Eigen::MatrixX3d::Zero(nn, 3);
  for (int i = 0; i < nn; ++i)
    if (fixed[size_t(i)]) sol.reaction.row(i) = r.segment<3>(3 * Eigen::Index(i)).transpose();
  return sol;
}

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
