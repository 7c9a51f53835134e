#include "sim/springs.hpp"

#include <Eigen/Cholesky>
#include <algorithm>

#include "core/timer.hpp"
#include "fem/dof_map.hpp"

namespace softcut::sim {

int solve_implicit_springs(const Model& m, State& s) {
  // Grasped nodes of implicit springs: stiffness K_n and K_n T_n per node.
  std::vector<std::pair<int, std::pair<double, Eigen::Vector3d>>> terms;  // node, (kn, kn * target)
  for (size_t t = 0; t < s.tools.size() && t < s.tool_specs.size(); ++t) {
    const tools::ToolSpec& spec = s.tool_specs[t];
    const tools::ToolState& ts = s.tools[t];
    if (!tools::is_implicit_spring(spec) || ts.nodes.empty()) continue;
    const double kn = spec.stiffness / double(ts.nodes.size());
    for (size_t i = 0; i < ts.nodes.size(); ++i)
      if (!is_fixed_node(m, s, ts.nodes[i]))
        terms.push_back({ts.nodes[i], {kn, kn * (ts.tip + ts.offsets[i])}});
  }
  if (terms.empty()) return 0;
  std::sort(terms.begin(), terms.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<int> nodes;
  std::vector<double> K;            // (m) N/m
  std::vector<Eigen::Vector3d> KT;  // (m) N
  for (const auto& [n, kt] : terms) {
    if (nodes.empty() || nodes.back() != n) {
      nodes.push_back(n);
      K.push_back(0.0);
      KT.push_back(Eigen::Vector3d::Zero());
    }
    K.back() += kt.first;
    KT.back() += kt.second;
  }
  const Eigen::Index ng = Eigen::Index(3 * nodes.size());

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

  // (diag(1/K) + C) f = T - X_g - u0_g
  Eigen::MatrixXd A = c.compliance;
  Eigen::VectorXd d(ng);
  for (size_t j = 0; j < nodes.size(); ++j) {
    const Eigen::Index r = Eigen::Index(3 * j);
    A.diagonal().segment<3>(r).array() += 1.0 / K[j];
    d.segment<3>(r) = KT[j] / K[j] - current_mesh(m, s).node(nodes[j]) - s.displacement.row(nodes[j]).transpose();
  }
  const Eigen::LLT<Eigen::MatrixXd> llt(A);
  if (llt.info() != Eigen::Success)
    fail("frame ", s.frame + 1, ": the implicit grasper springs give a singular system (grasped-node compliance not ",
         "positive definite); set implicit = false on the grasper");
  const Eigen::VectorXd f = llt.solve(d);

  Eigen::VectorXd u = fem::flatten(s.displacement);
  u.noalias() += c.response * f;
  s.displacement = fem::unflatten(u);

  // Each tool's share on the final positions (they sum to f per node).
  for (size_t t = 0; t < s.tools.size() && t < s.tool_specs.size(); ++t) {
    const tools::ToolSpec& spec = s.tool_specs[t];
    tools::ToolState& ts = s.tools[t];
    if (!tools::is_implicit_spring(spec) || ts.nodes.empty()) continue;
    const double kn = spec.stiffness / double(ts.nodes.size());
    ts.forces.assign(ts.nodes.size(), Eigen::Vector3d::Zero());
    ts.total_force.setZero();
    for (size_t i = 0; i < ts.nodes.size(); ++i) {
      const int n = ts.nodes[i];
      if (is_fixed_node(m, s, n)) continue;
      const Eigen::Vector3d x = current_mesh(m, s).node(n) + s.displacement.row(n).transpose();
      ts.forces[i] = kn * (ts.tip + ts.offsets[i] - x);
      ts.total_force += ts.forces[i];
      s.forces.row(n) += ts.forces[i].transpose();
    }
  }
  return int(nodes.size());
}

}  // namespace softcut::sim
