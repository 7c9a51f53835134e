#include "hybrid/operational_system.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <future>

#include "core/error.hpp"
#include "fem/assembly.hpp"
#include "hybrid/factor_correction.hpp"

namespace softcut::hybrid {

namespace {
std::atomic<long> next_generation{1};
}

void OperationalSystem::apply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
  const int nb = size() / 3;
  if (int(block_row_start.size()) == nb + 1) {
    y.resize(size());
    for (int i = 0; i < nb; ++i) {
      Eigen::Vector3d acc = Eigen::Vector3d::Zero();
      for (int k = block_row_start[size_t(i)]; k < block_row_start[size_t(i) + 1]; ++k)
        acc.noalias() += blocks[size_t(k)] * x.segment<3>(3 * Eigen::Index(block_col[size_t(k)]));
      y.segment<3>(3 * Eigen::Index(i)) = acc;
    }
  } else {
    y.noalias() = K * x;
  }
  if (num_interface > 0) {
    const Eigen::Index off = interface_offset(), n = 3 * Eigen::Index(num_interface);
    // K' is symmetric: reading one triangle halves the memory traffic of the
    // dense product, which dominates a CG iteration for large interfaces.
    y.segment(off, n).noalias() += K_prime->selfadjointView<Eigen::Lower>() * x.segment(off, n);
  }
}

SparseMatrix OperationalSystem::assembled() const {
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(size_t(K.nonZeros()) + (num_interface > 0 ? size_t(K_prime->size()) : 0));
  for (int col = 0; col < K.outerSize(); ++col)
    for (SparseMatrix::InnerIterator it(K, col); it; ++it) trip.emplace_back(int(it.row()), col, it.value());
  const int off = interface_offset();
  for (Eigen::Index j = 0; num_interface > 0 && j < K_prime->cols(); ++j)
    for (Eigen::Index i = 0; i < K_prime->rows(); ++i) trip.emplace_back(off + int(i), off + int(j), (*K_prime)(i, j));
  SparseMatrix A(size(), size());
  A.setFromTriplets(trip.begin(), trip.end());
  return A;
}

Eigen::VectorXd OperationalSystem::rhs(const Eigen::MatrixX3d& forces, const Eigen::VectorXd& P_prime) const {
  Eigen::VectorXd b(size());
  for (size_t k = 0; k < nodes.size(); ++k) b.segment<3>(3 * Eigen::Index(k)) = forces.row(nodes[k]).transpose();
  if (num_interface > 0) b.tail(3 * Eigen::Index(num_interface)) -= P_prime;
  return b;
}

OperationalSystem build_operational_system(const mesh::TetMesh& m, const std::vector<fem::Material>& tet_material,
                                           const std::vector<int>& operational_tets,
                                           const std::vector<int>& interface_nodes,
                                           const std::vector<char>& node_fixed,
                                           const std::vector<char>& node_nonoperational,
                                           std::shared_ptr<const Eigen::MatrixXd> K_prime) {
  const int nn = m.num_nodes();
  const Eigen::Index ni = 3 * Eigen::Index(interface_nodes.size());
  if (!K_prime || K_prime->rows() != ni || K_prime->cols() != ni)
    fail("operational system: K' must be ", ni, " x ", ni, " for ", interface_nodes.size(), " interface nodes");
  auto flag = [](const std::vector<char>& v, int i) { return size_t(i) < v.size() && v[size_t(i)]; };
  std::vector<char> is_interface(size_t(nn), 0), touched(size_t(nn), 0);
  for (int v : interface_nodes) {
    if (v < 0 || v >= nn) fail("operational system: interface node ", v, " is not a node of the mesh");
    is_interface[size_t(v)] = 1;
  }
  for (int t : operational_tets) {
    if (t < 0 || t >= m.num_tets()) fail("operational system: tet ", t, " is not a tet of the mesh");
    for (int k = 0; k < 4; ++k) {
      const int v = m.tets(t, k);
      if (flag(node_nonoperational, v))
        fail("operational system: operational tet ", t, " uses node ", v, ", a nonoperational node that is "
             "not an interface node; cutting and remeshing may touch only operational tets and must not "
             "reach past the interface");
      touched[size_t(v)] = 1;
    }
  }
  OperationalSystem sys;
  for (int v = 0; v < nn; ++v)
    if (touched[size_t(v)] && !is_interface[size_t(v)] && !flag(node_fixed, v)) sys.nodes.push_back(v);
  sys.num_operational = int(sys.nodes.size());
  sys.nodes.insert(sys.nodes.end(), interface_nodes.begin(), interface_nodes.end());
  sys.num_interface = int(interface_nodes.size());
  sys.node_index = node_positions(sys.nodes, nn);
  if (operational_tets.empty())
    sys.K = SparseMatrix(sys.size(), sys.size());
  else
    sys.K = node_block(fem::assemble_stiffness(m, tet_material, operational_tets), sys.nodes, sys.nodes);
  sys.K_prime = std::move(K_prime);
  sys.generation = next_generation++;
  // Node blocks of K, row by row. K's column c holds its row c (symmetric),
  // so the blocks of node column j, transposed, are node row j's.
  const int nb = int(sys.nodes.size());
  std::vector<int> slot(static_cast<size_t>(nb), -1);
  std::vector<int> rows_seen;
  sys.block_row_start.assign(1, 0);
  for (int j = 0; j < nb; ++j) {
    for (int b = 0; b < 3; ++b)
      for (SparseMatrix::InnerIterator it(sys.K, 3 * j + b); it; ++it) {
        const int i = int(it.row()) / 3;
        if (slot[size_t(i)] < 0) {
          slot[size_t(i)] = int(sys.blocks.size());
          sys.blocks.push_back(Eigen::Matrix3d::Zero());
          sys.block_col.push_back(i);
          rows_seen.push_back(i);
        }
        sys.blocks[size_t(slot[size_t(i)])](b, int(it.row()) % 3) = it.value();  // K(i, j) block = K(j, i)^T
      }
    for (int i : rows_seen) slot[size_t(i)] = -1;
    rows_seen.clear();
    sys.block_row_start.push_back(int(sys.blocks.size()));
  }
  return sys;
}

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
  OperationalSystem sys;
  solve::Cholesky factor;
  std::future<void> done;  // its destructor waits for the thread
};

