#include "hybrid/factor_correction.hpp"

#include <doctest/doctest.h>

#include <Eigen/LU>
#include <algorithm>
#include <cstdlib>
#include <random>

#include "core/error.hpp"
#include "core/threads.hpp"
#include "fixtures.hpp"
#include "hybrid/operational_solvers.hpp"
#include "hybrid/precompute.hpp"

using namespace softcut;
using namespace softcut::hybrid;

namespace {

// A changing operational mesh, as cutting changes it (cut/ is a later stage:
// these changes are made by hand): a crack at a free node (the node is
// duplicated for the tets on one side: a node appended, its neighbours'
// rows changed), a stiffness change of a few tets (rows changed, no node
// appended), and the removal of every tet around a node (a node dropped).
struct Changing {
  mesh::TetMesh mesh;
  std::vector<fem::Material> material;
  std::vector<int> op_tets;
  std::vector<int> free_nodes;  // set-1 nodes of the rest mesh (never interface, never fixed)

  bool crack(std::mt19937& rng) {
    const int v = free_nodes[rng() % free_nodes.size()];
    const Eigen::Vector3d dir = Eigen::Vector3d::Random().normalized();
    std::vector<int> side, all;
    for (int t : op_tets)
      for (int k = 0; k < 4; ++k)
        if (mesh.tets(t, k) == v) {
          all.push_back(t);
          Eigen::Vector3d c = Eigen::Vector3d::Zero();
          for (int j = 0; j < 4; ++j) c += mesh.node(mesh.tets(t, j)) / 4;
          if ((c - mesh.node(v)).dot(dir) > 0) side.push_back(t);
        }
    if (side.empty() || side.size() == all.size()) return false;
    const int nv = mesh.num_nodes();
    mesh.nodes.conservativeResize(nv + 1, 3);
    mesh.nodes.row(nv) = mesh.nodes.row(v);
    for (int t : side)
      for (int k = 0; k < 4; ++k)
        if (mesh.tets(t, k) == v) mesh.tets(t, k) = nv;
    return true;
  }
  bool soften(std::mt19937& rng) {
    for (int i = 0; i < 3; ++i) material[size_t(op_tets[rng() % op_tets.size()])].young *= 0.3;
    return true;
  }
  bool drop(std::mt19937& rng) {
    const int v = free_nodes[rng() % free_nodes.size()];
    const auto before = op_tets.size();
    std::erase_if(op_tets, [&](int t) {
      for (int k = 0; k < 4; ++k)
        if (mesh.tets(t, k) == v) return true;
      return false;
    });
    return op_tets.size() < before && !op_tets.empty();
  }
};

double rel(const Eigen::VectorXd& a, const Eigen::VectorXd& b) { return (a - b).norm() / b.norm(); }

// Runs `steps` changes on random cases; after each, the solver kept since the
// first system solves the new one and is compared with a dense LU of the
// assembled system (independent truth) and with a fresh CHOLMOD factor.
struct Outcome {
  int solves = 0, corrected = 0, refined = 0, appended = 0, dropped = 0;
  int one_blas_thread = 0;  // solves after which OpenBLAS was on one thread (a refactor pending)
  long refactors = 0, adopted = 0, fallbacks = 0;
  std::vector<Eigen::VectorXd> solutions;
};

Outcome run_changes(unsigned seed, int cases, int steps, int max_cells, double budget,
                    std::shared_ptr<HelperThread> helper = nullptr) {
  std::mt19937 rng(seed);
  Outcome out;
  for (int trial = 0; trial < cases; ++trial) {
    test::HybridCase c;
    do c = test::random_case(rng, 2 * (trial % 2), max_cells);  // sphere, half-space
    while (c.partition.operational.size() < 8 || c.partition.interface.empty());
    const Model M = precompute(c.mesh, c.material, c.partition, {});
    Changing ch{c.mesh, c.material, {}, c.partition.operational};
    for (int t = 0; t < c.mesh.num_tets(); ++t)
      if (c.partition.operational_tet[size_t(t)]) ch.op_tets.push_back(t);
    CholmodSolver kept(false, true, budget);
    if (helper) kept.share_helper(helper);
    Eigen::VectorXd x;
    std::shared_ptr<const OperationalSystem> sys = M.operational;
    for (int s = 0; s <= steps; ++s) {
      if (s > 0) {
        Changing next = ch;
        const int kind = int(rng() % 3);
        if (!(kind == 0 ? next.crack(rng) : kind == 1 ? next.soften(rng) : next.drop(rng))) continue;
        std::shared_ptr<const OperationalSystem> cand =
            rebuild_operational_system(M, next.mesh, next.material, next.op_tets);
        // A part that came loose or hangs by a node (nearly singular) is no test of the correction.
        const Eigen::LLT<Eigen::MatrixXd> llt{Eigen::MatrixXd(cand->assembled())};
        if (llt.info() != Eigen::Success || llt.rcond() < 1e-9) continue;
        ch = std::move(next);
        out.appended += int(cand->nodes.size() > sys->nodes.size() && kind == 0);
        out.dropped += int(kind == 2);
        sys = cand;
      }
      const Eigen::VectorXd b = Eigen::VectorXd::Random(sys->size());
      const SolveReport r = kept.solve(*sys, b, x);
      const Eigen::PartialPivLU<Eigen::MatrixXd> lu(Eigen::MatrixXd(sys->assembled()));
      const Eigen::VectorXd truth = lu.solve(b);
      CholmodSolver fresh(false, false);
      Eigen::VectorXd xf;
      fresh.solve(*sys, b, xf);
      CAPTURE(trial);
      CAPTURE(s);
      CAPTURE(r.correction_rank);
      CHECK(r.relative_residual <= 1e-12);
      CHECK(rel(x, truth) <= 1e-9);
      CHECK(rel(x, xf) <= 1e-9);
      ++out.solves;
      out.solutions.push_back(x);
      out.one_blas_thread += blas_threads() == 1;
      out.corrected += r.correction_rank > 0;
      out.refined += r.iterations > 0;
      // A second right-hand side on the same system: no new factor.
      const long factors = kept.refactors();
      const Eigen::VectorXd b2 = Eigen::VectorXd::Random(sys->size());
      kept.solve(*sys, b2, x);
      CHECK(rel(x, lu.solve(b2)) <= 1e-9);
      if (budget > 1e6) CHECK(kept.refactors() == factors);
    }
    out.refactors += kept.refactors();
    out.adopted += kept.adopted();
    out.fallbacks += kept.fallbacks();
  }
  return out;
}

}  // namespace

