#pragma once
// The operational system of the hybrid model (paper Eq. 12, DESIGN.md §1):
//
//   [ K11   K1I       ] [A1]   [ P1        ]
//   [ KI1   K1II + K' ] [AI] = [ PI_ext - P' ]
//
// K (K11, K1I, KI1, K1II) is assembled from the operational tets only; K' is
// the dense Schur complement of the nonoperational region on the interface
// DOFs (precomputed once, never changes). Cutting changes only operational
// tets and appends nodes, so this system is rebuilt from the cut mesh while K'
// and every other precomputed block stay valid.
//
// DOF ordering (shared with the GPU solver):
//   unknown node k, 0 <= k < size_nodes(), is mesh node nodes[k]; its DOFs are
//   3k + axis (axis 0,1,2 = x,y,z).
//   nodes[0 .. num_operational)     set-1 nodes (free, touched only by
//                                   operational tets, including nodes appended
//                                   by cutting), increasing node id;
//   nodes[num_operational .. end)   the interface nodes, in the model's
//                                   interface order (increasing node id).
//   So the interface DOFs are the LAST 3*num_interface DOFs, contiguous,
//   starting at interface_offset() = 3*num_operational, and K' row/column j is
//   system DOF interface_offset() + j.
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <string>
#include <vector>

#include "fem/material.hpp"
#include "hybrid/node_blocks.hpp"
#include "mesh/tet_mesh.hpp"
#include "solve/cg.hpp"
#include "solve/cholesky.hpp"

namespace softcut::hybrid {

class FactorCorrection;

struct OperationalSystem {
  std::vector<int> nodes;       // (num_operational + num_interface) mesh node id of each unknown node
  std::vector<int> node_index;  // (nnode of the operational mesh) position in `nodes`, -1 if none
  int num_operational = 0;      // |1|
  int num_interface = 0;        // |I|
  SparseMatrix K;               // (3n x 3n) N/m, operational tets only, both triangles stored
  std::shared_ptr<const Eigen::MatrixXd> K_prime;  // (3|I| x 3|I|) N/m, dense, on the last 3|I| DOFs
  long generation = 0;          // unique per build; solvers cache per-system data by it
  // K again in 3x3 node blocks, row by row (block CSR; K is symmetric), made by
  // build_operational_system: apply() runs on it, 3x faster than the scalar
  // sparse product. Empty for a hand-made system: apply() uses K then.
  std::vector<int> block_row_start;      // (size()/3 + 1) first block of each node row
  std::vector<int> block_col;            // node column of each block
  std::vector<Eigen::Matrix3d> blocks;   // K(3 row + a, 3 col + b) = blocks[k](a, b)

  int size() const { return int(3 * nodes.size()); }
  int interface_offset() const { return 3 * num_operational; }

  // y = (K + K') x, x and y of size(); y is resized.
  void apply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const;
  // K with K' added into its interface block (sparse with a dense corner), for
  // direct solvers and checks.
  SparseMatrix assembled() const;
  // b = [P1; PI - P'] from per-node forces (nnode x 3, N; rows of other nodes
  // are ignored) and P' (3|I|, N).
  Eigen::VectorXd rhs(const Eigen::MatrixX3d& forces, const Eigen::VectorXd& P_prime) const;
};

// Builds the system from the operational tets of a mesh. `interface_nodes`
// are the model's interface node ids (kept last, in this order, even if no
// operational tet touches one any more); `node_fixed` (nnode) marks fixed
// nodes. K_prime must be (3|I| x 3|I|). Throws when an operational tet uses a
// nonoperational node that is not an interface node (the precomputed data
// would no longer describe the nonoperational region).
OperationalSystem build_operational_system(const mesh::TetMesh& m, const std::vector<fem::Material>& tet_material,
                                           const std::vector<int>& operational_tets,
                                           const std::vector<int>& interface_nodes,
                                           const std::vector<char>& node_fixed,
                                           const std::vector<char>& node_nonoperational,
                                           std::shared_ptr<const Eigen::MatrixXd> K_prime);

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
  bool uses_dense() const { return bool(dense_); }  // for the current system
  long refactors() const { return refactors_; }      // factors made (the first included)
  long adopted() const { return adopted_; }          // of those, made on the second thread

 private:
  static constexpr int kDenseMax = 500;  // unknowns: up to here a dense LL' is used
  struct Refactor;  // a factor being made on a second thread
  void refactor(const OperationalSystem& sys);
  bool correct(const OperationalSystem& sys);
  void adopt_pending();
  bool allow_dense_ = true, allow_correction_ = true;
  double correction_budget_ = 1.0;
  solve::Cholesky factor_;
  OperationalSystem base_;         // the system factor_ belongs to (K' shared)
  std::unique_ptr<FactorCorrection> correction_;  // solves a changed system with factor_
  bool corrected_ = false;         // the current system goes through correction_
  double correction_flops_ = 0;    // spent on corrections against factor_
  std::unique_ptr<Refactor> pending_;
  long refactors_ = 0, adopted_ = 0;
  std::unique_ptr<Eigen::LLT<Eigen::MatrixXd>> dense_;  // systems of up to kDenseMax unknowns
  solve::SolveWorkspace ws_;  // CHOLMOD's solve buffers, kept between frames
  Eigen::VectorXd r_;  // residual scratch
  long generation_ = -1;
};

}  // namespace softcut::hybrid
