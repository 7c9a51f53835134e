// The whole mesh's mixed model by Newton (fem/whole_mesh.hpp, solve_nonlinear).
#include <algorithm>

#include "core/error.hpp"
#include "fem/whole_mesh.hpp"

namespace softcut::fem {

std::vector<int> unknown_nodes(const WholeMesh& sys) {
  std::vector<int> unknown(size_t(sys.num_nodes()), -1);
  for (int n = 0; n < sys.num_nodes(); ++n) {
    const int dof = sys.dofs().reduced[size_t(3 * n)];
    if (dof >= 0) unknown[size_t(n)] = dof / 3;
  }
  return unknown;
}

solve::NewtonReport solve_nonlinear(const NonlinearSolve& s, const Eigen::MatrixX3d& forces,
                                    const Eigen::MatrixX3d& prescribed, Eigen::VectorXd& x, NonlinearWork& work,
                                    solve::SolveWorkspace& ws, const std::string& what) {
  const WholeMesh& sys = s.linear->system();
  const Eigen::Index n = sys.dofs().size();
  if (x.size() != n) x.setZero(n);
  if (n == 0) return {};
  const SpringMap map{unknown_nodes(sys)};
  const GripSprings none;
  const GripSprings& springs = s.springs ? *s.springs : none;
  check_springs(springs, map, "is fixed in the whole-mesh system");
  // b without the prescribed motion's load: the tets with a moving fixed
  // corner are in `set`, whose correction adds it (fem/nonlinear_tets.hpp).
  const Eigen::VectorXd b = sys.load(forces);
  double scale = 0;
  Eigen::VectorXd Kx(n);
  solve::NewtonProblem p;
  p.residual = [&](const Eigen::VectorXd& at, Eigen::VectorXd& r) {
    Eigen::VectorXd d = Eigen::VectorXd::Zero(n);
    const double correction = evaluate(*s.set, at, prescribed, d, work);
    Kx.noalias() = sys.K() * at;
    r = b - Kx - d;
    // The sizes of the terms r is the difference of: its rounding floor
    // (a rotated tet's linear force K_e u, in Kx, cancels in d).
    scale = b.norm() + Kx.norm() + d.norm() + 1e-6 * work.force_unit;
    const double spring_energy = add_spring_forces(springs, map, at, r);
    return 0.5 * at.dot(Kx) - b.dot(at) + correction + spring_energy;
  };
  p.project = [&] { project(*s.set, work); };
  p.tangent_difference = [&](const Eigen::VectorXd& v, Eigen::VectorXd& y) { apply_difference(*s.set, work, v, y); };
  p.precondition = [&](const Eigen::VectorXd& r, Eigen::VectorXd& z) {
    s.linear->factor().solve_into(r, z, ws);
    spring_correction(springs, map, z);
  };
  p.scale = [&](const Eigen::VectorXd&) { return scale; };
  const solve::NewtonReport rep = solve::newton(p, x, s.options, what, s.start);
  measure_deformation(*s.set, work);
  return rep;
}

}  // namespace softcut::fem
