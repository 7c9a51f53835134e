#include "fem/nonlinear_tets.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/helper_thread.hpp"
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

namespace {

// out += work.scratch's per-tet 12-vectors at their unknowns, in tet order
// (the order a serial loop adds them in, whoever computed them).
void add_scratch(const NonlinearTets& set, const NonlinearWork& work, Eigen::VectorXd& out) {
  for (int e = 0; e < set.size(); ++e) {
    const auto& unk = set.unknown(e);
    for (int k = 0; k < 4; ++k)
      if (unk[size_t(k)] >= 0)
        out.segment<3>(3 * Eigen::Index(unk[size_t(k)])) += work.scratch[size_t(e)].segment<3>(3 * k);
  }
}

}  // namespace

double evaluate(const NonlinearTets& set, const Eigen::VectorXd& x, const Eigen::MatrixX3d& prescribed,
                Eigen::VectorXd& d, NonlinearWork& work, bool tangent, HelperThread* helper) {
  const int n = set.size();
  work.D.resize(size_t(n));
  work.x.resize(size_t(n));
  work.scratch.resize(size_t(n));
  work.force_unit = set.force_unit();
  // The tets in two fixed halves, the second on the helper: each tet's
  // force difference into work.scratch, added into d in tet order after;
  // the energy as the two halves' sums. The same bits with or without it.
  double energy[2] = {0, 0};
  row_halves(helper, n, [&](long first, long count) {
    Vec12 f, uf;
    Mat12 K;
    double sum = 0;
    for (long e = first; e < first + count; ++e) {
      const auto& unk = set.unknown(int(e));
      TetCorners u;
      for (int k = 0; k < 4; ++k) {
        const int j = unk[size_t(k)];
        if (j >= 0) u.row(k) = x.segment<3>(3 * Eigen::Index(j)).transpose();
        else if (prescribed.size() > 0) u.row(k) = prescribed.row(set.node(int(e))[size_t(k)]);
        else u.row(k).setZero();
        uf.segment<3>(3 * k) = j >= 0 ? Eigen::Vector3d(u.row(k).transpose()) : Eigen::Vector3d::Zero();
      }
      TetCorners& xe = work.x[size_t(e)];
      xe = set.corners(int(e)) + u;
      double energy_e = 0;
      element_force(set.rest(int(e)), xe, f, tangent ? &K : nullptr, tangent ? Tangent::exact : Tangent::none,
                    &energy_e);
      const Mat12& K0 = set.linear_stiffness(int(e));
      const Vec12& f0 = set.initial_force(int(e));
      const Vec12 K0u = K0 * uf;
      work.scratch[size_t(e)] = f - K0u + f0;
      sum += energy_e - 0.5 * uf.dot(K0u) + f0.dot(uf);
      if (tangent) {
        Mat12& D = work.D[size_t(e)];
        D = K - K0;
        for (int k = 0; k < 4; ++k)
          if (unk[size_t(k)] < 0) D.middleRows<3>(3 * k).setZero(), D.middleCols<3>(3 * k).setZero();
      }
    }
    energy[first == 0 ? 0 : 1] = sum;
  });
  add_scratch(set, work, d);
  return energy[0] + energy[1];
}

void measure_deformation(const NonlinearTets& set, NonlinearWork& work) {
  work.max_rotation = work.max_strain = 0;
  work.inverted = 0;
  for (int e = 0; e < set.size() && size_t(e) < work.x.size(); ++e) {
    const TetRest& r = set.rest(e);
    if (r.model == MaterialModel::linear) continue;
    const Eigen::Matrix3d F = deformation_gradient(r, work.x[size_t(e)]);
    const Deformation def = deformation(F, work.max_strain);  // its strain only where it can pass the largest so far
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

void apply_difference(const NonlinearTets& set, NonlinearWork& work, const Eigen::VectorXd& p, Eigen::VectorXd& y,
                      HelperThread* helper) {
  work.scratch.resize(size_t(set.size()));
  row_halves(helper, set.size(), [&](long first, long count) {
    Vec12 pe;
    for (long e = first; e < first + count; ++e) {
      if (set.rest(int(e)).model == MaterialModel::linear) {
        work.scratch[size_t(e)].setZero();
        continue;
      }
      const auto& unk = set.unknown(int(e));
      for (int k = 0; k < 4; ++k)
        pe.segment<3>(3 * k) = unk[size_t(k)] >= 0
                                   ? Eigen::Vector3d(p.segment<3>(3 * Eigen::Index(unk[size_t(k)])))
                                   : Eigen::Vector3d::Zero();
      work.scratch[size_t(e)].noalias() = work.D[size_t(e)] * pe;
    }
  });
  add_scratch(set, work, y);
}

}  // namespace softcut::fem
