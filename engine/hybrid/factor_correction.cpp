#include "hybrid/factor_correction.hpp"

#include <algorithm>
#include <exception>
#include <optional>

#include <Eigen/Cholesky>

#include "core/error.hpp"
#include "core/threads.hpp"

namespace softcut::hybrid {

namespace {

// Node row `pos` of a system's block CSR: the node ids of its blocks, in order.
struct BlockRow {
  const OperationalSystem& sys;
  int pos;
  int begin() const { return sys.block.row_start[size_t(pos)]; }
  int end() const { return sys.block.row_start[size_t(pos) + 1]; }
  int node(int k) const { return sys.nodes[size_t(sys.block.col[size_t(k)])]; }
  const Eigen::Matrix3d& block(int k) const { return sys.block.blocks[size_t(k)]; }
};

// Rows equal bit for bit: same neighbour nodes in the same order, same blocks.
bool same_row(const BlockRow& a, const BlockRow& b) {
  if (a.end() - a.begin() != b.end() - b.begin()) return false;
  for (int i = a.begin(), j = b.begin(); i < a.end(); ++i, ++j)
    if (a.node(i) != b.node(j) || a.block(i) != b.block(j)) return false;
  return true;
}

int position(const OperationalSystem& sys, int node) {
  return node >= 0 && size_t(node) < sys.node_index.size() ? sys.node_index[size_t(node)] : -1;
}

Eigen::Matrix3d diagonal_block(const OperationalSystem& sys, int pos) {
  const BlockRow r{sys, pos};
  for (int k = r.begin(); k < r.end(); ++k)
    if (sys.block.col[size_t(k)] == pos) return r.block(k);
  return Eigen::Matrix3d::Zero();
}

}  // namespace

// work(half, first, count) over columns [0, n) in two fixed halves, the
// second on the helper when it is awake; an exception of either is rethrown
// once both are done.
template <class Work>
void FactorCorrection::column_halves(Eigen::Index n, const Work& work) {
  std::exception_ptr error[2];
  const Eigen::Index h = n / 2;
  const auto half = [&](int k) {
    const Eigen::Index c0 = k == 0 ? 0 : h, w = k == 0 ? h : n - h;
    try {
      if (w > 0) work(k, c0, w);
    } catch (...) {
      error[k] = std::current_exception();
    }
  };
  run_halves(helper_, half);
  for (const auto& e : error)
    if (e) std::rethrow_exception(e);
}

void FactorCorrection::clear() {
  base_dofs_ = 0;
  base_generation_ = -1;
  cols_ = 0;
  W_.resize(0, 0);
  gram_.resize(0, 0);
  col_of_dof_.clear();
  changed_.clear();
  ext_of_next_.clear();
  added_ = 0;
}

bool FactorCorrection::prepare(const OperationalSystem& base, const solve::Cholesky& F, const OperationalSystem& next,
                               int max_dofs, double max_flops, solve::SolveWorkspace& ws, double* flops) {
  if (flops) *flops = 0;
  const int nb = int(base.nodes.size()), nn = int(next.nodes.size());
  if (F.rows() != base.size() || base.num_interface != next.num_interface || base.K_prime != next.K_prime ||
      int(base.block.row_start.size()) != nb + 1 || int(next.block.row_start.size()) != nn + 1 ||
      !std::equal(base.nodes.begin() + base.num_operational, base.nodes.end(),
                  next.nodes.begin() + next.num_operational))
    return false;
  changed_.clear();  // nothing prepared until this one succeeds
  ext_of_next_.clear();
  if (base_generation_ != base.generation || base_dofs_ != base.size()) {
    clear();
    base_generation_ = base.generation;
    base_dofs_ = base.size();
    col_of_dof_.assign(size_t(base_dofs_), -1);
    W_.resize(base_dofs_, 0);  // n rows from the start: W' y is defined with no column
  }
  const int n = base_dofs_;

  // Extended nodes: the base's positions, then next's appended nodes.
  std::vector<int> ext_node(static_cast<size_t>(nn));
  int ext_nodes = nb;
  for (int q = 0; q < nn; ++q) {
    const int p = position(base, next.nodes[size_t(q)]);
    ext_node[size_t(q)] = p >= 0 ? p : ext_nodes++;
  }
  const int na = ext_nodes - nb;
  // Changed base nodes: dropped ones and rows that differ (an appended
  // node's neighbours among them).
  std::vector<int> next_of_ext(static_cast<size_t>(ext_nodes), -1);
  for (int q = 0; q < nn; ++q) next_of_ext[size_t(ext_node[size_t(q)])] = q;
  std::vector<int> k_of_node(static_cast<size_t>(nb), -1), k_nodes;
  for (int p = 0; p < nb; ++p) {
    const int q = next_of_ext[size_t(p)];
    if (q < 0 || !same_row(BlockRow{base, p}, BlockRow{next, q})) {
      k_of_node[size_t(p)] = int(k_nodes.size());
      k_nodes.push_back(p);
    }
  }
  const int k = 3 * int(k_nodes.size());
  if (k > max_dofs) return false;

  // Cost of what is still missing, before computing any of it.
  std::vector<int> missing;
  for (int p : k_nodes)
    for (int a = 0; a < 3; ++a)
      if (col_of_dof_[size_t(3 * p + a)] < 0) missing.push_back(3 * p + a);
  const double c = double(missing.size()), cols_after = double(cols_) + c;
  // Columns (forward solves) and Gram entries, then G Delta, G Delta G, the
  // definiteness check's LL' and the capacitance LU: about 5 k^3.
  const double cost = c * (2 * F.factor_nonzeros() + 2.0 * n * cols_after) + 5.0 * double(k) * k * k;
  if (cost > max_flops) return false;

  // Appended nodes: N_aa (sparse, factored) and their coupling to the
  // changed rows, N_oa (a row of N that reaches an appended node changed).
  std::vector<Eigen::Triplet<double>> aa, ka;
  for (int e = nb; e < ext_nodes; ++e) {
    const BlockRow r{next, next_of_ext[size_t(e)]};
    for (int b = r.begin(); b < r.end(); ++b) {
      const int f = ext_node[size_t(next.block.col[size_t(b)])];
      const int i = 3 * (e - nb);
      for (int u = 0; u < 3; ++u)
        for (int v = 0; v < 3; ++v) {
          if (f >= nb) aa.emplace_back(i + u, 3 * (f - nb) + v, r.block(b)(u, v));
          else if (k_of_node[size_t(f)] >= 0) ka.emplace_back(3 * k_of_node[size_t(f)] + v, i + u, r.block(b)(u, v));
        }
    }
  }
  SparseMatrix Naa(3 * na, 3 * na);
  Naa.setFromTriplets(aa.begin(), aa.end());
  coupling_.resize(k, 3 * na);
  coupling_.setFromTriplets(ka.begin(), ka.end());
  added_ = 3 * na;
  // The Schur term's changed DOFs J (rows of N_oa with a nonzero) and
  // X = N_aa^-1 N_aJ.
  std::vector<int> touching;
  Eigen::MatrixXd X;
  if (na > 0) {
    try {
      added_factor_.factor(Naa, "appended nodes");
    } catch (const Error&) {
      return false;  // not positive definite: a refactor says why
    }
    const SparseMatrix coupling_t = coupling_.transpose();
    for (int j = 0; j < k; ++j)
      if (coupling_t.col(j).nonZeros() > 0) touching.push_back(j);
    Eigen::MatrixXd NaJ = Eigen::MatrixXd::Zero(3 * na, Eigen::Index(touching.size()));
    // CHOLMOD solves in two halves at once: OpenBLAS on one thread while
    // they run (two callers would fight over its pool).
    std::optional<SingleThreadedBlas> one_blas_thread;
    if (helper_) one_blas_thread.emplace();
    for (size_t j = 0; j < touching.size(); ++j)
      for (SparseMatrix::InnerIterator it(coupling_t, touching[j]); it; ++it) NaJ(it.row(), Eigen::Index(j)) = it.value();
    X.resize(3 * na, NaJ.cols());
    column_halves(NaJ.cols(), [&](int k, Eigen::Index c0, Eigen::Index w) {
      X.middleCols(c0, w) = added_factor_.solve(Eigen::MatrixXd(NaJ.middleCols(c0, w)), k == 0 ? ws : helper_ws_);
    });
  }

  // New columns of W and of its Gram matrix, in two fixed halves.
  if (!missing.empty()) {
    const Eigen::Index old = cols_, add = Eigen::Index(missing.size());
    if (old + add > W_.cols()) {  // grow by doubling, keeping the first cols_
      const Eigen::Index cap = std::max(old + add, 2 * Eigen::Index(W_.cols()));
      Eigen::MatrixXd W(n, cap), gram(cap, cap);
      W.leftCols(old) = W_.leftCols(old);
      gram.topLeftCorner(old, old) = gram_.topLeftCorner(old, old);
      W_.swap(W), gram_.swap(gram);
    }
    column_halves(add, [&](int k, Eigen::Index c0, Eigen::Index w) {
      Eigen::MatrixXd Wn;
      F.forward_columns_into(std::span(missing).subspan(size_t(c0), size_t(w)), Wn, k == 0 ? ws : helper_ws_);
      W_.middleCols(old + c0, w) = Wn;
    });
    // Gram entries over the rows where the new columns are nonzero (their
    // elimination-tree paths): runs of consecutive rows.
    column_halves(add, [&](int, Eigen::Index c0, Eigen::Index w) {
      auto out = gram_.block(0, old + c0, old + add, w);
      out.setZero();
      const auto Wn = W_.middleCols(old + c0, w);
      for (Eigen::Index r = 0; r < n;) {
        if ((Wn.row(r).array() == 0).all()) {
          ++r;
          continue;
        }
        const Eigen::Index start = r;
        while (r < n && !(Wn.row(r).array() == 0).all()) ++r;
        out.noalias() += W_.block(start, 0, r - start, old + add).transpose() * Wn.middleRows(start, r - start);
      }
    });
    gram_.block(old, 0, add, old) = gram_.block(0, old, old, add).transpose();
    cols_ = int(old + add);
    for (size_t j = 0; j < missing.size(); ++j) col_of_dof_[size_t(missing[j])] = int(old + Eigen::Index(j));
  }

  // Delta = (N_oo - M) - N_oa N_aa^-1 N_ao on the changed DOFs; a dropped
  // node's row of N_oo is M's diagonal block.
  delta_ = Eigen::MatrixXd::Zero(k, k);
  for (int i = 0; i < int(k_nodes.size()); ++i) {
    const int p = k_nodes[size_t(i)], q = next_of_ext[size_t(p)];
    auto add_row = [&](const BlockRow& r, auto base_pos, double sign) {
      for (int b = r.begin(); b < r.end(); ++b) {
        const int f = base_pos(r.sys.block.col[size_t(b)]);
        const int j = f >= 0 && f < nb ? k_of_node[size_t(f)] : -1;
        if (j >= 0) delta_.block<3, 3>(3 * i, 3 * j) += sign * r.block(b);
      }
    };
    if (q >= 0) add_row(BlockRow{next, q}, [&](int pos) { return ext_node[size_t(pos)]; }, 1.0);
    else delta_.block<3, 3>(3 * i, 3 * i) += diagonal_block(base, p);
    add_row(BlockRow{base, p}, [](int pos) { return pos; }, -1.0);
  }
  if (!touching.empty()) {
    const Eigen::MatrixXd schur = coupling_ * X;  // (k x J) N_oa N_aa^-1 N_ao, zero outside J's rows
    for (size_t j = 0; j < touching.size(); ++j) delta_.col(touching[j]) -= schur.col(Eigen::Index(j));
  }

  changed_.clear();
  for (int p : k_nodes)
    for (int a = 0; a < 3; ++a) changed_.push_back(3 * p + a);
  Eigen::MatrixXd G(k, k);
  for (int i = 0; i < k; ++i)
    for (int j = 0; j < k; ++j) G(i, j) = gram_(col_of_dof_[size_t(changed_[size_t(i)])], col_of_dof_[size_t(changed_[size_t(j)])]);
  // R = M + E Delta E' is positive definite exactly when
  // S = G + G Delta G = G^1/2 (I + G^1/2 Delta G^1/2) G^1/2 is (G = W'W is):
  // the check a refactor's Cholesky would make. A nearly singular R (a part
  // hanging by a node) is left to the refactor, which names it. G Delta and
  // G Delta G in column halves.
  if (k > 0) {
    Eigen::MatrixXd GD(k, k), S = G;
    column_halves(k, [&](int, Eigen::Index c0, Eigen::Index w) {
      GD.middleCols(c0, w).noalias() = G * delta_.middleCols(c0, w);
    });
    column_halves(k, [&](int, Eigen::Index c0, Eigen::Index w) {
      S.middleCols(c0, w).noalias() += GD * G.middleCols(c0, w);
    });
    S = 0.5 * (S + S.transpose()).eval();
    const Eigen::LLT<Eigen::MatrixXd> spd(S);
    if (spd.info() != Eigen::Success || !(spd.rcond() > 1e-13)) {
      changed_.clear();
      return false;
    }
    GD.diagonal().array() += 1.0;
    capacitance_.compute(GD);
  }
  ext_of_next_.resize(size_t(next.size()));
  for (int q = 0; q < nn; ++q) {
    const int e = ext_node[size_t(q)];
    for (int a = 0; a < 3; ++a) ext_of_next_[size_t(3 * q + a)] = 3 * e + a;  // appended: n + 3 (e - nb) + a
  }
  if (flops) *flops = cost;
  return true;
}

void FactorCorrection::solve(const solve::Cholesky& F, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                             solve::SolveWorkspace& ws) {
  const int n = base_dofs_, k = rank();
  if (b.size() != Eigen::Index(ext_of_next_.size()) || F.rows() != n)
    fail("FactorCorrection::solve: a right-hand side of size ", b.size(), " for a prepared system of ",
         ext_of_next_.size(), " unknowns (base factor ", F.rows(), " rows, kept columns for ", n, ")");
  b_.setZero(n);
  ba_.setZero(added_);
  for (size_t i = 0; i < ext_of_next_.size(); ++i) {
    const int e = ext_of_next_[i];
    if (e < n) b_[e] = b[Eigen::Index(i)];
    else ba_[e - n] = b[Eigen::Index(i)];
  }
  // Appended nodes eliminated: c = b_o - N_oa N_aa^-1 b_a.
  if (added_ > 0) {
    added_factor_.solve_into(ba_, xa_, ws);
    q_.noalias() = coupling_ * xa_;
    for (int j = 0; j < k; ++j) b_[changed_[size_t(j)]] -= q_[j];
  }
  F.forward_vector(b_, y_, ws, helper_);
  t_.resize(cols_);
  // W's two products read n x cols doubles each (18 MB at 8k operational
  // tets), which two cores stream faster.
  row_halves(helper_, cols_, [&](Eigen::Index c0, Eigen::Index w) {
    t_.segment(c0, w).noalias() = W_.middleCols(c0, w).transpose() * y_;
  });
  g_.resize(k);
  for (int j = 0; j < k; ++j) g_[j] = t_[col_of_dof_[size_t(changed_[size_t(j)])]];
  if (k > 0) {
    q_.noalias() = delta_ * capacitance_.solve(g_);
  } else {
    q_.resize(0);
  }
  t_.setZero(cols_);
  for (int j = 0; j < k; ++j) t_[col_of_dof_[size_t(changed_[size_t(j)])]] = q_[j];
  if (cols_ > 0)  // (no block of a matrix without storage)
    row_halves(helper_, n, [&](Eigen::Index r0, Eigen::Index h) {
      y_.segment(r0, h).noalias() -= W_.block(r0, 0, h, cols_) * t_;
    });
  F.backward_vector(y_, xb_, ws, helper_);
  // x_a = N_aa^-1 (b_a - N_ao x_o).
  if (added_ > 0) {
    for (int j = 0; j < k; ++j) g_[j] = xb_[changed_[size_t(j)]];
    ba_.noalias() -= coupling_.transpose() * g_;
    added_factor_.solve_into(ba_, xa_, ws);
  }
  x.resize(Eigen::Index(ext_of_next_.size()));
  for (size_t i = 0; i < ext_of_next_.size(); ++i) {
    const int e = ext_of_next_[i];
    x[Eigen::Index(i)] = e < n ? xb_[e] : xa_[e - n];
  }
}

}  // namespace softcut::hybrid
