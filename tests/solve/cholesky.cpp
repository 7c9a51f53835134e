#include "solve/cholesky.hpp"

#include <doctest/doctest.h>
#include <fcntl.h>
#include <unistd.h>

#include <Eigen/Dense>
#include <array>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <vector>

#include "core/binary_io.hpp"
#include "core/error.hpp"
#include "core/helper_thread.hpp"
#include "spd_fixtures.hpp"

using namespace softcut;

namespace {

// One solve with a workspace of its own (every solve takes one).
Eigen::MatrixXd solved(const solve::Cholesky& c, const Eigen::MatrixXd& B) {
  solve::SolveWorkspace ws;
  return c.solve(B, ws);
}

// A saved supernodal factor taken apart (Cholesky::save's layout: an
// 11-int64 header, then each array as a u64 count and its elements, then
// lnz), so a test can change one entry and write it back with a valid CRC.
struct SavedSupernodal {
  std::array<std::int64_t, 11> header{};
  std::vector<int> perm, colcount, super, pi, px, s;
  std::vector<double> x;
  double lnz = 0;

  template <class T>
  static std::vector<T> take(const std::string& b, size_t& at) {
    std::uint64_t n = 0;
    std::memcpy(&n, b.data() + at, 8);
    std::vector<T> v(n);
    std::memcpy(v.data(), b.data() + at + 8, n * sizeof(T));
    at += 8 + n * sizeof(T);
    return v;
  }
  explicit SavedSupernodal(const solve::Cholesky& chol) {
    std::ostringstream out;
    BinaryWriter w(out);
    chol.save(w);
    const std::string b = out.str();
    size_t at = sizeof header;
    std::memcpy(header.data(), b.data(), sizeof header);
    perm = take<int>(b, at), colcount = take<int>(b, at), super = take<int>(b, at), pi = take<int>(b, at);
    px = take<int>(b, at), s = take<int>(b, at), x = take<double>(b, at);
    std::memcpy(&lnz, b.data() + at, 8);
  }
  // Written back through BinaryWriter (valid CRC) and loaded; the load's error or "".
  std::string load() const {
    const std::filesystem::path file = std::filesystem::temp_directory_path() / "softcut_test_crafted_factor.bin";
    {
      std::ofstream out(file, std::ios::binary);
      BinaryWriter w(out);
      w.pod(header);
      w.array(perm.data(), perm.size()), w.array(colcount.data(), colcount.size());
      w.array(super.data(), super.size()), w.array(pi.data(), pi.size()), w.array(px.data(), px.size());
      w.array(s.data(), s.size()), w.array(x.data(), x.size());
      w.pod(lnz);
      w.finish();
    }
    const int fd = ::open(file.c_str(), O_RDONLY);
    REQUIRE(fd >= 0);
    std::string err;
    try {
      BinaryReader r(fd, std::filesystem::file_size(file), "crafted.bin", 1);
      solve::Cholesky c;
      c.load(r);
      r.finish();
    } catch (const Error& e) {
      err = e.what();
    }
    ::close(fd);
    std::filesystem::remove(file);
    return err;
  }
};

extern "C" void stop_handler(int) {}

// SIGTERM's action now.
struct sigaction sigterm_action() {
  struct sigaction now {};
  sigaction(SIGTERM, nullptr, &now);
  return now;
}

// The 7-point Laplacian of an n^3 grid plus its diagonal: a 3D system whose
// fill makes CHOLMOD try METIS after AMD.
Eigen::SparseMatrix<double> grid_laplacian(int n) {
  auto id = [n](int i, int j, int k) { return (k * n + j) * n + i; };
  std::vector<Eigen::Triplet<double>> t;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        t.emplace_back(id(i, j, k), id(i, j, k), 7.0);
        if (i + 1 < n) t.emplace_back(id(i + 1, j, k), id(i, j, k), -1.0);
        if (j + 1 < n) t.emplace_back(id(i, j + 1, k), id(i, j, k), -1.0);
        if (k + 1 < n) t.emplace_back(id(i, j, k + 1), id(i, j, k), -1.0);
      }
  Eigen::SparseMatrix<double> A(n * n * n, n * n * n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}


}  // namespace

