#include "hybrid/nonlinear_solve.hpp"

#include <algorithm>

namespace softcut::hybrid {

bool needs_nonlinear_solve(const OperationalSystem& sys, const NonlinearFrame& frame) {
  return sys.nonlinear_law || (sys.nonlinear && frame.prescribed.size() > 0 && frame.prescribed.squaredNorm() > 0);
}

NonlinearReport solve_nonlinear(const OperationalSystem& sys, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                                OperationalSolver& solver, fem::NonlinearWork& work, const NonlinearFrame& frame,
                                const std::string& what, const Eigen::VectorXd* start, HelperThread* helper) {
  const Eigen::Index n = sys.size();
  if (x.size() != n) x.setZero(n);
  NonlinearReport rep;
  if (n == 0) return rep;
  const fem::NonlinearTets none_tets;
  const fem::NonlinearTets& set = sys.nonlinear ? *sys.nonlinear : none_tets;
  const fem::GripSprings none;
  const fem::GripSprings& springs = frame.springs ? *frame.springs : none;
  const fem::SpringMap map{sys.node_index};
  fem::check_springs(springs, map,
                     "is not an unknown of the operational system (a nonoperational or fixed node): with a nonlinear "
                     "model a grasper must hold operational nodes; enlarge s:operational{} to take in the grasp");
  double scale = 0;
  Eigen::VectorXd Ax(n), Ax_base(n);
  solve::NewtonProblem p;
  p.residual = [&](const Eigen::VectorXd& at, Eigen::VectorXd& r) {
    Eigen::VectorXd d = Eigen::VectorXd::Zero(n);
    const double correction = fem::evaluate(set, at, frame.prescribed, d, work, true, helper);
    sys.apply(at, Ax);
    r = b - Ax - d;
    // The sizes of the terms r is the difference of: its rounding floor
    // (a rotated tet's linear force K_e u, in Ax, cancels in d).
    scale = b.norm() + Ax.norm() + d.norm() + 1e-6 * work.force_unit;
    const double spring_energy = fem::add_spring_forces(springs, map, at, r);
    return 0.5 * at.dot(Ax) - b.dot(at) + correction + spring_energy;
  };
  p.project = [&] { fem::project(set, work); };
  p.tangent_difference = [&](const Eigen::VectorXd& v, Eigen::VectorXd& y) {
    fem::apply_difference(set, work, v, y, helper);
  };
  if (solver.keeps_factor()) {  // P^-1 exactly, the springs by Woodbury
    p.precondition = [&](const Eigen::VectorXd& r, Eigen::VectorXd& z) {
      solver.precondition(sys, r, z);
      fem::spring_correction(springs, map, z);
    };
  } else {  // block Jacobi (the CG backends): P p formed each PCG iteration
    p.precondition = [&](const Eigen::VectorXd& r, Eigen::VectorXd& z) { solver.precondition(sys, r, z); };
    p.apply_base = [&](const Eigen::VectorXd& v, Eigen::VectorXd& y) {
      sys.apply(v, Ax_base);
      y += Ax_base;
      fem::apply_spring_stiffness(springs, map, v, y);
    };
  }
  p.scale = [&](const Eigen::VectorXd&) { return scale; };
  solve::NewtonOptions options = frame.newton;
  // Block Jacobi needs more PCG iterations per step than the factor: up to
  // the system's size (where CG in exact arithmetic is done).
  if (!solver.keeps_factor()) options.max_cg_iterations = std::max(options.max_cg_iterations, int(n));
  rep.newton = solve::newton(p, x, options, what, start);
  fem::measure_deformation(set, work);
  rep.max_rotation = work.max_rotation;
  rep.max_strain = work.max_strain;
  rep.inverted = work.inverted;
  return rep;
}

}  // namespace softcut::hybrid
