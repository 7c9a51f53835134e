// solve/newton on problems whose answers are known: a linear one (one step,
// one CG iteration: P is the tangent), a stiffening one checked against its
// own equations at a tight tolerance with quadratic convergence, one whose
// exact tangent is indefinite on the way (the projected fallback), one
// that cannot converge in the steps it is given (a clear error), and loads
// over frames (the predicted start: a ramp, a ramp that stops, a fallback).
#include "solve/newton.hpp"

#include <doctest/doctest.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include "core/error.hpp"
#include "test_support.hpp"

using namespace softcut;

namespace {

// F(x) = A x + c g(x) componentwise, P = A (SPD, its factor the preconditioner).
struct Problem {
  Eigen::MatrixXd A;
  Eigen::LLT<Eigen::MatrixXd> llt;
  Eigen::VectorXd b;
  double c = 0;
  int kind = 0;  // 0: g = x^3 (stiffening); 1: g = -sin(x) (softening: T indefinite where cos x > lambda_min)
  Eigen::VectorXd tangent;  // diag(T - P) at the last residual()
  int residual_calls = 0, projected_calls = 0;

  explicit Problem(int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> g(0, 1);
    Eigen::MatrixXd B(n, n);
    for (int i = 0; i < n * n; ++i) B(i) = g(rng);
    A = B * B.transpose() / n + 0.2 * Eigen::MatrixXd::Identity(n, n);
    llt.compute(A);
    b.resize(n);
    for (int i = 0; i < n; ++i) b(i) = g(rng);
  }
  Eigen::VectorXd F(const Eigen::VectorXd& x) const {
    return A * x + c * (kind == 0 ? Eigen::VectorXd(x.array().cube()) : Eigen::VectorXd(-x.array().sin()));
  }
  solve::NewtonProblem problem() {
    solve::NewtonProblem p;
    p.residual = [this](const Eigen::VectorXd& x, Eigen::VectorXd& r) {
      ++residual_calls;
      r = b - F(x);
      tangent = c * (kind == 0 ? Eigen::VectorXd(3 * x.array().square()) : Eigen::VectorXd(-x.array().cos()));
      const double g = kind == 0 ? 0.25 * x.array().pow(4).sum() : x.array().cos().sum();
      return 0.5 * x.dot(A * x) + c * g - b.dot(x);
    };
    p.project = [this] { ++projected_calls, tangent = tangent.cwiseMax(0.0); };
    p.tangent_difference = [this](const Eigen::VectorXd& d, Eigen::VectorXd& y) { y = tangent.cwiseProduct(d); };
    p.precondition = [this](const Eigen::VectorXd& r, Eigen::VectorXd& z) { z = llt.solve(r); };
    p.scale = [this](const Eigen::VectorXd& x) { return b.norm() + F(x).norm(); };
    return p;
  }
};

}  // namespace

