#include "fem/grip_springs.hpp"

#include <algorithm>

#include "core/error.hpp"

namespace softcut::fem {

namespace {

Eigen::Vector3d point_displacement(const GripSprings::Point& p, const SpringMap& map, const Eigen::VectorXd& x) {
  Eigen::Vector3d u = Eigen::Vector3d::Zero();
  for (const auto& [n, w] : p.nodes) u += w * x.segment<3>(3 * Eigen::Index(map.unknown[size_t(n)]));
  return u;
}

}  // namespace

void check_springs(const GripSprings& s, const SpringMap& map, const char* what) {
  for (const auto& p : s.points)
    for (const auto& [n, w] : p.nodes)
      if (n < 0 || size_t(n) >= map.unknown.size() || map.unknown[size_t(n)] < 0)
        fail("a grasper holds node ", n, ", which ", what);
  if (!s.points.empty() && (!s.grasped || !s.response || !s.W || !s.A_llt))
    fail("grasper springs without their preconditioner data (internal error)");
}

double add_spring_forces(const GripSprings& s, const SpringMap& map, const Eigen::VectorXd& x, Eigen::VectorXd& r) {
  double energy = 0;
  for (const auto& p : s.points) {
    const Eigen::Vector3d f = p.k * (p.target - point_displacement(p, map, x));
    energy += 0.5 * f.squaredNorm() / p.k;
    for (const auto& [n, w] : p.nodes) r.segment<3>(3 * Eigen::Index(map.unknown[size_t(n)])) += w * f;
  }
  return energy;
}

void apply_spring_stiffness(const GripSprings& s, const SpringMap& map, const Eigen::VectorXd& v, Eigen::VectorXd& y) {
  for (const auto& p : s.points) {
    Eigen::Vector3d up = Eigen::Vector3d::Zero();
    for (const auto& [n, w] : p.nodes) up += w * v.segment<3>(3 * Eigen::Index(map.unknown[size_t(n)]));
    for (const auto& [n, w] : p.nodes) y.segment<3>(3 * Eigen::Index(map.unknown[size_t(n)])) += w * p.k * up;
  }
}

std::vector<Eigen::Vector3d> spring_point_forces(const GripSprings& s, const SpringMap& map, const Eigen::VectorXd& x) {
  std::vector<Eigen::Vector3d> f;
  for (const auto& p : s.points) f.push_back(p.k * (p.target - point_displacement(p, map, x)));
  return f;
}

void spring_correction(const GripSprings& s, const SpringMap& map, Eigen::VectorXd& z) {
  if (s.points.empty()) return;
  const std::vector<int>& g = *s.grasped;
  Eigen::VectorXd zg(3 * Eigen::Index(g.size()));
  for (size_t j = 0; j < g.size(); ++j) zg.segment<3>(3 * Eigen::Index(j)) = z.segment<3>(3 * Eigen::Index(map.unknown[size_t(g[j])]));
  const Eigen::VectorXd h = s.W->transpose() * s.A_llt->solve(*s.W * zg);  // (3m) N on the grasped nodes
  const Eigen::MatrixXd& R = *s.response;
  for (size_t n = 0; n < map.unknown.size(); ++n) {
    const int k = map.unknown[n];
    if (k >= 0) z.segment<3>(3 * Eigen::Index(k)).noalias() -= R.middleRows<3>(3 * Eigen::Index(n)) * h;
  }
}

}  // namespace softcut::fem
