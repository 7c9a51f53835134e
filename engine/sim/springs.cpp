#include "sim/springs.hpp"

#include <Eigen/Cholesky>
#include <algorithm>

#include "core/timer.hpp"
#include "fem/dof_map.hpp"

namespace softcut::sim {

int solve_implicit_springs(const Model& m, State& s) {
  // Grip points of implicit springs: stiffness k_p, target T_p, and their
  // free nodes with weights (a fixed node's share goes into the support).
  struct Point {
    double k;
    Eigen::Vector3d target;
    std::vector<std::pair<int, double>> free;  // (node, weight)
    Eigen::Vector3d at_rest = Eigen::Vector3d::Zero();  // sum w (X + held displacement) over all its nodes, m
  };
  const mesh::TetMesh& mesh = current_mesh(m, s);
  std::vector<Point> points;
  std::vector<int> nodes;
  std::vector<double> key;  // the grips' nodes, weights and stiffnesses: A's factor is kept while they stay
  for (size_t t = 0; t < s.tools.size() && t < s.tool_specs.size(); ++t) {
    const tools::ToolSpec& spec = s.tool_specs[t];
    tools::ToolState& ts = s.tools[t];
    if (!tools::is_implicit_spring(spec)) continue;
    // Set below on the final positions; zero when nothing of it is free
    // (update_tool's explicit estimate is never applied).
    ts.forces.assign(ts.nodes.size(), Eigen::Vector3d::Zero());
    ts.total_force.setZero();
    if (ts.grip.empty()) continue;
    for (size_t i = 0; i < ts.grip.size(); ++i) {
      const tools::SurfacePoint& g = ts.grip[i];
      Point p{spec.stiffness / double(ts.grip.size()), ts.tip + ts.offsets[i], {}};
      for (int j = 0; j < 3; ++j) {
        const int n = g.nodes[size_t(j)];
        p.at_rest += g.weights(j) * mesh.node(n);
        if (is_held_node(s, n)) p.at_rest += g.weights(j) * s.cut->held_displacement.row(n).transpose();
        if (g.weights(j) != 0 && !is_fixed_node(m, s, n)) {
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
    fail("frame ", s.frame + 1, ": the implicit graspers hold ", nodes.size(), " nodes (", points.size(),
         " grip points), more than the ", kMaxGraspedNodes, " their exact solve allows; use a smaller jaw radius, ",
         "or the force drive");

  SpringCache& c = s.springs;
  const long generation = m.solver->system_generation(s.solver_run);
  const bool rebuild = !c.enabled || c.nodes != nodes || c.generation != generation;
  if (rebuild) {
    Timer t;
    m.solver->unit_responses(nodes, s.solver_run, c.response);
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
      fail("frame ", s.frame + 1, ": the implicit grasper springs give a singular system (grasped-point compliance ",
           "not positive definite); lower the grasper's stiffness or use the force drive");
    }
  }
  Eigen::VectorXd d(np), u0(ng);
  for (size_t j = 0; j < nodes.size(); ++j) u0.segment<3>(3 * Eigen::Index(j)) = s.displacement.row(nodes[j]).transpose();
  for (size_t p = 0; p < points.size(); ++p) d.segment<3>(3 * Eigen::Index(p)) = points[p].target - points[p].at_rest;
  d.noalias() -= c.W * u0;
  const Eigen::VectorXd f = c.A_llt.solve(d);
  const Eigen::VectorXd g = c.W.transpose() * f;  // (3m) N on the grasped nodes

  Eigen::VectorXd u = fem::flatten(s.displacement);
  u.noalias() += c.response * g;
  s.displacement = fem::unflatten(u);

  // Each tool's forces on the final positions, point by point onto its nodes
  // (fixed nodes' shares go into the support, not into s.forces).
  for (size_t t = 0; t < s.tools.size() && t < s.tool_specs.size(); ++t) {
    const tools::ToolSpec& spec = s.tool_specs[t];
    tools::ToolState& ts = s.tools[t];
    if (!tools::is_implicit_spring(spec) || ts.grip.empty()) continue;
    const double kp = spec.stiffness / double(ts.grip.size());
    const Eigen::MatrixX3d x = mesh.nodes + s.displacement;
    for (size_t i = 0; i < ts.grip.size(); ++i) {
      const tools::SurfacePoint& gp = ts.grip[i];
      const Eigen::Vector3d fp = kp * (ts.tip + ts.offsets[i] - gp.at(x));
      for (int j = 0; j < 3; ++j) {
        const int n = gp.nodes[size_t(j)];
        if (gp.weights(j) == 0 || is_fixed_node(m, s, n)) continue;
        const size_t at = size_t(std::lower_bound(ts.nodes.begin(), ts.nodes.end(), n) - ts.nodes.begin());
        ts.forces[at] += gp.weights(j) * fp;
        ts.total_force += gp.weights(j) * fp;
        s.forces.row(n) += gp.weights(j) * fp.transpose();
      }
    }
  }
  return int(nodes.size());
}

}  // namespace softcut::sim