TEST_SUITE("hybrid/factor_correction") {
  TEST_CASE("the kept factor with a low-rank correction solves cracked, softened and thinned systems exactly") {
    // An unbounded budget: every change goes through the correction (on
    // these small systems the flop rule would rather refactor).
    const Outcome o = run_changes(41, 8, 6, 5, 1e9);
    MESSAGE(o.solves, " solves, ", o.corrected, " corrected, ", o.refactors, " factors, ", o.adopted, " from the second thread");
    CHECK(o.solves >= 40);
    CHECK(o.corrected >= o.solves - 8);  // all but each case's first system
    CHECK(o.refined == 0);               // exact without refinement
    CHECK(o.fallbacks == 0);             // no residual sent a solve to a refactor
    CHECK(o.appended >= 3);
    CHECK(o.dropped >= 3);
  }

  TEST_CASE("a long sequence of changes spends the budget: the factor made on the second thread takes over") {
    // OpenBLAS on two threads, which a pending refactor holds at one from its
    // launch to its adoption (so the frames keep a core), then gives back.
    REQUIRE(blas_threads() > 0);
    const int before = blas_threads();
    apply_blas_threads(2);
    const Outcome o = run_changes(7, 3, 30, 5, 20.0);
    CHECK(blas_threads() == 2);
    apply_blas_threads(before);
    MESSAGE(o.solves, " solves, ", o.corrected, " corrected, ", o.refactors, " factors, ", o.adopted, " from the second thread");
    CHECK(o.solves >= 45);
    CHECK(o.adopted >= 3);
    CHECK(o.one_blas_thread >= o.adopted);  // each adopted factor was pending over a solve at least
    CHECK(o.one_blas_thread < o.solves);
    CHECK(o.fallbacks == 0);  // every taken-over factor solved its systems exactly
    CHECK(o.corrected >= o.solves / 3);
  }

  TEST_CASE("with the run's helper thread: the same bits, OpenBLAS on one thread while corrected, given back") {
    // Both runs start from OpenBLAS on two threads; the helper computes the
    // second halves of new columns and of W's products.
    REQUIRE(blas_threads() > 0);
    const int before = blas_threads();
    apply_blas_threads(2);
    std::srand(43);  // Eigen's Random: the same right-hand sides in both runs
    const Outcome alone = run_changes(43, 4, 8, 6, 1e9);
    auto helper = std::make_shared<HelperThread>();
    helper->leave_to_helper(true);  // the second halves are the helper's under any load
    std::srand(43);
    const Outcome helped = run_changes(43, 4, 8, 6, 1e9, helper);
    CHECK(blas_threads() == 2);  // the solvers are gone: given back
    apply_blas_threads(before);
    REQUIRE(helped.solutions.size() == alone.solutions.size());
    REQUIRE(alone.corrected >= 20);
    for (size_t k = 0; k < alone.solutions.size(); ++k) {
      CAPTURE(k);
      CHECK((helped.solutions[k].array() == alone.solutions[k].array()).all());
    }
    CHECK(helper->helped() > 0);
    CHECK(alone.one_blas_thread == 0);
    CHECK(helped.one_blas_thread == helped.corrected);  // held exactly while corrected
  }

  TEST_CASE("prepare refuses what it cannot correct: another interface, more changed DOFs than allowed, no budget") {
    std::mt19937 rng(5);
    test::HybridCase c;
    do c = test::random_case(rng, 1, 4);
    while (c.partition.operational.size() < 8 || c.partition.interface.empty());
    const Model M = precompute(c.mesh, c.material, c.partition, {});
    const OperationalSystem& base = *M.operational;
    solve::Cholesky F;
    F.factor(base.assembled(), "test");
    Changing ch{c.mesh, c.material, {}, c.partition.operational};
    for (int t = 0; t < c.mesh.num_tets(); ++t)
      if (c.partition.operational_tet[size_t(t)]) ch.op_tets.push_back(t);
    REQUIRE(ch.soften(rng));
    const auto next = rebuild_operational_system(M, ch.mesh, ch.material, ch.op_tets);
    solve::SolveWorkspace ws;
    FactorCorrection fc;
    double flops = -1;
    CHECK(!fc.prepare(base, F, *next, 2, 1e18, ws, &flops));     // at least one node (3 DOFs) changed
    CHECK(!fc.prepare(base, F, *next, 1 << 20, 1.0, ws, &flops));  // no budget
    CHECK(flops == 0);
    CHECK(fc.kept_columns() == 0);  // nothing computed when refused
    OperationalSystem other = *next;
    other.K_prime = std::make_shared<const Eigen::MatrixXd>(*next->K_prime);  // equal values, another K'
    CHECK(!fc.prepare(base, F, other, 1 << 20, 1e18, ws));
    OperationalSystem hand = *next;
    hand.block.row_start.clear();  // a hand-made system without node blocks
    CHECK(!fc.prepare(base, F, hand, 1 << 20, 1e18, ws));
    REQUIRE(fc.prepare(base, F, *next, 1 << 20, 1e18, ws, &flops));
    CHECK(flops > 0);
    CHECK(fc.rank() % 3 == 0);
    CHECK(fc.rank() > 0);
    CHECK(fc.kept_columns() == fc.rank());
    const Eigen::VectorXd b = Eigen::VectorXd::Random(next->size());
    Eigen::VectorXd x;
    fc.solve(F, b, x, ws);
    CHECK(rel(x, Eigen::MatrixXd(next->assembled()).partialPivLu().solve(b)) <= 1e-10);
    // The base itself: nothing changed, nothing to correct.
    REQUIRE(fc.prepare(base, F, base, 1 << 20, 1e18, ws));
    CHECK(fc.rank() == 0);
    fc.solve(F, b.head(base.size()), x, ws);
    CHECK(rel(x, Eigen::VectorXd(F.solve(Eigen::MatrixXd(b.head(base.size())), ws))) <= 1e-14);
  }

  TEST_CASE("a change that leaves a loose piece is refused and the refactor names it") {
    std::mt19937 rng(9);
    for (int trial = 0; trial < 40; ++trial) {
      test::HybridCase c;
      do c = test::random_case(rng, 0, 5);
      while (c.partition.operational.size() < 8 || c.partition.interface.empty());
      // An operational tet whose four nodes are all free set-1 nodes: kept
      // alone, it floats (six rigid modes).
      std::vector<char> free1(size_t(c.mesh.num_nodes()), 0);
      for (int v : c.partition.operational) free1[size_t(v)] = 1;
      int lone = -1;
      for (int t = 0; t < c.mesh.num_tets() && lone < 0; ++t)
        if (c.partition.operational_tet[size_t(t)] && free1[size_t(c.mesh.tets(t, 0))] &&
            free1[size_t(c.mesh.tets(t, 1))] && free1[size_t(c.mesh.tets(t, 2))] && free1[size_t(c.mesh.tets(t, 3))])
          lone = t;
      if (lone < 0) continue;
      const Model M = precompute(c.mesh, c.material, c.partition, {});
      CholmodSolver kept(false, true, 1e9);
      Eigen::VectorXd x;
      kept.solve(*M.operational, Eigen::VectorXd::Random(M.operational->size()), x);
      const auto loose = rebuild_operational_system(M, c.mesh, c.material, {lone});
      solve::Cholesky F;
      F.factor(M.operational->assembled(), "test");
      solve::SolveWorkspace ws;
      FactorCorrection fc;
      CHECK_FALSE(fc.prepare(*M.operational, F, *loose, 1 << 20, 1e18, ws));
      CHECK_THROWS_WITH(kept.solve(*loose, Eigen::VectorXd::Random(loose->size()), x),
                        doctest::Contains("not positive definite"));
      CHECK(kept.fallbacks() == 0);  // refused before any solve, not caught by its residual
      return;
    }
    FAIL("no case with an operational tet of four free nodes");
  }

  TEST_CASE("forward and backward halves of a CHOLMOD solve compose to the solve") {
    std::mt19937 rng(3);
    const test::HybridCase c = test::random_case(rng, 5, 3);
    const Model M = precompute(c.mesh, c.material, c.partition, {});
    solve::Cholesky F;
    F.factor(M.operational->assembled(), "test");
    solve::SolveWorkspace ws;
    const Eigen::MatrixXd B = Eigen::MatrixXd::Random(F.rows(), 3);
    Eigen::MatrixXd Y;
    F.forward_into(B, Y, ws);
    Eigen::VectorXd x;
    F.backward_into(Y.col(1), x, ws);
    CHECK(rel(x, Eigen::VectorXd(F.solve(Eigen::MatrixXd(B.col(1)), ws))) <= 1e-13);
    // (A^-1)(i, j) = forward(e_i) . forward(e_j)
    const Eigen::MatrixXd E = Eigen::MatrixXd::Identity(F.rows(), 2);
    F.forward_into(E, Y, ws);
    const Eigen::MatrixXd Ainv_cols = F.solve(E, ws);
    CHECK(std::abs(Y.col(0).dot(Y.col(1)) - Ainv_cols(0, 1)) <= 1e-12 * std::abs(Ainv_cols(0, 0)));
    CHECK(F.factor_flops() > 0);
  }
}
