#include "hybrid/operational_system.hpp"

#include <doctest/doctest.h>

#include <Eigen/LU>
#include <random>

#include "fem/assembly.hpp"
#include "fem/fem_fixtures.hpp"
#include "fixtures.hpp"
#include "hybrid/precompute.hpp"

using namespace softcut;
using namespace softcut::hybrid;

TEST_SUITE("hybrid/operational_system") {
  TEST_CASE("K + K' is the Schur complement of the whole free stiffness onto the operational DOFs") {
    std::mt19937 rng(12);
    int checked = 0;
    for (int trial = 0; trial < 15; ++trial) {
      const test::HybridCase c = test::random_case(rng, trial % 4, 3);
      const Partition& p = c.partition;
      if (p.interface.empty()) continue;
      const Model M = precompute(c.mesh, c.material, p, {});
      const OperationalSystem& sys = *M.operational;
      // DOF ordering: set 1 first, interface last and contiguous.
      CHECK(sys.num_operational == int(p.operational.size()));
      CHECK(sys.num_interface == int(p.interface.size()));
      for (int k = 0; k < sys.num_interface; ++k)
        CHECK(sys.nodes[size_t(sys.num_operational + k)] == p.interface[size_t(k)]);
      for (size_t k = 0; k < sys.nodes.size(); ++k) CHECK(sys.node_index[size_t(sys.nodes[k])] == int(k));

      // Dense reference: whole K over free nodes, op DOFs first, eliminate the rest.
      const Eigen::MatrixXd K(fem::assemble_stiffness(c.mesh, c.material));
      std::vector<int> a, b;
      for (int v : sys.nodes)
        for (int x = 0; x < 3; ++x) a.push_back(3 * v + x);
      for (const auto* set : {&p.surface, &p.interior})
        for (int v : *set)
          for (int x = 0; x < 3; ++x) b.push_back(3 * v + x);
      auto pick = [&](const std::vector<int>& r, const std::vector<int>& cc) {
        Eigen::MatrixXd B(r.size(), cc.size());
        for (size_t i = 0; i < r.size(); ++i)
          for (size_t j = 0; j < cc.size(); ++j) B(Eigen::Index(i), Eigen::Index(j)) = K(r[i], cc[j]);
        return B;
      };
      const Eigen::MatrixXd S = pick(a, a) - pick(a, b) * pick(b, b).inverse() * pick(b, a);
      const Eigen::MatrixXd A(sys.assembled());
      CHECK((A - S).norm() <= 1e-12 * S.norm());
      // apply() agrees with the assembled matrix.
      const Eigen::VectorXd x = Eigen::VectorXd::Random(sys.size());
      Eigen::VectorXd y;
      sys.apply(x, y);
      CHECK((y - A * x).norm() <= 1e-13 * (A * x).norm());
      ++checked;
    }
    CHECK(checked >= 5);
  }

  TEST_CASE("apply on the 3x3 node blocks equals the assembled matrix times x, and a hand-made system falls back to K") {
    std::mt19937 rng(71);
    int checked = 0;
    for (int trial = 0; trial < 20; ++trial) {
      const test::HybridCase c = test::random_case(rng, trial % 4, 3);
      const Model M = precompute(c.mesh, c.material, c.partition, {});
      const OperationalSystem& sys = *M.operational;
      if (sys.size() == 0) continue;
      CHECK(sys.block.row_start.size() == sys.nodes.size() + 1);
      const Eigen::VectorXd x = Eigen::VectorXd::Random(sys.size());
      Eigen::VectorXd y, y_plain;
      sys.apply(x, y);
      const Eigen::VectorXd ref = sys.assembled() * x;
      CHECK((y - ref).norm() <= 1e-13 * ref.norm());
      OperationalSystem plain = sys;  // no blocks: the scalar sparse product
      plain.block.row_start.clear();
      plain.apply(x, y_plain);
      CHECK((y_plain - ref).norm() <= 1e-13 * ref.norm());
      ++checked;
    }
    CHECK(checked >= 10);
  }

  TEST_CASE("the assembled matrix is K with K' summed into its interface corner, entry for entry and bit for bit") {
    std::mt19937 rng(37);
    int checked = 0;
    for (int trial = 0; trial < 16; ++trial) {
      const test::HybridCase c = test::random_case(rng, trial % 4, 3);
      const Model M = precompute(c.mesh, c.material, c.partition, {});
      const OperationalSystem& sys = *M.operational;
      if (sys.num_interface == 0) continue;
      // Reference: the same sums through triplets.
      std::vector<Eigen::Triplet<double>> trip;
      for (int col = 0; col < sys.K.outerSize(); ++col)
        for (SparseMatrix::InnerIterator it(sys.K, col); it; ++it) trip.emplace_back(int(it.row()), col, it.value());
      const int off = sys.interface_offset();
      for (Eigen::Index j = 0; j < sys.K_prime->cols(); ++j)
        for (Eigen::Index i = 0; i < sys.K_prime->rows(); ++i)
          trip.emplace_back(off + int(i), off + int(j), (*sys.K_prime)(i, j));
      SparseMatrix ref(sys.size(), sys.size());
      ref.setFromTriplets(trip.begin(), trip.end());
      const SparseMatrix A = sys.assembled();
      REQUIRE(A.nonZeros() == ref.nonZeros());
      CHECK(std::equal(A.outerIndexPtr(), A.outerIndexPtr() + A.cols() + 1, ref.outerIndexPtr()));
      CHECK(std::equal(A.innerIndexPtr(), A.innerIndexPtr() + A.nonZeros(), ref.innerIndexPtr()));
      CHECK(std::equal(A.valuePtr(), A.valuePtr() + A.nonZeros(), ref.valuePtr()));
      OperationalSystem loose = sys;  // a hand-made K, not compressed: the same matrix
      loose.K.uncompress();
      CHECK((Eigen::MatrixXd(loose.assembled()).array() == Eigen::MatrixXd(A).array()).all());
      ++checked;
    }
    CHECK(checked >= 8);
  }

  TEST_CASE("a system rebuilt from the one before a cut has K of a rebuild from scratch, bit for bit") {
    // Operational tets split at their centroids, one step after another;
    // each rebuild reuses the last system's rows.
    std::mt19937 rng(29);
    int reused = 0;
    for (int trial = 0; trial < 12; ++trial) {
      test::HybridCase c = test::random_case(rng, trial % 4, 3);
      if (c.partition.operational_tets.size() < 3) continue;
      const Model M = precompute(c.mesh, c.material, c.partition, {});
      std::shared_ptr<const OperationalSystem> sys = M.operational;
      std::vector<int> op = c.partition.operational_tets;
      for (int step = 0; step < 3; ++step) {
        CAPTURE(trial);
        CAPTURE(step);
        const int t = op[std::uniform_int_distribution<size_t>(0, op.size() - 1)(rng)], nt = c.mesh.num_tets();
        test::split_at_centroid(c.mesh, t);
        c.material.resize(size_t(nt + 3), c.material[size_t(t)]);
        for (int k = 0; k < 3; ++k) op.push_back(nt + k);
        fem::ReassemblyReport rep;
        const auto next = rebuild_operational_system(M, c.mesh, c.material, op, {}, sys.get(), &rep);
        const auto fresh = rebuild_operational_system(M, c.mesh, c.material, op);
        REQUIRE(next->nodes == fresh->nodes);
        CHECK(next->block.row_start == fresh->block.row_start);
        CHECK(next->block.col == fresh->block.col);
        CHECK(std::equal(next->block.blocks.begin(), next->block.blocks.end(), fresh->block.blocks.begin(),
                         fresh->block.blocks.end()));
        const SparseMatrix d = next->K - fresh->K;
        CHECK(next->K.nonZeros() == fresh->K.nonZeros());
        CHECK(d.norm() == 0);
        CHECK(rep.reused);
        CHECK(rep.rows_assembled < rep.rows);
        reused += rep.rows - rep.rows_assembled;
        sys = next;
      }
    }
    CHECK(reused > 0);
  }

  TEST_CASE("an operational tet reaching a nonoperational node is refused") {
    std::mt19937 rng(14);
    test::HybridCase c;
    do c = test::random_case(rng, 2, 3); while (c.partition.surface.empty() || c.partition.operational_tets.empty());
    const Model M = precompute(c.mesh, c.material, c.partition, {});
    std::vector<int> op = c.partition.operational_tets;
    op.push_back(c.partition.nonoperational_tets[0]);
    bool touches = false;
    for (int k = 0; k < 4; ++k) touches |= M.node_nonoperational[size_t(c.mesh.tets(op.back(), k))] != 0;
    if (touches)
      CHECK_THROWS_WITH_AS(rebuild_operational_system(M, c.mesh, c.material, op), doctest::Contains("past the interface"),
                           Error);
    CHECK_THROWS_WITH_AS(rebuild_operational_system(M, c.mesh, {}, c.partition.operational_tets),
                         doctest::Contains("materials"), Error);
  }
}
