#include "hybrid/operational_solvers.hpp"

#include <algorithm>
#include <cmath>
#include <future>

#include "core/error.hpp"
#include "core/threads.hpp"
#include "hybrid/factor_correction.hpp"

namespace softcut::hybrid {

void CgSolver::prepare(const OperationalSystem& sys) {
  const int n1 = sys.interface_offset(), ni = sys.size() - n1;
  if (pre_ == CgPreconditioner::block_jacobi || ni == 0) {
    precond_ = solve::BlockJacobi(sys.K);
    if (ni > 0) precond_.add_dense(*sys.K_prime, n1);
  } else {
    precond_ = solve::BlockJacobi(SparseMatrix(sys.K.topLeftCorner(n1, n1)));
    Eigen::MatrixXd D = *sys.K_prime;
    D += Eigen::MatrixXd(sys.K.bottomRightCorner(ni, ni));
    interface_llt_.compute(D);
    if (interface_llt_.info() != Eigen::Success)
      fail("operational solve: the interface block K1II + K' is not positive definite");
  }
  precond_.finalize();
  generation_ = sys.generation;
}

SolveReport CgSolver::solve(const OperationalSystem& sys, const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  if (sys.size() == 0) {
    x.resize(0);
    return {};
  }
  if (generation_ != sys.generation) prepare(sys);
  const Eigen::Index n1 = sys.interface_offset(), ni = sys.size() - n1;
  Eigen::VectorXd head_in, head_out;
  const solve::LinearOperator interface_pre = [&](const Eigen::VectorXd& r, Eigen::VectorXd& z) {
    head_in = r.head(n1);
    head_out.resize(n1);
    precond_.apply(head_in, head_out);
    z.head(n1) = head_out;
    z.tail(ni) = interface_llt_.solve(r.tail(ni));
  };
  const bool whole = pre_ == CgPreconditioner::block_jacobi || ni == 0;
  const solve::CgResult r = solve::pcg([&](const Eigen::VectorXd& v, Eigen::VectorXd& y) { sys.apply(v, y); },
                                       whole ? precond_.as_operator() : interface_pre, b, x, opt_);
  if (!r.converged)
    fail("operational solve: conjugate gradient stopped after ", r.iterations, " iterations at relative residual ",
         r.relative_residual, " (tolerance ", opt_.tolerance, "); the operational mesh may hold slivers or a "
         "part without fixed nodes; raise the iteration limit or use the cholmod backend");
  return {r.iterations, r.relative_residual};
}

struct CholmodSolver::Refactor {
  // OpenBLAS on one thread from the launch to the adoption (or the solver's
  // end): the factorization takes one core and the frames the other. Opened
  // and closed by the frame thread at points counted in cuts and solves, so
  // every BLAS call of the run sees the same thread count whatever the
  // timing. Declared first: closed after the thread has finished.
  SingleThreadedBlas one_blas_thread;
  OperationalSystem sys;
  solve::Cholesky factor;
  std::future<void> done;  // its destructor waits for the thread
};

CholmodSolver::CholmodSolver(bool allow_dense, bool allow_correction, double correction_budget)
    : allow_dense_(allow_dense), allow_correction_(allow_correction), correction_budget_(correction_budget),
      correction_(std::make_unique<FactorCorrection>()) {}

CholmodSolver::~CholmodSolver() = default;

void CholmodSolver::share_helper(std::shared_ptr<HelperThread> helper) {
  helper_ = std::move(helper);
  correction_->share_helper(helper_.get());
}

void CholmodSolver::refactor(const OperationalSystem& sys) {
  // Small systems: a dense LL' factor and the inverse it gives, so a solve
  // is one symmetric product reading half the matrix once (a triangular
  // solve pair reads it twice), refined through the factor when its
  // residual is above 1e-12 (ill-conditioned systems). Measured on the upper
  // leg's 321 unknowns: operational stage 14 -> 11 us a frame; CHOLMOD's
  // supernodal solve took 12.5 us. Chosen by size, not by timing, so a run's
  // results never depend on the machine's load. Only one of the two factors
  // is made.
  pending_.reset();
  corrected_ = false;
  correcting_blas_.reset();
  correction_->clear();
  correction_flops_ = 0;
  const SparseMatrix A = sys.assembled();
  dense_.reset();
  ++refactors_;
  if (allow_dense_ && sys.size() <= kDenseMax) {
    dense_ = std::make_unique<Eigen::LLT<Eigen::MatrixXd>>(Eigen::MatrixXd(A));
    if (dense_->info() != Eigen::Success) {
      dense_.reset();
      fail("operational system (K + K'): the stiffness matrix is singular or not positive definite; every "
           "connected part of the body needs fixed nodes");
    }
    dense_inverse_ = dense_->solve(Eigen::MatrixXd::Identity(A.rows(), A.cols()));
  } else {
    factor_.factor(A, "operational system (K + K')");
    base_ = sys;
  }
}

bool CholmodSolver::correct(const OperationalSystem& sys) {
  if (!dense_ && factor_.factored() && sys.generation == base_.generation) {  // the factor's own system
    corrected_ = false;
    correcting_blas_.reset();
    return true;
  }
  // Budget: all corrections against one factor together cost at most its
  // factorization's flops (times correction_budget_), and the changed DOFs stay few enough that a
  // frame's two n x k products cost about what its solve does.
  const double budget = correction_budget_ * factor_.factor_flops() - correction_flops_;
  const int max_rank = std::max(300, int(2 * factor_.factor_nonzeros() / std::max(1, base_.size())));
  double spent = 0;
  if (!allow_correction_ || dense_ || !factor_.factored() || budget <= 0 ||
      !correction_->prepare(base_, factor_, sys, max_rank, budget, ws_, &spent))
    return false;
  corrected_ = true;
  if (helper_ && !correcting_blas_) correcting_blas_.emplace();
  correction_flops_ += spent;
  return true;
}

void CholmodSolver::adopt_pending() {
  std::unique_ptr<Refactor> r = std::move(pending_);
  r->done.get();  // rethrows the factorization's error
  factor_ = std::move(r->factor);
  base_ = std::move(r->sys);
  correction_->clear();
  correction_flops_ = 0;
  corrected_ = false;
  correcting_blas_.reset();
  ++refactors_;
  ++adopted_;
}

void CholmodSolver::launch_refactor(const OperationalSystem& sys) {
  auto r = std::make_unique<Refactor>();
  r->sys = sys;
  r->done = std::async(std::launch::async, [p = r.get()] {
    p->factor.factor(p->sys.assembled(), "operational system (K + K')");
  });
  pending_ = std::move(r);  // only once the thread runs
  solves_since_launch_ = 0;
}

// The factor made on the second thread, for `sys`: a corrected system then
// solves against it. Its failure (a system that is not positive definite)
// is reported by a refactor of `sys` itself, naming this frame's system.
void CholmodSolver::take_pending(const OperationalSystem& sys) {
  try {
    adopt_pending();
  } catch (const Error&) {
    refactor(sys);
    return;
  }
  if (!correct(sys)) refactor(sys);
}

// x = A^-1 b with the kept inverse. A frame's b is mostly zero (loads on a
// few nodes, P' on the interface), so only the columns of its nonzero runs
// are read, in two fixed row halves (the second on the run's helper thread);
// a b nonzero on more than 3/4 of its entries takes the symmetric product,
// which reads one triangle at about 1.5x the time per entry. The choice
// depends on b alone, never on threads: same bits either way.
void CholmodSolver::dense_product(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  const Eigen::Index n = b.size();
  runs_.clear();
  Eigen::Index nonzero = 0;
  for (Eigen::Index i = 0; i < n;) {
    if (b[i] == 0) {
      ++i;
      continue;
    }
    const Eigen::Index start = i;
    while (i < n && b[i] != 0) ++i;
    runs_.emplace_back(start, i - start);
    nonzero += i - start;
  }
  if (4 * nonzero > 3 * n || n < 64) {
    x.noalias() = dense_inverse_.selfadjointView<Eigen::Lower>() * b;
    return;
  }
  x.resize(n);
  row_halves(helper_.get(), n, [&](Eigen::Index r0, Eigen::Index rows) {
    auto out = x.segment(r0, rows);
    out.setZero();
    for (const auto& [start, len] : runs_)
      out.noalias() += dense_inverse_.block(r0, start, rows, len) * b.segment(start, len);
  });
}

void OperationalSolver::precondition(const OperationalSystem& sys, const Eigen::VectorXd& r, Eigen::VectorXd& z) {
  if (node_blocks_generation_ != sys.generation) {
    node_blocks_ = solve::BlockJacobi(sys.K);
    const int n1 = sys.interface_offset();
    if (sys.size() > n1) node_blocks_.add_dense(*sys.K_prime, n1);
    node_blocks_.finalize();
    node_blocks_generation_ = sys.generation;
  }
  z.resize(r.size());
  node_blocks_.apply(r, z);
}

void CholmodSolver::precondition(const OperationalSystem& sys, const Eigen::VectorXd& r, Eigen::VectorXd& z) {
  if (sys.size() == 0) {
    z.resize(0);
    return;
  }
  prepare(sys);
  if (corrected_) correction_->solve(factor_, r, z, ws_);
  else if (dense_) dense_product(r, z);
  else factor_solve(r, z);
}

// x = A^-1 b through the kept factor. A supernodal factor is solved
// supernode by supernode (solve::Cholesky::forward_vector), its dense
// interface block in row halves on the helper if there is one; chosen by
// the factor, never by the helper, so the bits do not depend on the
// threads. Against CHOLMOD's solve (cholmod_solve2), on one thread, in
// bench nonlinear's box_111132 (3,591 unknowns, 1,557 on the interface,
// 2.2 M factor entries): a solve 1.9 -> 1.4 ms; its corotational frames
// take 15-28 (85 -> 73 ms).
void CholmodSolver::factor_solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  if (!factor_.supernodal()) {
    factor_.solve_into(b, x, ws_);
    return;
  }
  factor_.forward_vector(b, y_, ws_, helper_.get());
  factor_.backward_vector(y_, x, ws_, helper_.get());
}