TEST_SUITE("solve/newton") {
  TEST_CASE("a linear problem: one step, one CG iteration, the direct solution") {
    Problem pr(30, 1);
    Eigen::VectorXd x = Eigen::VectorXd::Zero(30);
    const solve::NewtonReport rep = solve::newton(pr.problem(), x);
    CHECK(rep.iterations == 1);
    CHECK(rep.cg_iterations == 1);
    CHECK((x - pr.llt.solve(pr.b)).norm() <= 1e-12 * x.norm());
  }

  TEST_CASE("a stiffening problem converges to its equations at 1e-12, quadratically at the end") {
    for (unsigned seed = 1; seed <= 5; ++seed) {
      Problem pr(40, seed);
      pr.c = 2.0;
      pr.b *= 5;  // far from linear: |x| ~ 1, the cubic term dominates
      Eigen::VectorXd x = Eigen::VectorXd::Zero(40);
      std::vector<double> history;
      solve::NewtonProblem p = pr.problem();
      auto plain = p.residual;
      p.residual = [&](const Eigen::VectorXd& at, Eigen::VectorXd& r) {
        const double e = plain(at, r);
        history.push_back(r.norm());
        return e;
      };
      solve::NewtonOptions opt;
      opt.tolerance = 1e-12;
      const solve::NewtonReport rep = solve::newton(p, x, opt);
      CAPTURE(seed);
      CHECK(rep.relative_residual <= 1e-12);
      CHECK((pr.b - pr.F(x)).norm() <= 1e-12 * (pr.b.norm() + pr.F(x).norm()));
      CHECK(rep.iterations >= 3);
      CHECK(rep.projected_steps == 0);
      // Quadratic at the end: the step before the last took the residual
      // from about e to about e^2 (relative; a power of 1.5 leaves room).
      // The last step's linear solve stops at a tenth of the tolerance (no
      // digits past what convergence needs), so it lands there, not at e^2.
      const double s = pr.b.norm();
      std::vector<double> rel;
      for (double h : history)
        if (h / s > 1e-14) rel.push_back(h / s);
      REQUIRE(rel.size() >= 3);
      CHECK(rel[rel.size() - 2] <= 10 * std::pow(rel[rel.size() - 3], 1.5));
      CHECK(rel[rel.size() - 2] > opt.tolerance);
    }
  }

  TEST_CASE("a ramped load: the secant start through the last two frames saves Newton steps, same answers") {
    // The stiffening problem loaded by b k / 10 over ten frames, each solve
    // warm-started from the frame before, with and without SecantStart.
    Problem pr(40, 3);
    pr.c = 2.0;
    const Eigen::VectorXd full = 5 * pr.b;
    Eigen::VectorXd plain = Eigen::VectorXd::Zero(40), secant = plain;
    solve::SecantStart predictor;
    int plain_steps = 0, secant_steps = 0;
    solve::NewtonOptions opt;
    opt.tolerance = 1e-12;
    for (int k = 1; k <= 10; ++k) {
      pr.b = full * (k / 10.0);
      plain_steps += solve::newton(pr.problem(), plain, opt).iterations;
      const Eigen::VectorXd from = secant;
      secant_steps += solve::newton(pr.problem(), secant, opt, "ramp", predictor.predict(secant)).iterations;
      predictor.record(from, secant);
      CAPTURE(k);
      CHECK((pr.b - pr.F(secant)).norm() <= 1e-12 * (pr.b.norm() + pr.F(secant).norm()));
      CHECK((secant - plain).norm() <= 1e-10 * plain.norm());
      if (k >= 3) CHECK(predictor.theta() > 0.5);  // a ramp continues: nearly the plain secant
    }
    CAPTURE(plain_steps);
    CHECK(secant_steps <= plain_steps - 5);
  }

  TEST_CASE("the predicted start learns that a load stopped, and follows it again") {
    // Ramped over four frames, then held: the secant would overshoot by one
    // frame's increment; theta falls to 0 and the held frames take no step.
    Problem pr(40, 4);
    pr.c = 2.0;
    const Eigen::VectorXd full = 2 * pr.b;
    Eigen::VectorXd x = Eigen::VectorXd::Zero(40);
    solve::SecantStart predictor;
    std::vector<int> steps;
    for (int k = 1; k <= 8; ++k) {
      pr.b = full * (std::min(k, 4) / 4.0);
      const Eigen::VectorXd from = x;
      steps.push_back(solve::newton(pr.problem(), x, {}, "hold", predictor.predict(x)).iterations);
      predictor.record(from, x);
    }
    CHECK(predictor.theta() == 0.0);
    CHECK(steps[6] == 0);  // converged where it started: no overshoot
    CHECK(steps[7] == 0);
    predictor.clear();
    CHECK(predictor.predict(x) == nullptr);
  }

  TEST_CASE("a predicted start Newton cannot converge from falls back to the warm start, its work counted") {
    Problem pr(40, 5);
    pr.c = 2.0;
    solve::NewtonOptions opt;
    opt.max_iterations = 12;
    Eigen::VectorXd x = Eigen::VectorXd::Zero(40), alone = x;
    const int direct = solve::newton(pr.problem(), alone, opt).iterations;
    // 1e4 out: the cubic term needs more than 12 steps back.
    const Eigen::VectorXd start = Eigen::VectorXd::Constant(40, 1e4);
    const solve::NewtonReport rep = solve::newton(pr.problem(), x, opt, "fallback", &start);
    CHECK((x - alone).norm() <= 1e-9 * alone.norm());
    CHECK(rep.iterations == direct + opt.max_iterations);
    // Failing from both is the error of the warm start's attempt.
    opt.max_iterations = 2;
    x.setZero();
    CHECK_THROWS_WITH_AS(solve::newton(pr.problem(), x, opt, "fallback", &start),
                         doctest::Contains("fallback: Newton's method did not converge in 2 steps"), Error);
  }

  TEST_CASE("an indefinite exact tangent on the way: the projected tangent takes over and converges") {
    Problem pr(20, 7);
    pr.kind = 1;
    pr.c = 1.0;  // A's smallest eigenvalue is about 0.2 < 1 = |d(-sin)/dx| at 0
    pr.b *= 0.05;
    Eigen::VectorXd x = Eigen::VectorXd::Zero(20);
    const solve::NewtonReport rep = solve::newton(pr.problem(), x);
    CHECK(rep.projected_steps >= 1);
    CHECK(pr.projected_calls >= 1);
    CHECK(rep.relative_residual <= 1e-10);
    CHECK((pr.b - pr.F(x)).norm() <= 1e-9 * pr.b.norm());
  }

  TEST_CASE("block Jacobi in place of the factor (apply_base set): the same answer") {
    Problem pr(40, 11);
    pr.c = 2.0;
    pr.b *= 5;
    Eigen::VectorXd x_factor = Eigen::VectorXd::Zero(40), x_jacobi = x_factor;
    const solve::NewtonReport with_factor = solve::newton(pr.problem(), x_factor);
    solve::NewtonProblem p = pr.problem();
    const Eigen::VectorXd inv_diag = pr.A.diagonal().cwiseInverse();
    p.precondition = [&](const Eigen::VectorXd& r, Eigen::VectorXd& z) { z = inv_diag.cwiseProduct(r); };
    p.apply_base = [&](const Eigen::VectorXd& v, Eigen::VectorXd& y) { y += pr.A * v; };
    const solve::NewtonReport with_jacobi = solve::newton(p, x_jacobi);
    CHECK(with_jacobi.relative_residual <= 1e-10);
    CHECK((x_jacobi - x_factor).norm() <= 1e-9 * x_factor.norm());
    CHECK(with_factor.relative_residual <= 1e-10);
  }

  TEST_CASE("a residual with a rounding floor: converged at the floor below 1e-8, an error above") {
    // r carries a deterministic noise of `floor` x its scale that changes
    // with every x (as rounding does): Newton cannot get below it.
    for (const double floor : {3e-10, 3e-9, 1e-6}) {
      CAPTURE(floor);
      Problem pr(30, 5);
      pr.c = 2.0;
      pr.b *= 5;
      solve::NewtonProblem p = pr.problem();
      auto plain = p.residual;
      p.residual = [&](const Eigen::VectorXd& at, Eigen::VectorXd& r) {
        const double e = plain(at, r);
        std::seed_seq seq{std::hash<double>{}(at.sum()), std::hash<double>{}(at(0))};
        std::mt19937 rng(seq);
        std::uniform_real_distribution<double> unit(-1, 1);
        const double size = floor * (pr.b.norm() + pr.F(at).norm()) / std::sqrt(double(at.size()));
        for (Eigen::Index i = 0; i < r.size(); ++i) r(i) += size * unit(rng);
        return e;
      };
      Eigen::VectorXd x = Eigen::VectorXd::Zero(30);
      if (floor < 1e-8) {
        const solve::NewtonReport rep = solve::newton(p, x);
        CHECK(rep.at_floor);
        CHECK(rep.relative_residual > 1e-10);
        CHECK(rep.relative_residual <= 1e-8);
        CHECK(rep.iterations < 20);  // stops when the floor is reached, not at the step limit
        CHECK((pr.b - pr.F(x)).norm() <= 1e-8 * (pr.b.norm() + pr.F(x).norm()));
      } else {
        CHECK(test::contains(test::error_of([&] { solve::newton(p, x, {}, "frame 9"); }), "frame 9: Newton's"));
      }
    }
  }

  TEST_CASE("not converging is an error naming the solve, never a result") {
    Problem pr(20, 3);
    pr.c = 5.0;
    pr.b *= 50;
    Eigen::VectorXd x = Eigen::VectorXd::Zero(20);
    solve::NewtonOptions opt;
    opt.max_iterations = 2;
    CHECK(test::contains(test::error_of([&] { solve::newton(pr.problem(), x, opt, "frame 3"); }),
                         "frame 3: Newton's method did not converge in 2 steps"));
    solve::NewtonProblem p = pr.problem();
    p.residual = [](const Eigen::VectorXd& at, Eigen::VectorXd& r) {
      r = at;
      r(0) = NAN;
      return 0.0;
    };
    CHECK(test::contains(test::error_of([&] { solve::newton(p, x); }), "the residual is not finite"));
  }
}
