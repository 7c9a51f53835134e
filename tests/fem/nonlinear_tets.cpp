// fem/nonlinear_tets: a region's element loops (DESIGN.md §1b), against the
// element kernels and finite differences, with and without a helper thread.
#include <doctest/doctest.h>

#include <random>

#include "core/helper_thread.hpp"
#include "fem/nonlinear_tets.hpp"
#include "fem_fixtures.hpp"

using namespace softcut;

namespace {

// A jittered box, corotational with a prestress, its x = 0 face fixed.
struct Region {
  mesh::TetMesh mesh = test::jittered_box(5, 4, 4, 0.2, 11, Eigen::Vector3d(0.02, 0.016, 0.016));
  std::vector<fem::Material> mat;
  std::vector<int> unknown;
  int unknowns = 0;
  fem::NonlinearTets set;
  Region() {
    mat.assign(size_t(mesh.num_tets()), fem::Material{3e3, 0.45});
    for (auto& m : mat) m.model = fem::MaterialModel::corotational, m.initial_strain = {0.01, 0, -0.02, 0, 0.005, 0};
    for (int v = 0; v < mesh.num_nodes(); ++v) unknown.push_back(mesh.nodes(v, 0) <= 1e-12 ? -1 : unknowns++);
    std::vector<int> tets(size_t(mesh.num_tets()));
    for (int t = 0; t < mesh.num_tets(); ++t) tets[size_t(t)] = t;
    set = fem::NonlinearTets(mesh, mat, tets, unknown);
  }
  // Unknowns of a large motion: a bend of the box about z plus noise (m).
  Eigen::VectorXd motion(unsigned seed) const {
    std::mt19937 rng(seed);
    std::normal_distribution<double> g(0, 1e-4);
    Eigen::VectorXd x(3 * unknowns);
    for (int v = 0; v < mesh.num_nodes(); ++v) {
      const int k = unknown[size_t(v)];
      if (k < 0) continue;
      const double a = 20.0 * mesh.nodes(v, 0);  // rad: 23 degrees at the free end
      const Eigen::Vector3d p = mesh.node(v);
      const Eigen::Vector3d q(p.x() * std::cos(a) - p.y() * std::sin(a), p.x() * std::sin(a) + p.y() * std::cos(a), p.z());
      for (int c = 0; c < 3; ++c) x[3 * k + c] = q[c] - p[c] + g(rng);
    }
    return x;
  }
};

}  // namespace

TEST_SUITE("fem/nonlinear_tets") {
  TEST_CASE("evaluate gives the element forces less K_e u gathered, and apply_difference the tangents less K_e") {
    const Region r;
    fem::NonlinearWork work;
    const Eigen::VectorXd x = r.motion(1);
    Eigen::VectorXd d = Eigen::VectorXd::Zero(x.size());
    fem::evaluate(r.set, x, {}, d, work);
    // The same from the element kernels, tet by tet.
    Eigen::VectorXd d_ref = Eigen::VectorXd::Zero(x.size()), p = Eigen::VectorXd::Random(x.size());
    Eigen::VectorXd y_ref = Eigen::VectorXd::Zero(x.size());
    for (int e = 0; e < r.set.size(); ++e) {
      fem::Vec12 uf = fem::Vec12::Zero(), pe = fem::Vec12::Zero(), f;
      fem::Mat12 K;
      for (int k = 0; k < 4; ++k)
        if (const int j = r.set.unknown(e)[size_t(k)]; j >= 0)
          uf.segment<3>(3 * k) = x.segment<3>(3 * j), pe.segment<3>(3 * k) = p.segment<3>(3 * j);
      fem::TetCorners xe = r.set.corners(e);
      for (int k = 0; k < 4; ++k) xe.row(k) += uf.segment<3>(3 * k).transpose();
      fem::element_force(r.set.rest(e), xe, f, &K, fem::Tangent::exact);
      const fem::Vec12 de = f - r.set.linear_stiffness(e) * uf + r.set.initial_force(e);
      const fem::Vec12 ye = (K - r.set.linear_stiffness(e)) * pe;
      for (int k = 0; k < 4; ++k)
        if (const int j = r.set.unknown(e)[size_t(k)]; j >= 0)
          d_ref.segment<3>(3 * j) += de.segment<3>(3 * k), y_ref.segment<3>(3 * j) += ye.segment<3>(3 * k);
    }
    CHECK((d - d_ref).norm() <= 1e-12 * d_ref.norm());
    Eigen::VectorXd y = Eigen::VectorXd::Zero(x.size());
    fem::apply_difference(r.set, work, p, y);
    CHECK((y - y_ref).norm() <= 1e-12 * y_ref.norm());
    CHECK(y_ref.norm() > 1e-3 * (d_ref.norm() / x.norm()) * p.norm());  // the motion is far from linear
  }

  TEST_CASE("evaluate and apply_difference give the same bits with a helper thread taking half the tets") {
    const Region r;
    REQUIRE(r.set.size() >= 128);  // two halves (row_halves splits from 64)
    const Eigen::VectorXd x = r.motion(2), p = Eigen::VectorXd::Random(x.size());
    fem::NonlinearWork alone, shared;
    Eigen::VectorXd d1 = Eigen::VectorXd::Zero(x.size()), d2 = d1, y1 = d1, y2 = d1;
    const double e1 = fem::evaluate(r.set, x, {}, d1, alone);
    fem::apply_difference(r.set, alone, p, y1);
    HelperThread helper;
    const long before = helper.helped();
    helper.leave_to_helper(true);  // the second halves are the helper's under any load
    const double e2 = fem::evaluate(r.set, x, {}, d2, shared, true, &helper);
    fem::apply_difference(r.set, shared, p, y2, &helper);
    helper.leave_to_helper(false);
    CHECK(helper.helped() >= before + 2);
    CHECK(e1 == e2);
    CHECK(d1 == d2);
    CHECK(y1 == y2);
    for (int e = 0; e < r.set.size(); ++e) CHECK(alone.D[size_t(e)] == shared.D[size_t(e)]);
  }

  TEST_CASE("evaluate: its d is the gradient of the energy it returns (no prestress: the law is conservative)") {
    Region r;
    for (auto& m : r.mat) m.initial_strain = {0, 0, 0, 0, 0, 0};
    std::vector<int> tets(size_t(r.mesh.num_tets()));
    for (int t = 0; t < r.mesh.num_tets(); ++t) tets[size_t(t)] = t;
    const fem::NonlinearTets set(r.mesh, r.mat, tets, r.unknown);
    fem::NonlinearWork work;
    const Eigen::VectorXd x = r.motion(3);
    Eigen::VectorXd d = Eigen::VectorXd::Zero(x.size()), scratch = d;
    fem::evaluate(set, x, {}, d, work, false);
    std::mt19937 rng(4);
    std::normal_distribution<double> g(0, 1);
    for (int trial = 0; trial < 5; ++trial) {
      Eigen::VectorXd v(x.size());
      for (auto& c : v) c = g(rng);
      const double h = 1e-8;
      const double ep = fem::evaluate(set, x + h * v, {}, scratch, work, false);
      const double em = fem::evaluate(set, x - h * v, {}, scratch, work, false);
      CHECK((ep - em) / (2 * h) == doctest::Approx(d.dot(v)).epsilon(1e-5));
    }
  }
}
