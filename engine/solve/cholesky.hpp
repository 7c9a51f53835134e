#pragma once
// Sparse Cholesky factor (CHOLMOD, through Eigen's CholmodSupport): factor once,
// solve many right-hand sides. Used for the monolithic reference solve, K22 in
// the hybrid precompute, and the direct operational backend.
#include <Eigen/CholmodSupport>
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace softcut {
class BinaryWriter;
class BinaryReader;
class HelperThread;
}  // namespace softcut

namespace softcut::solve {

// CHOLMOD workspace of one thread: lets a second thread solve with a factor
// that another thread also solves with (CHOLMOD's solve reads the factor
// only; its workspace and status live in the common object).
class SolveWorkspace {
 public:
  SolveWorkspace();
  ~SolveWorkspace();
  SolveWorkspace(const SolveWorkspace&) = delete;
  SolveWorkspace& operator=(const SolveWorkspace&) = delete;
  cholmod_common& common() { return c_; }
  // Solution and scratch of cholmod_solve2, kept between solves (no allocation per frame).
  cholmod_dense* X = nullptr;
  cholmod_dense* Y = nullptr;
  cholmod_dense* E = nullptr;

 private:
  cholmod_common c_;
};

class Cholesky {
 public:
  Cholesky() = default;
  // Factors the symmetric positive definite A (lower triangle is read).
  // Throws softcut::Error naming `what` when A is not positive definite
  // (e.g. a part of the body without fixed nodes).
  // `max_bytes`: the factor's size, estimated from CHOLMOD's symbolic
  // analysis before the numeric factorization allocates it, must not pass
  // it (the sandbox's memory budget); else a softcut::Error naming `what`.
  explicit Cholesky(const Eigen::SparseMatrix<double>& A, const std::string& what = "matrix");
  void factor(const Eigen::SparseMatrix<double>& A, const std::string& what = "matrix",
              double max_bytes = std::numeric_limits<double>::infinity());
  // Nonzeros of the factor factor() would make of a matrix with A's pattern
  // (lower triangle read; values ignored): CHOLMOD's symbolic analysis only,
  // with the same ordering methods. For estimates made before a matrix is
  // assembled (hybrid/precompute_estimate.hpp).
  static double symbolic_nonzeros(const Eigen::SparseMatrix<double>& A);

  // Every solve takes the caller's workspace: CHOLMOD's solve reads the
  // factor only and keeps its scratch and status in the workspace's common,
  // so a factor (a Model's K22) serves solves on several threads at once,
  // each with its own workspace. One column per right-hand side.
  Eigen::MatrixXd solve(const Eigen::MatrixXd& B, SolveWorkspace& ws) const;
  // x = A^-1 b with the workspace's kept buffers: no allocation once sized
  // (the per-frame solve of small systems, where allocation is a large share).
  void solve_into(const Eigen::VectorXd& b, Eigen::VectorXd& x, SolveWorkspace& ws) const;

