#include "tools/springs.hpp"

#include <Eigen/Cholesky>
#include <algorithm>

#include "core/error.hpp"
#include "core/timer.hpp"
#include "fem/dof_map.hpp"
#include "fem/grip_springs.hpp"

namespace softcut::tools {

namespace {

// Grip points of implicit springs: stiffness k_p, target T_p, and their
// free nodes with weights (a fixed node's share goes into the support).
struct Point {
  double k;
  Eigen::Vector3d target;
  std::vector<std::pair<int, double>> free;  // (node, weight)
  Eigen::Vector3d at_rest = Eigen::Vector3d::Zero();  // sum w (X + held displacement) over all its nodes, m
};

struct Grip {
  std::vector<Point> points;
  std::vector<int> nodes;   // the free grasped nodes, sorted
  std::vector<double> key;  // the grips' nodes, weights and stiffnesses: A's factor is kept while they stay
};

// The engaged implicit graspers' grip points; resets their ToolState forces
// (set on the final positions by grasper_forces).
Grip collect(const SpringSystem& sys, const std::vector<ToolSpec>& specs, std::vector<ToolState>& states, int frame) {
  const mesh::TetMesh& mesh = *sys.mesh;
  Grip g;
  for (size_t t = 0; t < states.size() && t < specs.size(); ++t) {
    const ToolSpec& spec = specs[t];
    ToolState& ts = states[t];
    if (!is_implicit_spring(spec)) continue;
    // Set below on the final positions; zero when nothing of it is free
    // (update_tool's explicit estimate is never applied).
    ts.forces.assign(ts.nodes.size(), Eigen::Vector3d::Zero());
    ts.total_force.setZero();
    if (ts.grip.empty()) continue;
    double shares = 0;
    for (const SurfacePoint& sp : ts.grip) shares += sp.share;
    for (size_t i = 0; i < ts.grip.size(); ++i) {
      const SurfacePoint& sp = ts.grip[i];
      Point p{spec.stiffness * sp.share / shares, ts.tip + ts.offsets[i], {}};
      for (int j = 0; j < 3; ++j) {
        const int n = sp.nodes[size_t(j)];
        p.at_rest += sp.weights(j) * mesh.node(n);
        if (sys.held) p.at_rest += sp.weights(j) * sys.held(n);
        if (sp.weights(j) != 0 && !sys.fixed(n)) {
          p.free.push_back({n, sp.weights(j)});
          g.nodes.push_back(n);
          g.key.insert(g.key.end(), {double(n), sp.weights(j)});
        }
      }
      g.key.push_back(p.k);
      if (!p.free.empty()) g.points.push_back(std::move(p));
    }
  }
  std::sort(g.nodes.begin(), g.nodes.end());
  g.nodes.erase(std::unique(g.nodes.begin(), g.nodes.end()), g.nodes.end());
  // 3 solves per node once per grasp and dense (3m)^2 and (3p)^2 blocks:
  // bounded before anything is computed.
  if (g.nodes.size() > kMaxGraspedNodes || g.points.size() > 2 * kMaxGraspedNodes)
    fail("frame ", frame, ": the implicit graspers hold ", g.nodes.size(), " nodes (", g.points.size(),
         " grip points), more than the ", kMaxGraspedNodes, " their exact solve allows; use a smaller jaw radius, ",
         "or the force drive");
  return g;
}

// The cache's compliance, W and factor of A for this grip (rebuilt when the
// grasped nodes, the system or the grips change).
void prepare(const SpringSystem& sys, const Grip& g, SpringCache& c, int frame) {
  const Eigen::Index ng = Eigen::Index(3 * g.nodes.size()), np = Eigen::Index(3 * g.points.size());
  auto slot = [&](int n) { return Eigen::Index(std::lower_bound(g.nodes.begin(), g.nodes.end(), n) - g.nodes.begin()); };
  const bool rebuild = !c.enabled || c.nodes != g.nodes || c.generation != sys.generation;
  if (rebuild) {
    Timer t;
    sys.unit_responses(g.nodes, c.response);
    c.compliance.resize(ng, ng);
    for (size_t j = 0; j < g.nodes.size(); ++j)
      c.compliance.middleRows(Eigen::Index(3 * j), 3) = c.response.middleRows(3 * Eigen::Index(g.nodes[j]), 3);
    // Symmetric in exact arithmetic (Maxwell-Betti); remove the solver's
    // round-off so the Cholesky factor sees an exactly symmetric matrix.
    c.compliance = 0.5 * (c.compliance + c.compliance.transpose()).eval();
    c.nodes = g.nodes;
    c.generation = sys.generation;
    c.builds++;
    c.build_ms += t.ms();
  }
  // W (3P x 3m): point p's displacement is W u_g. With C_gg the nodes'
  // compliance, the points' is W C Wt:
  //   (diag(1/k) + W C Wt) f = T - X_p - W u0_g,   node forces g = Wt f.
  // W and the factor of A depend on the grips and C only: kept while both stay.
  if (rebuild || !c.enabled || c.grip_key != g.key) {
    c.W.setZero(np, ng);
    for (size_t p = 0; p < g.points.size(); ++p)
      for (const auto& [n, w] : g.points[p].free) c.W.block<3, 3>(3 * Eigen::Index(p), 3 * slot(n)).diagonal().array() += w;
    Eigen::MatrixXd A = c.W * c.compliance * c.W.transpose();
    for (size_t p = 0; p < g.points.size(); ++p) A.diagonal().segment<3>(3 * Eigen::Index(p)).array() += 1.0 / g.points[p].k;
    c.A_llt.compute(A);
    c.grip_key = g.key;
    if (c.A_llt.info() != Eigen::Success) {
      c.grip_key.clear();
      fail("frame ", frame, ": the implicit grasper springs give a singular system (grasped-point compliance ",
           "not positive definite); lower the grasper's stiffness or use the force drive");
    }
  }
}

}  // namespace

void grasper_forces(const SpringSystem& sys, const std::vector<ToolSpec>& specs, std::vector<ToolState>& states,
                    const Eigen::MatrixX3d& displacement, Eigen::MatrixX3d& forces) {
  // Each tool's forces on the final positions, point by point onto its nodes
  // (fixed nodes' shares go into the support, not into s.forces).
  const mesh::TetMesh& mesh = *sys.mesh;
  for (size_t t = 0; t < states.size() && t < specs.size(); ++t) {
    const ToolSpec& spec = specs[t];
    ToolState& ts = states[t];
    if (!is_implicit_spring(spec) || ts.grip.empty()) continue;
    const double kp = spec.stiffness / double(ts.grip.size());
    const Eigen::MatrixX3d x = mesh.nodes + displacement;
    for (size_t i = 0; i < ts.grip.size(); ++i) {
      const SurfacePoint& gp = ts.grip[i];
      const Eigen::Vector3d fp = kp * (ts.tip + ts.offsets[i] - gp.at(x));
      for (int j = 0; j < 3; ++j) {
        const int n = gp.nodes[size_t(j)];
        if (gp.weights(j) == 0 || sys.fixed(n)) continue;
        const size_t at = size_t(std::lower_bound(ts.nodes.begin(), ts.nodes.end(), n) - ts.nodes.begin());
        ts.forces[at] += gp.weights(j) * fp;
        ts.total_force += gp.weights(j) * fp;
        forces.row(n) += gp.weights(j) * fp.transpose();
      }
    }
  }
}

int solve_implicit_springs(const SpringSystem& sys, const std::vector<ToolSpec>& specs, std::vector<ToolState>& states,
                           SpringCache& c, Eigen::MatrixX3d& displacement, Eigen::MatrixX3d& forces, int frame) {
  const Grip g = collect(sys, specs, states, frame);
  if (g.points.empty()) return 0;
  prepare(sys, g, c, frame);
  const Eigen::Index ng = Eigen::Index(3 * g.nodes.size()), np = Eigen::Index(3 * g.points.size());
  Eigen::VectorXd d(np), u0(ng);
  for (size_t j = 0; j < g.nodes.size(); ++j) u0.segment<3>(3 * Eigen::Index(j)) = displacement.row(g.nodes[j]).transpose();
  for (size_t p = 0; p < g.points.size(); ++p) d.segment<3>(3 * Eigen::Index(p)) = g.points[p].target - g.points[p].at_rest;
  d.noalias() -= c.W * u0;
  const Eigen::VectorXd f = c.A_llt.solve(d);
  const Eigen::VectorXd h = c.W.transpose() * f;  // (3m) N on the grasped nodes

  Eigen::VectorXd u = fem::flatten(displacement);
  u.noalias() += c.response * h;
  displacement = fem::unflatten(u);
  grasper_forces(sys, specs, states, displacement, forces);
  return int(g.nodes.size());
}

int grip_springs(const SpringSystem& sys, const std::vector<ToolSpec>& specs, std::vector<ToolState>& states,
                 SpringCache& c, fem::GripSprings& out, int frame) {
  out = fem::GripSprings{};
  const Grip g = collect(sys, specs, states, frame);
  if (g.points.empty()) return 0;
  prepare(sys, g, c, frame);
  for (const Point& p : g.points) out.points.push_back({p.k, p.target - p.at_rest, p.free});
  out.grasped = &c.nodes;
  out.response = &c.response;
  out.W = &c.W;
  out.A_llt = &c.A_llt;
  return int(g.nodes.size());
}

}  // namespace softcut::tools