TEST_SUITE("solve/cholesky") {
  TEST_CASE("solves match a dense Cholesky for vectors, dense and sparse right-hand sides") {
    for (unsigned seed = 1; seed <= 4; ++seed) {
      const Eigen::SparseMatrix<double> A = test::grid_spd(3 + int(seed) % 2, seed);
      const Eigen::MatrixXd Ad(A);
      const Eigen::LLT<Eigen::MatrixXd> ref(Ad);
      const solve::Cholesky chol(A, "test matrix");
      CHECK(chol.factored());
      CHECK(chol.rows() == A.rows());
      const Eigen::VectorXd b = Eigen::VectorXd::Random(A.rows());
      const Eigen::VectorXd x = ref.solve(b);
      CHECK((solved(chol, b) - x).norm() <= 1e-10 * x.norm());
      const Eigen::MatrixXd B = Eigen::MatrixXd::Random(A.rows(), 4);
      const Eigen::MatrixXd X = ref.solve(B);
      CHECK((solved(chol, B) - X).norm() <= 1e-10 * X.norm());
      const Eigen::SparseMatrix<double> Bs = B.sparseView();
      CHECK((solved(chol, Eigen::MatrixXd(Bs)) - X).norm() <= 1e-10 * X.norm());
    }
  }

  TEST_CASE("unit forward and many-column backward halves equal the solve on supernodal and simplicial factors") {
    // n = 12: 5184 unknowns, which CHOLMOD factors supernodally; n = 3: simplicial.
    for (const int n : {12, 3}) {
      const Eigen::SparseMatrix<double> A = test::grid_spd(n, 11);
      const solve::Cholesky chol(A, "test matrix");
      CHECK(chol.supernodal() == (n == 12));
      solve::SolveWorkspace ws;
      for (const std::vector<int>& rows :
           {std::vector<int>{0}, std::vector<int>{int(A.rows()) - 1, 5, 6, 7}, std::vector<int>{9, 9, 2},
            std::vector<int>{}}) {
        Eigen::MatrixXd E = Eigen::MatrixXd::Zero(A.rows(), Eigen::Index(rows.size()));
        for (size_t j = 0; j < rows.size(); ++j) E(rows[j], Eigen::Index(j)) = 1;
        Eigen::MatrixXd Yd, Yu, X;
        chol.forward_into(E, Yd, ws);
        chol.forward_unit_into(rows, Yu, ws);
        REQUIRE(Yu.rows() == Yd.rows());
        REQUIRE(Yu.cols() == Yd.cols());
        // (BLAS and these loops sum in different orders)
        CHECK((Yu - Yd).norm() <= 1e-13 * std::max(1.0, Yd.norm()));
        chol.backward_into(Yu, X, ws);
        const Eigen::MatrixXd Xs = solved(chol, E);
        CHECK((X - Xs).norm() <= 1e-12 * std::max(1.0, Xs.norm()));
      }
      // backward on a dense block equals the vector backward, column by column
      const Eigen::MatrixXd Y = Eigen::MatrixXd::Random(A.rows(), 3);
      Eigen::MatrixXd X;
      chol.backward_into(Y, X, ws);
      for (Eigen::Index k = 0; k < 3; ++k) {
        Eigen::VectorXd x;
        chol.backward_into(Eigen::VectorXd(Y.col(k)), x, ws);
        CHECK((X.col(k) - x).norm() <= 1e-12 * x.norm());
      }
      Eigen::MatrixXd Y2;
      CHECK_THROWS_WITH_AS(chol.forward_unit_into(std::vector<int>{int(A.rows())}, Y2, ws),
                           doctest::Contains("unit column at row"), softcut::Error);
    }
  }

  TEST_CASE("forward over many unit columns equals CHOLMOD's forward solve, with a dense block on top") {
    // A grid with a dense SPD block on its last 300 unknowns (as K' on the
    // operational system's interface): supernodal, its top a dense block.
    const Eigen::SparseMatrix<double> G = test::grid_spd(10, 3);
    const Eigen::Index n = G.rows(), nd = 300;
    const Eigen::MatrixXd R = Eigen::MatrixXd::Random(nd, nd);
    Eigen::MatrixXd D = R * R.transpose() / double(nd);
    D.diagonal().array() += 1.0;
    Eigen::MatrixXd Adense = Eigen::MatrixXd(G);
    Adense.bottomRightCorner(nd, nd) += D;
    const Eigen::SparseMatrix<double> A = Adense.sparseView();
    for (const Eigen::SparseMatrix<double>& M : {A, test::grid_spd(3, 2)}) {
      const solve::Cholesky chol(M, "test matrix");
      CHECK(chol.supernodal() == (M.rows() == n));
      solve::SolveWorkspace ws;
      std::vector<int> rows;
      for (int j = 0; j < 45; ++j) rows.push_back(int((j * 7919L) % M.rows()));
      rows.push_back(int(M.rows()) - 1);  // in the dense block
      rows.push_back(rows[3]);            // twice
      for (const std::vector<int>& r : {rows, std::vector<int>{5}, std::vector<int>{}}) {
        Eigen::MatrixXd E = Eigen::MatrixXd::Zero(M.rows(), Eigen::Index(r.size()));
        for (size_t j = 0; j < r.size(); ++j) E(r[j], Eigen::Index(j)) = 1;
        Eigen::MatrixXd Yd, Yc;
        chol.forward_into(E, Yd, ws);
        chol.forward_columns_into(r, Yc, ws);
        REQUIRE(Yc.rows() == Yd.rows());
        REQUIRE(Yc.cols() == Yd.cols());
        CHECK((Yc - Yd).norm() <= 1e-13 * std::max(1.0, Yd.norm()));
        // Y Y' = E' A^-1 E: the Gram matrix a low-rank correction uses.
        const Eigen::MatrixXd X = Eigen::MatrixXd(solved(chol, E));
        CHECK((Yc.transpose() * Yc - E.transpose() * X).norm() <= 1e-12 * std::max(1.0, X.norm()));
      }
      Eigen::MatrixXd Y2;
      CHECK_THROWS_WITH_AS(chol.forward_columns_into(std::vector<int>{-1}, Y2, ws),
                           doctest::Contains("unit column at row"), softcut::Error);
    }
  }

  TEST_CASE("one-vector forward and backward equal CHOLMOD's, with the same bits on two threads") {
    // Grids with and without a dense SPD block on their last 600 unknowns
    // (a top supernode of three kSplitTop blocks), and a simplicial factor.
    const Eigen::SparseMatrix<double> G = test::grid_spd(10, 5);
    const Eigen::Index nd = 600;
    const Eigen::MatrixXd R = Eigen::MatrixXd::Random(nd, nd);
    Eigen::MatrixXd Adense = Eigen::MatrixXd(G);
    Adense.bottomRightCorner(nd, nd) += R * R.transpose() / double(nd) + Eigen::MatrixXd::Identity(nd, nd);
    const Eigen::SparseMatrix<double> A = Adense.sparseView();
    softcut::HelperThread helper;
    const std::vector<Eigen::SparseMatrix<double>> matrices{A, G, test::grid_spd(3, 4)};
    for (size_t which = 0; which < matrices.size(); ++which) {
      const Eigen::SparseMatrix<double>& M = matrices[which];
      const solve::Cholesky chol(M, "test matrix");
      solve::SolveWorkspace ws;
      const Eigen::VectorXd b = Eigen::VectorXd::Random(M.rows());
      Eigen::MatrixXd Yref;
      chol.forward_into(b, Yref, ws);
      Eigen::VectorXd y, x, xref, y2, x2;
      chol.forward_vector(b, y, ws);
      CHECK((y - Yref.col(0)).norm() <= 1e-13 * Yref.norm());
      chol.backward_vector(y, x, ws);
      chol.backward_into(Eigen::VectorXd(Yref.col(0)), xref, ws);
      CHECK((x - xref).norm() <= 1e-12 * xref.norm());
      const Eigen::VectorXd xs = solved(chol, b);
      CHECK((x - xs).norm() <= 1e-12 * xs.norm());
      // The top's halves take microseconds: on a loaded machine the caller
      // would often finish both before the helper runs, so it leaves them.
      const long before = helper.helped();
      helper.leave_to_helper(true);
      chol.forward_vector(b, y2, ws, &helper);
      chol.backward_vector(y2, x2, ws, &helper);
      helper.leave_to_helper(false);
      CHECK(y2 == y);
      CHECK(x2 == x);
      if (which == 0) CHECK(helper.helped() > before);  // the dense top's halves
      CHECK_THROWS_WITH_AS(chol.forward_vector(Eigen::VectorXd::Zero(3), y2, ws), doctest::Contains("a vector of size 3"),
                           softcut::Error);
      CHECK_THROWS_WITH_AS(chol.backward_vector(Eigen::VectorXd::Zero(3), x2, ws), doctest::Contains("a vector of size 3"),
                           softcut::Error);
    }
  }

  TEST_CASE("backward on two threads gives the bits of one, and a column the bits it has alone") {
    const Eigen::SparseMatrix<double> A = test::grid_spd(12, 7);
    const solve::Cholesky chol(A, "test matrix");
    REQUIRE(chol.supernodal());
    REQUIRE(chol.subtrees() >= 2);
    solve::SolveWorkspace ws;
    const std::vector<int> rows{3, 4, 5, 700, 701, 702, int(A.rows()) - 1};
    Eigen::MatrixXd Y, X1, X2;
    chol.forward_unit_into(rows, Y, ws);
    chol.backward_into(Y, X1, ws);
    softcut::HelperThread helper;
    helper.leave_to_helper(true);  // subtrees the caller has not started go to the helper
    chol.backward_into(Y, X2, ws, &helper);
    CHECK(X2 == X1);
    CHECK(helper.helped() > 0);
    // Independent truth: CHOLMOD's whole solve of the unit columns.
    Eigen::MatrixXd E = Eigen::MatrixXd::Zero(A.rows(), Eigen::Index(rows.size()));
    for (size_t j = 0; j < rows.size(); ++j) E(rows[j], Eigen::Index(j)) = 1;
    CHECK((X1 - solved(chol, E)).norm() <= 1e-12 * X1.norm());
    // Each column (3 at a time and the odd one) as when it is solved alone.
    for (size_t j = 0; j < rows.size(); ++j) {
      Eigen::MatrixXd y, x;
      chol.forward_unit_into(std::vector<int>{rows[j]}, y, ws);
      CHECK(y == Y.col(Eigen::Index(j)));
      chol.backward_into(y, x, ws);
      CHECK(x == X1.col(Eigen::Index(j)));
    }
  }

  TEST_CASE("a supernodal factor saved and loaded solves its unit columns bit for bit as before") {
    const Eigen::SparseMatrix<double> A = test::grid_spd(12, 4);
    const solve::Cholesky chol(A, "test matrix");
    REQUIRE(chol.supernodal());
    const std::filesystem::path file = std::filesystem::temp_directory_path() / "softcut_test_cholesky_factor.bin";
    {
      std::ofstream out(file, std::ios::binary);
      softcut::BinaryWriter w(out);
      chol.save(w);
      w.finish();
    }
    solve::Cholesky loaded;
    {
      const int fd = ::open(file.c_str(), O_RDONLY);
      REQUIRE(fd >= 0);
      softcut::BinaryReader r(fd, std::filesystem::file_size(file), file.string(), 1);
      loaded.load(r);
      r.finish();
      ::close(fd);
    }
    std::filesystem::remove(file);
    REQUIRE(loaded.supernodal());
    solve::SolveWorkspace ws;
    const std::vector<int> rows{17, 18, 19, int(A.rows()) / 2};
    Eigen::MatrixXd Y0, Y1, X0, X1;
    chol.forward_unit_into(rows, Y0, ws);
    loaded.forward_unit_into(rows, Y1, ws);
    CHECK(Y0 == Y1);
    chol.backward_into(Y0, X0, ws);
    loaded.backward_into(Y1, X1, ws);
    CHECK(X0 == X1);
  }

  TEST_CASE("only the lower triangle is read") {
    const Eigen::SparseMatrix<double> A = test::grid_spd(3, 5);
    Eigen::SparseMatrix<double> L = A.triangularView<Eigen::Lower>();
    const Eigen::VectorXd b = Eigen::VectorXd::Random(A.rows());
    CHECK((solved(solve::Cholesky(L), b) - solved(solve::Cholesky(A), b)).norm() <= 1e-14 * solved(solve::Cholesky(A), b).norm());
  }

  TEST_CASE("indefinite, non-square and mismatched inputs are errors") {
    Eigen::SparseMatrix<double> A = test::grid_spd(3, 2);
    A.coeffRef(5, 5) = -1e3;
    CHECK_THROWS_WITH_AS(solve::Cholesky(A, "K22"), doctest::Contains("K22: the stiffness matrix is singular"), Error);
    // Larger matrices take CHOLMOD's supernodal path; the check holds there too.
    Eigen::SparseMatrix<double> big = test::grid_spd(12, 3);
    big.coeffRef(300, 300) = -1e3;
    CHECK_THROWS_AS(solve::Cholesky(big, "big"), Error);
    solve::Cholesky c(test::grid_spd(3, 2));
    CHECK_THROWS_AS(c.factor(A, "K22"), Error);
    CHECK_FALSE(c.factored());  // a failed refactor leaves no stale factor behind
    CHECK_THROWS_AS(solved(c, Eigen::VectorXd(Eigen::VectorXd::Zero(A.rows()))), Error);
    CHECK_THROWS_AS(solve::Cholesky(Eigen::SparseMatrix<double>(3, 6)), Error);
    const solve::Cholesky ok(test::grid_spd(3, 2));
    CHECK_THROWS_AS(solved(ok, Eigen::VectorXd(Eigen::VectorXd::Zero(7))), Error);
    CHECK_THROWS_AS(solved(ok, Eigen::MatrixXd(Eigen::MatrixXd::Zero(7, 2))), Error);
  }

  TEST_CASE("a cached factor with a valid checksum but a broken supernode layout is refused, not read past its end") {
    const Eigen::SparseMatrix<double> A = test::grid_spd(12, 4);
    const solve::Cholesky chol(A, "test matrix");
    REQUIRE(chol.supernodal());
    const SavedSupernodal good(chol);
    const int n = int(A.rows());
    REQUIRE(good.super.size() >= 3);
    CHECK(good.load() == "");  // taken apart and written back unchanged: it loads
    // Each break keeps the checksum valid; the load checks the layout itself
    // (cholmod_check_factor let a last row equal to n, still increasing,
    // through, and never looked at maxesize, the solve's workspace).
    // A supernode with rows below its own columns.
    size_t k = 0;
    while (k + 1 < good.super.size() && good.pi[k + 1] - good.pi[k] <= good.super[k + 1] - good.super[k]) ++k;
    REQUIRE(k + 1 < good.super.size());
    const size_t below = size_t(good.pi[k] + (good.super[k + 1] - good.super[k]));  // its first row below
    std::vector<std::pair<const char*, std::function<void(SavedSupernodal&)>>> breaks = {
        {"a last row index equal to n (rows still increasing)", [&](SavedSupernodal& f) { f.s[size_t(good.pi[k + 1] - 1)] = n; }},
        {"a row index equal to n", [&](SavedSupernodal& f) { f.s[below] = n; }},
        {"a row index past n", [&](SavedSupernodal& f) { f.s[below] = n + 1000; }},
        {"rows below the diagonal not increasing", [&](SavedSupernodal& f) {
           if (good.pi[k + 1] - int(below) >= 2) std::swap(f.s[below], f.s[below + 1]);
           else f.s[below] = good.super[k + 1] - 1;  // one row: at or above the diagonal block
         }},
        {"the first supernode not starting at 0", [&](SavedSupernodal& f) { f.super[0] = 1; }},
        {"the supernodes ending before n", [&](SavedSupernodal& f) { f.super.back() = n - 1; }},
        {"a supernode's block past the values", [&](SavedSupernodal& f) { f.px.back() = int(f.x.size()) + 1; }},
        {"a supernode's own rows not its columns", [&](SavedSupernodal& f) { f.s[size_t(good.pi[k])] += 1; }},
        {"a supernode's rows past the row array, the last end still right",
         [&](SavedSupernodal& f) { f.pi[1] = int(f.s.size()) + 1000; }},
        {"a supernode's block smaller than rows x columns", [&](SavedSupernodal& f) { f.px[1] -= 1; }},
        {"maxesize, the solve's workspace, too small", [&](SavedSupernodal& f) { f.header[10] = 0; }},
        {"a permutation that repeats a row", [&](SavedSupernodal& f) { f.perm[1] = f.perm[0]; }},
        {"a permutation past n", [&](SavedSupernodal& f) { f.perm[0] = n; }},
        {"a column count past the rows below it", [&](SavedSupernodal& f) { f.colcount.back() = 2; }},
    };
    for (const auto& [what, broken] : breaks) {
      const std::string name = what;
      CAPTURE(name);
      SavedSupernodal f = good;
      broken(f);
      const std::string err = f.load();
      CHECK(err.find("crafted.bin: the saved Cholesky factor is inconsistent") == 0);
    }
  }

  TEST_CASE("a CHOLMOD factor ordered by METIS leaves SIGTERM's action as it found it") {
    // The run's stop handler (app/run_support.cpp SignalGuard); METIS traps
    // SIGTERM while it orders and put ours back with SA_RESETHAND, so a run's
    // second stop killed it (docs/hardening.md #38.11).
    struct sigaction sa {}, old{};
    sa.sa_handler = stop_handler;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGTERM, &sa, &old);
    solve::Cholesky factor;
    factor.factor(grid_laplacian(24), "grid");
    const struct sigaction now = sigterm_action();
    sigaction(SIGTERM, &old, nullptr);
    REQUIRE(factor.factored());
    const bool ours = now.sa_handler == stop_handler;
    CHECK(ours);
    CHECK((now.sa_flags & (SA_RESETHAND | SA_NODEFER)) == 0);
  }
}
