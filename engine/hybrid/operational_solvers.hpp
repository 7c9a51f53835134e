#pragma once
// Solvers of the operational system (operational_system.hpp) behind one
// interface: CPU CG, CHOLMOD with a kept factor (and, for cut systems, a
// low-rank correction: factor_correction.hpp); the GPU CG lives in gpu/.
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/helper_thread.hpp"
#include "core/threads.hpp"
#include "hybrid/operational_system.hpp"
#include "solve/cg.hpp"
#include "solve/cholesky.hpp"

namespace softcut::hybrid {

class FactorCorrection;

struct SolveReport {
  int iterations = 0;            // CG iterations (0 for direct solves); refinement steps of a corrected solve
  double relative_residual = 0;  // ||b - A x|| / ||b||
  int correction_rank = 0;       // CHOLMOD: DOFs changed since the kept factor (0: the factor is this system's)
};

// Pluggable solver for the operational system (CPU CG, CHOLMOD, GPU CG).
// solve() gets the previous solution in x (warm start) and leaves the new one.
// Implementations cache per-system data keyed by OperationalSystem::generation.
class OperationalSolver {
 public:
  virtual ~OperationalSolver() = default;
  virtual std::string name() const = 0;
  virtual SolveReport solve(const OperationalSystem& sys, const Eigen::VectorXd& b, Eigen::VectorXd& x) = 0;
  // The preconditioner of a nonlinear frame (nonlinear_solve.hpp), whose
  // Newton iteration checks the true residual: z = A^-1 r through the kept
  // factor where keeps_factor(), else z = M^-1 r with M the 3x3 node blocks
  // of A (block Jacobi, made once per system), what the CG backends'
  // Newton steps use: more PCG iterations, the same answer.
  virtual void precondition(const OperationalSystem& sys, const Eigen::VectorXd& r, Eigen::VectorXd& z);
  virtual bool keeps_factor() const { return false; }
  // The run's second thread for dense products (hybrid::State::helper);
  // solvers without such products ignore it.
  virtual void share_helper(std::shared_ptr<HelperThread> helper) { (void)helper; }

 private:
  solve::BlockJacobi node_blocks_;  // precondition() without a factor
  long node_blocks_generation_ = -1;
};

// Preconditioned CG, warm-started. Preconditioners:
//   block_jacobi     3x3 node blocks of K + K' (what a GPU kernel applies)
//   interface_block  3x3 node blocks on set 1, and the whole interface block
//                    K1II + K' (dense, Cholesky once per system) on I: fewer
//                    iterations (ligament: 125 -> 68), but each costs two dense
//                    triangular solves, so on the CPU it is not faster.
// The slow part is physical: K' carries the soft global modes of the whole
// body into the operational system (Jacobi-scaled condition ~2e3 for the
// ligament), which no local preconditioner removes.
// Throws when CG does not reach the tolerance.
enum class CgPreconditioner { block_jacobi, interface_block };

class CgSolver : public OperationalSolver {
 public:
  explicit CgSolver(solve::CgOptions opt = {}, CgPreconditioner pre = CgPreconditioner::block_jacobi)
      : opt_(opt), pre_(pre) {}
  std::string name() const override { return "cg"; }
  SolveReport solve(const OperationalSystem& sys, const Eigen::VectorXd& b, Eigen::VectorXd& x) override;
  solve::CgOptions& options() { return opt_; }

