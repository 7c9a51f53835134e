#pragma once
// Small scenarios shared by the sim tests.
#include <Eigen/Core>
#include <algorithm>
#include <filesystem>
#include <string>

#include "sim/scenario_spec.hpp"

namespace softcut::test {

// A 0.1 x 0.02 x 0.02 m bar (5 x 2 x 2 cells), fixed at x = 0, pulled down at
// x = 0.1 by a force growing linearly to `tip_force` N over 1 s, with a slab of
// operational tets in the middle; 10 Hz for `duration` s.
inline sim::ScenarioSpec cantilever_spec(const std::filesystem::path& out, double duration = 0.2,
                                         double tip_force = 0.01) {
  using V = Eigen::Vector3d;
  sim::ScenarioSpec s;
  s.name = "cantilever";
  s.mesh.generator = "box";
  s.mesh.options = {{"max.x", 0.1}, {"max.y", 0.02}, {"max.z", 0.02}, {"nx", 5}, {"ny", 2}, {"nz", 2}};
  sim::MaterialAssignment mat;
  mat.name = "tissue";
  mat.young = 5e3;
  mat.poisson = 0.45;
  s.materials.push_back(mat);
  s.operational.kind = sim::TetSelector::Kind::box;
  s.operational.min = V(0.04, -1, -1);
  s.operational.max = V(0.06, 1, 1);
  s.fixed = sim::NodeSelector::box(V(-1, -1, -1), V(0, 1, 1));
  sim::LoadSpec tip;
  tip.name = "tip";
  tip.nodes = sim::NodeSelector::box(V(0.1, -1, -1), V(0.1, 1, 1));
  tip.direction = V(0, 0, -1);
  tip.magnitude = tools::Ramp::linear_ramp(0.0, tip_force, 0.0, 1.0);
  s.loads.push_back(tip);
  s.timeline.duration = duration;
  s.timeline.fps = 10.0;
  s.outputs.dir = out;
  s.solver.cg_tolerance = 1e-12;
  return s;
}

// A spring-driven grasper named "jaw" of total `stiffness` (N/m) and jaw
// `radius` (m) on `path` (implicit, closing on first contact).
inline tools::ToolSpec spring_grasper(double stiffness, double radius, tools::Path path) {
  tools::ToolSpec g;
  g.name = "jaw";
  g.kind = tools::ToolSpec::Kind::grasper;
  g.drive = tools::ToolSpec::Drive::spring;
  g.stiffness = stiffness;
  g.radius = radius;
  g.path = std::move(path);
  return g;
}

// A box bar from the origin to `size` (m), 10 x 4 x 4 cells, of one material
// (`young` Pa, Poisson 0.4), operational between x = op_lo and op_hi across
// the whole section, fixed at x = 0 and, when `both_ends`, at x = size.x.
// The cutting tests add their loads, blades and timeline.
inline sim::ScenarioSpec held_bar_spec(const std::string& name, const Eigen::Vector3d& size, double young,
                                       double op_lo, double op_hi, bool both_ends) {
  using V = Eigen::Vector3d;
  sim::ScenarioSpec s;
  s.name = name;
  s.mesh.generator = "box";
  s.mesh.options = {{"max.x", size.x()}, {"max.y", size.y()}, {"max.z", size.z()}, {"nx", 10}, {"ny", 4}, {"nz", 4}};
  sim::MaterialAssignment mat;
  mat.name = "tissue";
  mat.young = young;
  mat.poisson = 0.4;
  s.materials.push_back(mat);
  s.operational.kind = sim::TetSelector::Kind::box;
  s.operational.min = V(op_lo, -1, -1);
  s.operational.max = V(op_hi, 1, 1);
  const auto left = sim::NodeSelector::box(V(-1, -1, -1), V(0, 1, 1));
  s.fixed = both_ends ? sim::NodeSelector::combine(sim::NodeSelector::Kind::union_of,
                                                   {left, sim::NodeSelector::box(V(size.x(), -1, -1), V(1, 1, 1))})
                      : left;
  return s;
}

// A load that moves the tissue while a blade passes: 4 mN along `direction`
// on `nodes`, oscillating by 2 mN at 3 Hz.
inline sim::LoadSpec wobble_load(const sim::NodeSelector& nodes, const Eigen::Vector3d& direction) {
  sim::LoadSpec wobble;
  wobble.name = "wobble";
  wobble.nodes = nodes;
  wobble.direction = direction;
  wobble.magnitude = tools::Ramp::sine_wave(0.004, 0.002, 3.0);
  return wobble;
}

// The cutting tests' scalpel: a 6 cm edge along `axis`, 1 mm contact radius,
// cutting from 1 Pa, pressing with 50 mN along `direction`; the caller sets
// its path.
inline tools::ToolSpec cutting_blade(const Eigen::Vector3d& axis, const Eigen::Vector3d& direction) {
  tools::ToolSpec blade;
  blade.name = "blade";
  blade.kind = tools::ToolSpec::Kind::scalpel;
  blade.blade_length = 0.06;
  blade.blade_axis = axis;
  blade.radius = 0.001;
  blade.cut_pressure = 1;
  blade.direction = direction;
  blade.force = tools::Ramp::constant_value(0.05);
  return blade;
}

// A scalpel with a 40 mm edge along y (wider than a 20 mm bar) that presses
// the top of the bar at x = 0.0512 with a force growing to 0.2 N over 0.2 s
// (1667 Pa over 40 mm x 3 mm), waits, and goes down through it by t = 1 s.
inline tools::ToolSpec through_cut_blade(double cut_pressure) {
  using V = Eigen::Vector3d;
  tools::ToolSpec blade;
  blade.name = "blade";
  blade.kind = tools::ToolSpec::Kind::scalpel;
  blade.blade_length = 0.04;
  blade.blade_axis = V(0, 1, 0);
  blade.radius = 0.0015;
  blade.cut_pressure = cut_pressure;
  blade.direction = V(0, 0, -1);
  blade.force = tools::Ramp::linear_ramp(0.0, 0.2, 0.0, 0.2);
  blade.path = tools::Path::polyline({0.0, 0.3, 1.0}, {V(0.0512, 0.01, 0.0205), V(0.0512, 0.01, 0.0205),
                                                        V(0.0512, 0.01, -0.004)});
  return blade;
}

// W (3p x 3m) of a grasper's grip: row block p holds point p's barycentric
// weights on the columns of its nodes' DOFs, the nodes ordered as ts.nodes.
inline Eigen::MatrixXd grip_weights(const tools::ToolState& ts) {
  Eigen::MatrixXd W = Eigen::MatrixXd::Zero(Eigen::Index(3 * ts.grip.size()), Eigen::Index(3 * ts.nodes.size()));
  for (size_t p = 0; p < ts.grip.size(); ++p)
    for (int j = 0; j < 3; ++j) {
      const auto at = std::find(ts.nodes.begin(), ts.nodes.end(), ts.grip[p].nodes[size_t(j)]) - ts.nodes.begin();
      W.block<3, 3>(Eigen::Index(3 * p), Eigen::Index(3 * at)).diagonal().array() += ts.grip[p].weights(j);
    }
  return W;
}

// The grip points' targets minus their positions for node displacements u
// (nnode x 3) on rest positions X: (3p) m.
inline Eigen::VectorXd grip_gaps(const tools::ToolState& ts, const Eigen::MatrixX3d& X, const Eigen::MatrixX3d& u) {
  Eigen::VectorXd d(Eigen::Index(3 * ts.grip.size()));
  const Eigen::MatrixX3d x = X + u;
  for (size_t p = 0; p < ts.grip.size(); ++p) d.segment<3>(Eigen::Index(3 * p)) = ts.tip + ts.offsets[p] - ts.grip[p].at(x);
  return d;
}

}  // namespace softcut::test
