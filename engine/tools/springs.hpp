#pragma once
// Implicit tool springs: a grasper spring solved exactly within the frame.
//
// The model is linear, so with the grasped DOFs g (3 per free node of the
// grip points' triangles) the displacement is u = u0 + R h, where u0 is the
// response to every other load of the frame, h (3m) the spring forces on
// those nodes and R (3 nnode x 3m) the unit-load responses
// (the solver's unit-load responses); C = R_g (3m x 3m) is their compliance block. A
// grip point p (tools::SurfacePoint) sits at X_p + W_p u_g (barycentric
// weights W) and its spring pulls it with f_p = k_p (T_p - X_p - W_p u_g),
// stiffness k_p (the tool's stiffness over its points), target T_p (tip +
// grasp offset); the nodes take h = W^T f. So
//     (diag(1/k) + W C W^T) f = T - X - W u0_g,
// a small SPD system, exact for any stiffness; as k grows f tends to the
// force that puts the points on their targets. R is cached in a
// SpringCache (per run) while the grasped node set and the solver's system
// (cutting changes it) stay the same: a grasper keeps its grip, so R costs
// 3m extra solves once per grasp and a 3 nnode x 3m product per frame.
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <functional>
#include <vector>

#include "fem/grip_springs.hpp"
#include "mesh/tet_mesh.hpp"
#include "tools/tool.hpp"

namespace softcut::tools {

// The grasped nodes' compliance, kept while the grasped node set and the
// solver's system stay the same (per run: sim::State::springs).
struct SpringCache {
  std::vector<int> nodes;     // (m) grasped node ids the data belongs to, sorted
  long generation = -1;       // SpringSystem::generation it was built for
  Eigen::MatrixXd response;   // (3 nnode x 3m) m/N, displacement field of 1 N on each grasped DOF
  Eigen::MatrixXd compliance; // (3m x 3m) m/N, C_gg: the grasped rows of `response`
  Eigen::MatrixXd W;          // (3p x 3m) the grip points' weights
  Eigen::LLT<Eigen::MatrixXd> A_llt;  // of diag(1/k) + W C W^T
  std::vector<double> grip_key;       // the grips (nodes, weights, stiffnesses) W and A_llt belong to
  bool enabled = true;        // false: rebuild every frame (for measuring the cache)
  int builds = 0;             // times `response` was computed
  double build_ms = 0;        // total time spent computing it
};

// What the springs need of the frame's elastic system (sim/step gives it).
struct SpringSystem {
  const mesh::TetMesh* mesh = nullptr;                 // the current (cut) mesh: rest positions, m
  std::function<bool(int node)> fixed;                 // a fixed node takes no force (its share: the support)
  std::function<Eigen::Vector3d(int node)> held;       // displacement a node of a piece cut free keeps, m (else 0)
  long generation = 0;                                 // changes whenever the system does (cutting)
  // (3 nnode x 3 nodes.size()) m/N: displacement field of 1 N on each DOF of `nodes`.
  std::function<void(const std::vector<int>& nodes, Eigen::MatrixXd& response)> unit_responses;
};

// After `displacement` (nnode x 3, m) holds u0 (the solve without implicit
// springs): solves the implicit springs of the engaged graspers (`specs` and
// their `states`, index by index), adds R f to `displacement`, sets their
// ToolState forces (on the final positions) and adds them to `forces`
// (nnode x 3, N). Fixed nodes take no force. Returns the number of grasped
// nodes solved for (0: nothing to do). `frame` (0-based, of the frame being
// solved) is for messages.
int solve_implicit_springs(const SpringSystem& sys, const std::vector<ToolSpec>& specs, std::vector<ToolState>& states,
                           SpringCache& cache, Eigen::MatrixX3d& displacement, Eigen::MatrixX3d& forces, int frame);

// A nonlinear model's implicit graspers (Solver::nonlinear()): their grip
// points as springs for the solve to take inside its Newton iteration
// (fem/grip_springs.hpp), with the preconditioner's data from `cache`
// (built as for the linear solve: the unit responses of the linear system,
// once per grasp). `out` points into `cache`. Returns the number of grasped
// nodes (0: nothing to do, `out` empty).
int grip_springs(const SpringSystem& sys, const std::vector<ToolSpec>& specs, std::vector<ToolState>& states,
                 SpringCache& cache, fem::GripSprings& out, int frame);
// After a solve with the graspers inside it: each implicit grasper's forces
// on the final positions, into its ToolState and added to `forces`
// (nnode x 3, N; fixed nodes take none).
void grasper_forces(const SpringSystem& sys, const std::vector<ToolSpec>& specs, std::vector<ToolState>& states,
                    const Eigen::MatrixX3d& displacement, Eigen::MatrixX3d& forces);

// The most nodes the implicit graspers may hold together (grip points: twice
// that): each costs 3 solves per grasp and the dense blocks grow with the
// square; past it a clear error asks for a smaller jaw or the force drive.
constexpr size_t kMaxGraspedNodes = 400;

}  // namespace softcut::tools
