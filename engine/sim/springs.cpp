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
    Eigen::Vector3d at_rest = Eigen::Vector3d::Zero();  // sum w X over all its nodes, current mesh, m
  };
  const mesh::TetMesh& mesh = current_mesh(m, s);
  std::vector<Point> points;
  std::vector<int> nodes;
  for (size_t t = 0; t < s.tools.size() && t < s.tool_specs.size(); ++t) {
    const tools::ToolSpec& spec = s.tool_specs[t];
    const tools::ToolState& ts = s.tools[t];
    if (!tools::is_implicit_spring(spec) || ts.grip.empty()) continue;
    for (size_t i = 0; i < ts.grip.size(); ++i) {
      const tools::SurfacePoint& g = ts.grip[i];
      Point p{spec.stiffness / double(ts.grip.size()), ts.tip + ts.offsets[i], {}};
      for (int j = 0; j < 3; ++j) {
        const int n = g.nodes[size_t(j)];
        p.at_rest += g.weights(j) * mesh.node(n);
        if (g.weights(j) != 0 && !is_fixed_node(m, s, n)) {
          p.free.push_back({n, g.weights(j)});
          nodes.push_back(n);
        }
      }
      if (!p.free.empty()) points.push_back(std::move(p));
    }
  }
  if (points.empty()) return 0;
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  auto slot = [&](int n) { return Eigen::Index(std::lower_bound(nodes.begin(), nodes.end(), n) - nodes.begin()); };
  const Eigen::Index ng = Eigen::Index(3 * nodes.size()), np = Eigen::Index(3 * points.size());

  SpringCache& c = s.springs;
  const long generation = m.solver->system_generation(s.solver_run);
  if (!c.enabled || c.nodes != nodes || c.generation != generation) {
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
  Eigen::MatrixXd W = Eigen::MatrixXd::Zero(np, ng);
  Eigen::VectorXd d(np), u0(ng);
  for (size_t j = 0; j < nodes.size(); ++j) u0.segment<3>(3 * Eigen::Index(j)) = s.displacement.row(nodes[j]).transpose();
  for (size_t p = 0; p < points.size(); ++p) {
    const Eigen::Index r = 3 * Eigen::Index(p);
    for (const auto& [n, w] : points[p].free) W.block<3, 3>(r, 3 * slot(n)).diagonal().array() += w;
    d.segment<3>(r) = points[p].target - points[p].at_rest;
  }
  d.noalias() -= W * u0;
  Eigen::MatrixXd A = W * c.compliance * W.transpose();
  for (size_t p = 0; p < points.size(); ++p) A.diagonal().segment<3>(3 * Eigen::Index(p)).array() += 1.0 / points[p].k;
  const Eigen::LLT<Eigen::MatrixXd> llt(A);
  if (llt.info() != Eigen::Success)
    fail("frame ", s.frame + 1, ": the implicit grasper springs give a singular system (grasped-point compliance not ",
         "positive definite); set implicit = false on the grasper");
  const Eigen::VectorXd f = llt.solve(d);
  const Eigen::VectorXd g = W.transpose() * f;  // (3m) N on the grasped nodes

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
    ts.forces.assign(ts.nodes.size(), Eigen::Vector3d::Zero());
    ts.total_force.setZero();
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