  // The two triangular halves of a solve, for low-rank corrections
  // (hybrid/factor_correction.hpp). CHOLMOD factors A = P' L L' P with a
  // fill-reducing permutation P:
  //   forward:  Y = L^-1 P B   (one column per right-hand side)
  //   backward: x = P' L'^-1 y
  // so A^-1 b = backward(forward(b)) and (A^-1)(i, j) = forward(e_i) . forward(e_j).
  void forward_into(const Eigen::MatrixXd& B, Eigen::MatrixXd& Y, SolveWorkspace& ws) const;
  void backward_into(const Eigen::VectorXd& y, Eigen::VectorXd& x, SolveWorkspace& ws) const;
  // backward for a few columns at once: a supernodal factor is read once,
  // by dot products with the columns (`ws` is then not used). With a helper
  // thread, the elimination tree's subtrees below its top are solved on two
  // threads (a first touch on a large factor is bound by memory bandwidth,
  // which two cores double); the same bits with or without it.
  void backward_into(const Eigen::MatrixXd& Y, Eigen::MatrixXd& X, SolveWorkspace& ws,
                     HelperThread* helper = nullptr) const;
  // forward(E) for unit columns E = [e_rows[0] e_rows[1] ...]: walks only
  // the supernodes on the elimination-tree paths from those rows to the root
  // (the rest of Y is exactly zero), so it costs a small part of a whole
  // forward solve on a large factor. Same Y as forward_into up to rounding;
  // a simplicial factor (small systems) takes forward_into.
  void forward_unit_into(std::span<const int> rows, Eigen::MatrixXd& Y, SolveWorkspace& ws) const;
  // The same Y for tens of unit columns (a cut's changed DOFs): each
  // supernode on the paths takes a triangular solve and a product over the
  // columns whose paths pass through it (BLAS 3), where forward_unit_into
  // updates one column at a time. Against CHOLMOD's forward solve of the
  // whole E it skips the supernodes off the paths (bench cut, 8k operational
  // tets: a cut's paths pass 5 to 23 of 185 supernodes below the dense
  // interface block at the top; the frame's new columns 12.6 -> 7.8 ms).
  // Y equals forward_into's up to rounding.
  void forward_columns_into(std::span<const int> rows, Eigen::MatrixXd& Y, SolveWorkspace& ws) const;

  // forward_into and backward_into for one vector, supernode by supernode.
  // A last supernode of kSplitTop columns or more (an operational system's
  // interface block, dense through K') goes in blocks of kSplitTop whose
  // products with the rows beside them run in two fixed row halves, the
  // second on `helper`: one vector's solve only streams the factor, and two
  // cores stream it about twice as fast. The same bits with or without the
  // helper; equal to forward_into / backward_into up to rounding.
  static constexpr int kSplitTop = 256;
  void forward_vector(const Eigen::VectorXd& b, Eigen::VectorXd& y, SolveWorkspace& ws,
                      HelperThread* helper = nullptr) const;
  void backward_vector(const Eigen::VectorXd& y, Eigen::VectorXd& x, SolveWorkspace& ws,
                       HelperThread* helper = nullptr) const;

  // Nonzeros of the factor L (CHOLMOD's count after the symbolic analysis).
  double factor_nonzeros() const { return lnz_; }
  // Floating-point operations of the numeric factorization (CHOLMOD's count
  // after the symbolic analysis; 0 for a loaded factor): a refactor's cost.
  double factor_flops() const { return flops_; }

  // The numeric factor as bytes (the precompute cache), and back: load()
  // rebuilds CHOLMOD's factor from them, checks it with cholmod_check_factor,
  // and solves bit for bit as the saved one. Throws softcut::Error naming the
  // reader's file on anything inconsistent.
  void save(BinaryWriter& w) const;
  void load(BinaryReader& r);

  int rows() const { return rows_; }
  // Subtrees below the elimination tree's top that backward_into shares out
  // between two threads (0 for a simplicial factor).
  int subtrees() const { return items_; }
  bool factored() const { return bool(llt_); }
  // CHOLMOD chose a supernodal factor (large or dense systems), else simplicial.
  bool supernodal() const;

 private:
  class Llt;  // Eigen's decomposition with access to its cholmod_factor
  std::shared_ptr<Llt> llt_;
  // (supernodes) of a supernodal factor: when backward_into solves it, 0
  // with the top of the elimination tree, k >= 1 with the k-th subtree
  // below (items_ of them; cholesky.cpp subtree_items).
  std::vector<int> item_;
  int items_ = 0;
  void set_items();  // from llt_
  // Column of L where each unit row lands after the permutation; checks the rows.
  std::vector<int> unit_columns(std::span<const int> rows) const;
  int rows_ = 0;
  double lnz_ = 0;
  double flops_ = 0;
};

}  // namespace softcut::solve
