#include "hybrid/precompute.hpp"

#include <doctest/doctest.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <random>

#include "fem/assembly.hpp"
#include "fixtures.hpp"

using namespace softcut;
using namespace softcut::hybrid;

namespace {

// Global DOF indices of a node list, node-major.
std::vector<int> dofs(const std::vector<int>& nodes) {
  std::vector<int> d;
  for (int v : nodes)
    for (int a = 0; a < 3; ++a) d.push_back(3 * v + a);
  return d;
}

Eigen::MatrixXd pick(const Eigen::MatrixXd& K, const std::vector<int>& r, const std::vector<int>& c) {
  Eigen::MatrixXd B(r.size(), c.size());
  for (size_t i = 0; i < r.size(); ++i)
    for (size_t j = 0; j < c.size(); ++j) B(Eigen::Index(i), Eigen::Index(j)) = K(r[i], c[j]);
  return B;
}

double rel(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return b.norm() > 0 ? (a - b).norm() / b.norm() : (a - b).norm();
}

}  // namespace

TEST_SUITE("hybrid/precompute") {
  TEST_CASE("every Table 1 block equals its explicit dense Schur-complement form") {
    std::mt19937 rng(42);
    int checked = 0;
    for (int trial = 0; trial < 60 && checked < 8; ++trial) {
      const test::HybridCase c = test::random_case(rng, trial % 4, 4);
      const Partition& p = c.partition;
      if (p.surface.empty() || p.interior.empty() || p.interface.empty()) continue;
      PrecomputeOptions po;
      po.storage = Storage::dense;
      po.block_columns = 7;  // several column blocks even on tiny meshes
      po.block_threads = 2;  // two blocks solved side by side
      po.initial_loads = test::load_field(c.mesh.num_nodes(), test::random_loads(p, rng, 5));
      const Model M = precompute(c.mesh, c.material, p, po);
      po.block_threads = 1;  // one after the other: the same bits
      const Model M1 = precompute(c.mesh, c.material, p, po);
      CHECK(M1.Kstar_inv == M.Kstar_inv);
      CHECK(M1.Kstar_inv_Pstar == M.Kstar_inv_Pstar);
      CHECK(*M1.K_prime == *M.K_prime);

      // Independent dense route: K^non by DOF lists, K22 inverted outright.
      const Eigen::MatrixXd Kn(fem::assemble_stiffness(c.mesh, c.material, p.nonoperational_tets));
      const auto s = dofs(p.surface), i = dofs(p.interior), I = dofs(p.interface);
      std::vector<int> two = s;
      two.insert(two.end(), i.begin(), i.end());
      const Eigen::MatrixXd K22inv = pick(Kn, two, two).inverse();
      const Eigen::MatrixXd Kss = pick(Kn, s, s), Ksi = pick(Kn, s, i), Kii = pick(Kn, i, i);
      const Eigen::MatrixXd KiI = pick(Kn, i, I), KsI = pick(Kn, s, I);
      const Eigen::MatrixXd Kii_inv = Kii.inverse();
      const Eigen::MatrixXd Kstar = Kss - Ksi * Kii_inv * Ksi.transpose();
      const Eigen::MatrixXd Pstar = Ksi * Kii_inv * KiI - KsI;
      const Eigen::MatrixXd Kstar_inv = Kstar.inverse();
      const Eigen::MatrixXd K2I = pick(Kn, two, I);
      const Eigen::MatrixXd Kprime = pick(Kn, I, I) - K2I.transpose() * K22inv * K2I;
      const Eigen::MatrixXd H = (K2I.transpose() * K22inv).leftCols(Eigen::Index(s.size()));
      const Eigen::VectorXd Ps0 = gather_nodes(po.initial_loads, p.surface);

      INFO("trial ", trial, " ", describe(p.counts));
      CHECK(rel(M.Kstar_inv, Kstar_inv) <= 1e-12);
      CHECK(rel(M.Kstar_inv_Pstar, Kstar_inv * Pstar) <= 1e-12);
      CHECK(rel(*M.K_prime, Kprime) <= 1e-12);
      CHECK(rel(M.KI2_K22inv_s, H) <= 1e-12);
      CHECK(rel(M.Kstar_inv_Ps0, Kstar_inv * Ps0) <= 1e-12);
      CHECK(rel(M.P_prime0, H * Ps0) <= 1e-12);
      CHECK(rel(*M.K_prime, M.K_prime->transpose()) == 0);
      po.storage = Storage::factor;  // K' from the bordered factorisation instead of solves
      const Model F = precompute(c.mesh, c.material, p, po);
      CHECK(rel(*F.K_prime, Kprime) <= 1e-12);
      CHECK(rel(*F.K_prime, F.K_prime->transpose()) == 0);
      ++checked;
    }
    CHECK(checked == 8);
  }

  TEST_CASE("factor storage keeps K' and the initial-load terms, not the dense blocks") {
    std::mt19937 rng(4);
    const test::HybridCase c = test::random_case(rng, 0, 3);
    PrecomputeOptions po;
    po.initial_loads = test::load_field(c.mesh.num_nodes(), test::random_loads(c.partition, rng, 4));
    po.storage = Storage::dense;
    const Model d = precompute(c.mesh, c.material, c.partition, po);
    po.storage = Storage::factor;
    const Model f = precompute(c.mesh, c.material, c.partition, po);
    CHECK(f.Kstar_inv.size() == 0);
    CHECK(f.Kstar_inv_Pstar.size() == 0);
    CHECK(rel(*f.K_prime, *d.K_prime) <= 1e-12);  // two routes: solves vs bordered factor
    CHECK(rel(f.Kstar_inv_Ps0, d.Kstar_inv_Ps0) <= 1e-12);
    CHECK(rel(f.P_prime0, d.P_prime0) <= 1e-12);
    CHECK(f.timings.total_ms > 0);
  }

  TEST_CASE("initial loads on interior nodes and mismatched inputs are refused") {
    std::mt19937 rng(6);
    test::HybridCase c;
    do c = test::random_case(rng, 2); while (c.partition.interior.empty());
    PrecomputeOptions po;
    po.initial_loads = Eigen::MatrixX3d::Zero(c.mesh.num_nodes(), 3);
    po.initial_loads(c.partition.interior[0], 2) = 1;
    CHECK_THROWS_WITH_AS(precompute(c.mesh, c.material, c.partition, po), doctest::Contains("condensed away"), Error);
    std::vector<fem::Material> short_list(c.material.begin(), c.material.end() - 1);
    CHECK_THROWS_WITH_AS(precompute(c.mesh, short_list, c.partition, {}), doctest::Contains("materials"), Error);
  }
}
