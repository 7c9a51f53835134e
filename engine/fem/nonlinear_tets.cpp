#include "fem/nonlinear_tets.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "fem/assembly.hpp"

namespace softcut::fem {

NonlinearTets::NonlinearTets(const mesh::TetMesh& m, const std::vector<Material>& tet_material, std::vector<int> tets,
                             const std::vector<int>& node_unknown)
    : tets_(std::move(tets)) {
  if (int(node_unknown.size()) != m.num_nodes())
    fail("nonlinear tets: node_unknown has ", node_unknown.size(), " entries for ", m.num_nodes(), " nodes");
  check_tets(m, tet_material, tets_, "nonlinear tets");
  const size_t n = tets_.size();
  rest_.resize(n), K0_.resize(n), f0_.resize(n), unknown_.resize(n), node_.resize(n), X_.resize(n);
  for (size_t e = 0; e < n; ++e) {
    const int t = tets_[e];
    const Material& mat = tet_material[size_t(t)];
    X_[e] = tet_corners(m, t);
    rest_[e] = tet_rest(X_[e], mat);
    K0_[e] = element_stiffness(X_[e], mat);
    // f0_e = V B^T D eps0: the linear law's force at rest, negated.
    TetRest linear = rest_[e];
    linear.model = MaterialModel::linear;
    element_force(linear, X_[e], f0_[e]);
    f0_[e] = -f0_[e];
    for (int k = 0; k < 4; ++k) {
      node_[e][size_t(k)] = m.tets(t, k);
      unknown_[e][size_t(k)] = node_unknown[size_t(m.tets(t, k))];
    }
    force_unit_ += rest_[e].mu * std::cbrt(rest_[e].volume * rest_[e].volume);
  }
}

double evaluate(const NonlinearTets& set, const Eigen::VectorXd& x, const Eigen::MatrixX3d& prescribed,
                Eigen::VectorXd& d, NonlinearWork& work, bool tangent) {
  const int n = set.size();
  work.D.resize(size_t(n));
  work.x.resize(size_t(n));
  work.force_unit = set.force_unit();
  double energy = 0;
  Vec12 f, uf;
  Mat12 K;
  for (int e = 0; e < n; ++e) {
    const auto& unk = set.unknown(e);
    TetCorners u;
    for (int k = 0; k < 4; ++k) {
      const int j = unk[size_t(k)];
      if (j >= 0) u.row(k) = x.segment<3>(3 * Eigen::Index(j)).transpose();
      else if (prescribed.size() > 0) u.row(k) = prescribed.row(set.node(e)[size_t(k)]);
      else u.row(k).setZero();
      uf.segment<3>(3 * k) = j >= 0 ? Eigen::Vector3d(u.row(k).transpose()) : Eigen::Vector3d::Zero();
    }
    const TetCorners& X = set.corners(e);
    TetCorners& xe = work.x[size_t(e)];
    xe = X + u;
    const TetRest& r = set.rest(e);
    double energy_e = 0;
    element_force(r, xe, f, tangent ? &K : nullptr, tangent ? Tangent::exact : Tangent::none, &energy_e);
    const Mat12& K0 = set.linear_stiffness(e);
    const Vec12& f0 = set.initial_force(e);
    const Vec12 K0u = K0 * uf;
    const Vec12 de = f - K0u + f0;
    energy += energy_e - 0.5 * uf.dot(K0u) + f0.dot(uf);
    for (int k = 0; k < 4; ++k)
      if (unk[size_t(k)] >= 0) d.segment<3>(3 * Eigen::Index(unk[size_t(k)])) += de.segment<3>(3 * k);
    if (tangent) {
      Mat12& D = work.D[size_t(e)];
      D = K - K0;
      for (int k = 0; k < 4; ++k)
        if (unk[size_t(k)] < 0) D.middleRows<3>(3 * k).setZero(), D.middleCols<3>(3 * k).setZero();
    }
  }
  return energy;
}

void measure_deformation(const NonlinearTets& set, NonlinearWork& work) {
  work.max_rotation = work.max_strain = 0;
  work.inverted = 0;
  for (int e = 0; e < set.size() && size_t(e) < work.x.size(); ++e) {
    const TetRest& r = set.rest(e);
    if (r.model == MaterialModel::linear) continue;
    const Eigen::Matrix3d F = deformation_gradient(r, work.x[size_t(e)]);
    const Deformation def = deformation(F);
    work.max_rotation = std::max(work.max_rotation, def.rotation);
    work.max_strain = std::max(work.max_strain, def.strain);
    work.inverted += F.determinant() <= 0;
  }
}

void project(const NonlinearTets& set, NonlinearWork& work) {
  Vec12 f;
  Mat12 K;
  for (int e = 0; e < set.size(); ++e) {
    if (set.rest(e).model == MaterialModel::linear) continue;  // K_T = K_e: D stays 0
    element_force(set.rest(e), work.x[size_t(e)], f, &K, Tangent::projected);
    Mat12& D = work.D[size_t(e)];
    D = K - set.linear_stiffness(e);
    for (int k = 0; k < 4; ++k)
      if (set.unknown(e)[size_t(k)] < 0) D.middleRows<3>(3 * k).setZero(), D.middleCols<3>(3 * k).setZero();
  }
}

void apply_difference(const NonlinearTets& set, const NonlinearWork& work, const Eigen::VectorXd& p,
                      Eigen::VectorXd& y) {
  Vec12 pe;
  for (int e = 0; e < set.size(); ++e) {
    if (set.rest(e).model == MaterialModel::linear) continue;
    const auto& unk = set.unknown(e);
    for (int k = 0; k < 4; ++k)
      pe.segment<3>(3 * k) = unk[size_t(k)] >= 0 ? Eigen::Vector3d(p.segment<3>(3 * Eigen::Index(unk[size_t(k)])))
                                                 : Eigen::Vector3d::Zero();
    const Vec12 ye = work.D[size_t(e)] * pe;
    for (int k = 0; k < 4; ++k)
      if (unk[size_t(k)] >= 0) y.segment<3>(3 * Eigen::Index(unk[size_t(k)])) += ye.segment<3>(3 * k);
  }
}

}  // namespace softcut::fem