CholmodSolver::CholmodSolver(bool allow_dense, bool allow_correction, double correction_budget)
    : allow_dense_(allow_dense), allow_correction_(allow_correction), correction_budget_(correction_budget),
      correction_(std::make_unique<FactorCorrection>()) {}

CholmodSolver::~CholmodSolver() = default;

void CholmodSolver::refactor(const OperationalSystem& sys) {
  // Small systems: a dense LL' solve has less overhead per call than
  // CHOLMOD's supernodal one (measured, 321 unknowns: 8.5 against 12.5 us).
  // Chosen by size, not by timing, so a run's results never depend on the
  // machine's load. Only one of the two factors is made.
  pending_.reset();
  corrected_ = false;
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
  } else {
    factor_.factor(A, "operational system (K + K')");
    base_ = sys;
  }
}

bool CholmodSolver::correct(const OperationalSystem& sys) {
  if (!dense_ && factor_.factored() && sys.generation == base_.generation) {  // the factor's own system
    corrected_ = false;
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
  ++refactors_;
  ++adopted_;
}

SolveReport CholmodSolver::solve(const OperationalSystem& sys, const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  if (sys.size() == 0) {
    x.resize(0);
    return {};
  }
  if (generation_ != sys.generation) {
    // A changed system (a cut): the kept factor with a low-rank correction
    // while that is cheaper than a refactor; then the factor made on the
    // second thread, else a refactor here.
    bool ok = correct(sys);
    if (!ok && pending_) {
      adopt_pending();
      ok = correct(sys);
    }
    if (!ok) refactor(sys);
    else if (corrected_ && !pending_ && correction_flops_ > 0.75 * correction_budget_ * factor_.factor_flops()) {
      pending_ = std::make_unique<Refactor>();
      pending_->sys = sys;
      pending_->done = std::async(std::launch::async, [r = pending_.get()] {
        r->factor.factor(r->sys.assembled(), "operational system (K + K')");
      });
    }
    generation_ = sys.generation;
  }
  const double bn = b.norm();
  auto residual = [&] {
    // Through K + K' (one triangle of K' read): half the memory traffic of
    // the assembled matrix.
    sys.apply(x, r_);
    r_ -= b;
    return bn == 0 ? 0.0 : r_.norm() / bn;
  };
  if (!corrected_) {
    if (dense_) x = dense_->solve(b);
    else factor_.solve_into(b, x, ws_);
    return {0, bn == 0 ? 0.0 : residual(), 0};
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
    refactor(sys);
    if (dense_) x = dense_->solve(b);
    else factor_.solve_into(b, x, ws_);
    return {0, residual(), 0};
  }
  return rep;
}

}  // namespace softcut::hybrid