 private:
  void prepare(const OperationalSystem& sys);
  solve::CgOptions opt_;
  CgPreconditioner pre_;
  solve::BlockJacobi precond_;     // whole system (block_jacobi) or set 1 only (interface_block)
  Eigen::LLT<Eigen::MatrixXd> interface_llt_;  // (3|I| x 3|I|) K1II + K'
  long generation_ = -1;
};

// CHOLMOD factor of K + K', kept between frames; systems of up to kDenseMax
// unknowns are solved with a dense LL' factor instead (fixed costs dominate
// CHOLMOD's solve below a few hundred unknowns). When a cut changes the
// system, the kept factor solves the new one through a low-rank correction
// (factor_correction.hpp) as long as the corrections since the factor cost
// fewer flops than a refactor and stay small enough to keep frames cheap.
// Once they have cost three quarters of a refactor, the current system is refactored on
// a second thread, and that factor is taken when the budget runs out (waiting
// for it if it is not done): the points where the factor changes depend on
// flop counts only, so a run's results never depend on timing. Every solve's
// residual is checked; a corrected solve above 1e-12 is refined (at most
// twice) and else refactored.
class CholmodSolver : public OperationalSolver {
 public:
  // allow_dense = false: always CHOLMOD's solve (tests compare the two).
  // allow_correction = false: refactor after every change (benches compare).
  // correction_budget: corrections against one factor may cost this many
  // times its factorization's flops (tests raise it to correct small systems).
  explicit CholmodSolver(bool allow_dense = true, bool allow_correction = true, double correction_budget = 1.0);
  ~CholmodSolver() override;
  std::string name() const override { return "cholmod"; }
  SolveReport solve(const OperationalSystem& sys, const Eigen::VectorXd& b, Eigen::VectorXd& x) override;
  void precondition(const OperationalSystem& sys, const Eigen::VectorXd& r, Eigen::VectorXd& z) override;
  bool keeps_factor() const override { return true; }
  bool uses_dense() const { return bool(dense_); }  // for the current system
  long refactors() const { return refactors_; }      // factors made (the first included)
  long adopted() const { return adopted_; }          // of those, made on the second thread
  long fallbacks() const { return fallbacks_; }      // corrected solves whose residual needed a refactor
  void share_helper(std::shared_ptr<HelperThread> helper) override;
  static constexpr int kDenseMax = 500;  // unknowns: up to here a dense LL' is used

 private:
  void dense_product(const Eigen::VectorXd& b, Eigen::VectorXd& x);
  void factor_solve(const Eigen::VectorXd& b, Eigen::VectorXd& x);
  static constexpr int kAdoptAfterSolves = 8;
  // Makes the kept factor (or its correction) serve `sys`.
  void prepare(const OperationalSystem& sys);
  struct Refactor;  // a factor being made on a second thread
  void refactor(const OperationalSystem& sys);
  bool correct(const OperationalSystem& sys);
  void adopt_pending();
  void launch_refactor(const OperationalSystem& sys);
  void take_pending(const OperationalSystem& sys);
  bool allow_dense_ = true, allow_correction_ = true;
  double correction_budget_ = 1.0;
  solve::Cholesky factor_;
  OperationalSystem base_;         // the system factor_ belongs to (K' shared)
  std::unique_ptr<FactorCorrection> correction_;  // solves a changed system with factor_
  bool corrected_ = false;         // the current system goes through correction_
  // While corrected with a helper thread: OpenBLAS on one thread. The
  // correction's column work runs in two halves on this thread and the
  // helper; an OpenBLAS worker spinning after a two-thread call would take
  // the helper's core (bench cut, 8k tets: frames 46 -> 38 ms).
  std::optional<SingleThreadedBlas> correcting_blas_;
  double correction_flops_ = 0;    // spent on corrections against factor_
  std::unique_ptr<Refactor> pending_;
  int solves_since_launch_ = 0;
  long refactors_ = 0, adopted_ = 0, fallbacks_ = 0;
  std::unique_ptr<Eigen::LLT<Eigen::MatrixXd>> dense_;  // systems of up to kDenseMax unknowns
  Eigen::MatrixXd dense_inverse_;                        // their inverse (n x n, both triangles)
  std::vector<std::pair<Eigen::Index, Eigen::Index>> runs_;  // nonzero runs of b: (start, length)
  std::shared_ptr<HelperThread> helper_;                 // the run's second thread, or null
  solve::SolveWorkspace ws_;  // CHOLMOD's solve buffers, kept between frames
  Eigen::VectorXd r_;  // residual scratch
  Eigen::VectorXd y_;  // the forward half of factor_solve
  long generation_ = -1;
};

}  // namespace softcut::hybrid