void CholmodSolver::prepare(const OperationalSystem& sys) {
  if (generation_ != sys.generation) {
    // A changed system (a cut): the kept factor with a low-rank correction
    // while that is cheaper than a refactor; then the factor made on the
    // second thread, else a refactor here. Until this succeeds the solver
    // holds no prepared system (an error leaves it to prepare again).
    generation_ = -1;
    corrected_ = false;
    if (correct(sys)) {
      if (corrected_ && !pending_ && correction_flops_ > 0.75 * correction_budget_ * factor_.factor_flops())
        launch_refactor(sys);
    } else if (pending_) {
      take_pending(sys);
    } else {
      refactor(sys);
    }
    generation_ = sys.generation;
  } else if (pending_ && corrected_ && ++solves_since_launch_ >= kAdoptAfterSolves) {
    // Cutting has paused: the corrected solves cost more than the factor
    // made meanwhile would (counted in solves, never in time).
    take_pending(sys);
  }
}

SolveReport CholmodSolver::solve(const OperationalSystem& sys, const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  if (sys.size() == 0) {
    x.resize(0);
    return {};
  }
  prepare(sys);
  const double bn = b.norm();
  if (bn == 0) {  // no load: no displacement (and no residual to divide by)
    x.setZero(sys.size());
    return {0, 0.0, corrected_ ? correction_->rank() : 0};
  }
  auto residual = [&] {
    // Through K + K' (one triangle of K' read): half the memory traffic of
    // the assembled matrix.
    sys.apply(x, r_);
    r_ -= b;
    return r_.norm() / bn;
  };
  if (!corrected_) {
    if (dense_) {
      dense_product(b, x);
      SolveReport rep{0, residual(), 0};
      if (rep.relative_residual > 1e-12) {
        x -= dense_->solve(r_);
        rep.relative_residual = residual();
        rep.iterations = 1;
      }
      return rep;
    }
    factor_solve(b, x);
    return {0, residual(), 0};
  }
  // Corrected: refined while the residual is above 1e-12 (an ill-conditioned
  // capacitance matrix), at most twice; still above 1e-10: refactored.
  correction_->solve(factor_, b, x, ws_);
  SolveReport rep{0, residual(), correction_->rank()};
  Eigen::VectorXd dx;
  while (rep.relative_residual > 1e-12 && rep.iterations < 2) {
    correction_->solve(factor_, Eigen::VectorXd(-r_), dx, ws_);
    x += dx;
    ++rep.iterations;
    rep.relative_residual = residual();
  }
  if (rep.relative_residual > 1e-10 || !std::isfinite(rep.relative_residual)) {
    ++fallbacks_;
    if (pending_ && pending_->sys.generation == sys.generation) take_pending(sys);  // made for this very system
    else refactor(sys);
    if (corrected_) correction_->solve(factor_, b, x, ws_);
    else if (dense_) x = dense_->solve(b);
    else factor_solve(b, x);
    return {0, residual(), corrected_ ? correction_->rank() : 0};
  }
  return rep;
}

}  // namespace softcut::hybrid
