#include "tools/springs.hpp"

#include <Eigen/Cholesky>
#include <algorithm>

#include "core/error.hpp"
#include "core/timer.hpp"
#include "fem/dof_map.hpp"

namespace softcut::tools {

int solve_implicit_springs(const SpringSystem& sys, const std::vector<ToolSpec>& specs, std::vector<ToolState>& states,
                           SpringCache& c, Eigen::MatrixX3d& displacement, Eigen::MatrixX3d& forces, int frame) {
  // Grip points of implicit springs: stiffness k_p, target T_p, and their
  // free nodes with weights (a fixed node's share goes into the support).
  struct Point {
    double k;
    Eigen::Vector3d target;
    std::vector<std::pair<int, double>> free;  // (node, weight)
    Eigen::Vector3d at_rest = Eigen::Vector3d::Zero();  // sum w (X + held displacement) over all its nodes, m
  };
  const mesh::TetMesh& mesh = *sys.mesh;
  std::vector<Point> points;
  std::vector<int> nodes;
  std::vector<double> key;  // the grips' nodes, weights and stiffnesses: A's factor is kept while they stay
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
    for (const SurfacePoint& g : ts.grip) shares += g.share;
    for (size_t i = 0; i < ts.grip.size(); ++i) {
      const SurfacePoint& g = ts.grip[i];
      Point p{spec.stiffness * g.share / shares, ts.tip + ts.offsets[i], {}};
      for (int j = 0; j < 3; ++j) {
        const int n = g.nodes[size_t(j)];
        p.at_rest += g.weights(j) * mesh.node(n);
        if (sys.held) p.at_rest += g.weights(j) * sys.held(n);
        if (g.weights(j) != 0 && !sys.fixed(n)) {
          p.free.push_back({n, g.weights(j)});
          nodes.push_back(n);
          key.insert(key.end(), {double(n), g.weights(j)});
        }
      }
      key.push_back(p.k);
      if (!p.free.empty()) points.push_back(std::move(p));
    }
  }
  if (points.empty()) return 0;
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  auto slot = [&](int n) { return Eigen::Index(std::lower_bound(nodes.begin(), nodes.end(), n) - nodes.begin()); };
  const Eigen::Index ng = Eigen::Index(3 * nodes.size()), np = Eigen::Index(3 * points.size());
  // 3 solves per node once per grasp and dense (3m)^2 and (3p)^2 blocks:
  // bounded before anything is computed.
  if (nodes.size() > kMaxGraspedNodes || points.size() > 2 * kMaxGraspedNodes)
    fail("frame ", frame, ": the implicit graspers hold ", nodes.size(), " nodes (", points.size(),
         " grip points), more than the ", kMaxGraspedNodes, " their exact solve allows; use a smaller jaw radius, ",
         "or the force drive");

  const long generation = sys.generation;
  const bool rebuild = !c.enabled || c.nodes != nodes || c.generation != generation;
  if (rebuild) {
    Timer t;
    sys.unit_responses(nodes, c.response);
    c.compliance.resize(ng, ng);
    for (size_t j = 0; j < nodes.size(); ++j)
      c.compliance.middleRows(Eigen::Index(3 * j), 3) = c.response.middleRows(3 * Eigen::Index(nodes[j]), 3);
    // Symmetric in exact arithmetic (Maxwell-Betti); remove the solver's
    // round-off so the Cholesky factor sees an exactly symmetric matrix.
    c.compliance = 0.5 * (c.compliance + c.compliance.transpose()).eval();
    c.nodes = nodes;
    c.generation = generation;
    c.builds++;
    c.build_ms += t.ms();
  }

  // W (3P x 3m): point p's displacement is W u_g. With C_gg the nodes'
  // compliance, the points' is W C Wt:
  //   (diag(1/k) + W C Wt) f = T - X_p - W u0_g,   node forces g = Wt f.
  // W and the factor of A depend on the grips and C only: kept while both stay.
  if (rebuild || !c.enabled || c.grip_key != key) {
    c.W.setZero(np, ng);
    for (size_t p = 0; p < points.size(); ++p)
      for (const auto& [n, w] : points[p].free) c.W.block<3, 3>(3 * Eigen::Index(p), 3 * slot(n)).diagonal().array() += w;
    Eigen::MatrixXd A = c.W * c.compliance * c.W.transpose();
    for (size_t p = 0; p < points.size(); ++p) A.diagonal().segment<3>(3 * Eigen::Index(p)).array() += 1.0 / points[p].k;
    c.A_llt.compute(A);
    c.grip_key = key;
    if (c.A_llt.info() != Eigen::Success) {
      c.grip_key.clear();
      fail("frame ", frame, ": the implicit grasper springs give a singular system (grasped-point compliance ",
           "not positive definite); lower the grasper's stiffness or use the force drive");
    }
  }
  Eigen::VectorXd d(np), u0(ng);
  for (size_t j = 0; j < nodes.size(); ++j) u0.segment<3>(3 * Eigen::Index(j)) = displacement.row(nodes[j]).transpose();
  for (size_t p = 0; p < points.size(); ++p) d.segment<3>(3 * Eigen::Index(p)) = points[p].target - points[p].at_rest;
  d.noalias() -= c.W * u0;
  const Eigen::VectorXd f = c.A_llt.solve(d);
  const Eigen::VectorXd g = c.W.transpose() * f;  // (3m) N on the grasped nodes

  Eigen::VectorXd u = fem::flatten(displacement);
  u.noalias() += c.response * g;
  displacement = fem::unflatten(u);

  // Each tool's forces on the final positions, point by point onto its nodes
  // (fixed nodes' shares go into the support, not into s.forces).
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
  return int(nodes.size());
}

}  // namespace softcut::tools
