// The supernode-by-supernode solves of solve::Cholesky (cholesky.hpp): the
// backward solve of a few columns on two threads, the forward solves of unit
// columns along their elimination-tree paths, and the one-vector solves
// whose dense top block runs in row halves.
#include <exception>
#include <functional>
#include <mutex>

#include "core/error.hpp"
#include "core/helper_thread.hpp"
#include "solve/supernodes.hpp"

namespace softcut::solve {

void Cholesky::backward_into(const Eigen::MatrixXd& Y, Eigen::MatrixXd& X, SolveWorkspace& ws,
                             HelperThread* helper) const {
  if (!llt_) fail("Cholesky::backward called before factor()");
  if (Y.rows() != rows_) fail("Cholesky::backward: vectors of size ", Y.rows(), " for a ", rows_, "-row factor");
  const cholmod_factor* L = llt_->raw();
  if (!L->is_ll) fail("Cholesky::backward: the factor is not LL' (an LDL' factor would need D)");
  X.resize(Y.rows(), Y.cols());
  if (Y.cols() == 0) return;
  const int* perm = static_cast<const int*>(L->Perm);
  if (!L->is_super) {
    cholmod_dense in = dense_view(Y.data(), Y.rows(), Y.cols());
    cholmod_dense* out = cholmod_solve(CHOLMOD_Lt, llt_->raw(), &in, &ws.common());
    if (!out) fail("Cholesky::backward: CHOLMOD failed (status ", ws.common().status, "; out of memory?)");
    const Eigen::Map<const Eigen::MatrixXd> t(static_cast<const double*>(out->x), Y.rows(), Y.cols());
    for (Eigen::Index k = 0; k < Y.rows(); ++k) X.row(perm ? perm[k] : k) = t.row(k);
    cholmod_free_dense(&out, &ws.common());
    return;
  }
  // Supernodes from the root down: the top of the tree first, then the
  // subtrees below it (item_), on two threads when a helper is given. Each
  // supernode reads only its ancestors' rows, so whoever computes it, it
  // gives the same bits.
  const Supernodes sn(*L);
  RowMajorMatrix T = Y;  // a row's m entries together (one cache line to gather)
  std::mutex error_mu;
  std::exception_ptr error;  // an item's (an allocation's) failure, rethrown once both threads are done
  auto solve_item = [&](int item) {
    try {
      Eigen::MatrixXd V;
      std::vector<double> sum;
      for (int s = sn.count - 1; s >= 0; --s)
        if (item_[size_t(s)] == item) backward_supernode(sn, s, T, V, sum);
    } catch (...) {
      std::lock_guard lk(error_mu);
      if (!error) error = std::current_exception();
    }
  };
  solve_item(0);
  if (error) std::rethrow_exception(error);
  const std::function<void(int)> subtree = [&](int k) { solve_item(k + 1); };
  if (helper) helper->run_items(items_, subtree);
  else for (int k = 0; k < items_; ++k) subtree(k);
  if (error) std::rethrow_exception(error);
  for (Eigen::Index k = 0; k < Y.rows(); ++k) X.row(perm ? perm[k] : k) = T.row(k);
}

std::vector<int> Cholesky::unit_columns(std::span<const int> rows) const {
  if (!llt_) fail("Cholesky::forward called before factor()");
  for (int r : rows)
    if (r < 0 || r >= rows_) fail("Cholesky::forward: unit column at row ", r, " of a ", rows_, "-row factor");
  // P e_r = e_k with perm[k] = r.
  const int* perm = static_cast<const int*>(llt_->raw()->Perm);
  const size_t m = rows.size();
  std::vector<int> column(m, -1), wanted(static_cast<size_t>(rows_), -1);
  for (size_t j = 0; j < m; ++j) wanted[size_t(rows[j])] = int(j);
  for (int k = 0; k < rows_; ++k) {
    const int j = wanted[size_t(perm ? perm[k] : k)];
    if (j >= 0) column[size_t(j)] = k;
  }
  for (size_t j = 0; j < m; ++j) column[j] = column[size_t(wanted[size_t(rows[j])])];
  return column;
}

void Cholesky::forward_unit_into(std::span<const int> rows, Eigen::MatrixXd& Y, SolveWorkspace& ws) const {
  const std::vector<int> column = unit_columns(rows);
  const cholmod_factor* L = llt_->raw();
  const Eigen::Index m = Eigen::Index(rows.size());
  if (!L->is_super) {
    Eigen::MatrixXd E = Eigen::MatrixXd::Zero(rows_, m);
    for (Eigen::Index j = 0; j < m; ++j) E(rows[size_t(j)], j) = 1;
    forward_into(E, Y, ws);
    return;
  }
  const Supernodes sn(*L);
  // The supernodes on the paths from those columns to the root, children first.
  std::vector<int> path;
  std::vector<char> on(size_t(sn.count), 0);
  for (int k : column)
    for (int s = sn.of(k); s >= 0 && !on[size_t(s)]; s = sn.parent(s)) {
      on[size_t(s)] = 1;
      path.push_back(s);
    }
  std::sort(path.begin(), path.end());

  Y.setZero(rows_, m);
  for (Eigen::Index j = 0; j < m; ++j) Y(column[size_t(j)], j) = 1;
  // Each supernode on the path, right-looking: V = its rows of Y (its own
  // first); column c of its block, read once, finishes V's row c and
  // updates every row below it; then V goes back to Y's rows.
  Eigen::MatrixXd V;
  for (int s : path) {
    const int nsrow = sn.rows(s);
    const auto block = sn.block(s);
    const int* rows_of_s = sn.Ls + sn.pi[s];
    V.resize(nsrow, m);
    for (int i = 0; i < nsrow; ++i) V.row(i) = Y.row(rows_of_s[i]);
    for (int c = 0; c < sn.cols(s); ++c) {
      const int len = nsrow - c - 1;
      for (Eigen::Index k = 0; k < m; ++k) {
        const double v = V(c, k) /= block(c, c);
        if (v != 0) V.col(k).tail(len) -= v * block.col(c).tail(len);
      }
    }
    for (int i = 0; i < nsrow; ++i) Y.row(rows_of_s[i]) = V.row(i);
  }
}

void Cholesky::forward_columns_into(std::span<const int> rows, Eigen::MatrixXd& Y, SolveWorkspace& ws) const {
  const std::vector<int> column = unit_columns(rows);
  const cholmod_factor* L = llt_->raw();
  const Eigen::Index m = Eigen::Index(rows.size());
  if (!L->is_super) {
    forward_unit_into(rows, Y, ws);
    return;
  }
  const Supernodes sn(*L);
  // (supernode, column) for every supernode on each column's path to its
  // root, grouped by supernode (children before parents), columns increasing.
  std::vector<std::pair<int, int>> on_path;
  for (Eigen::Index j = 0; j < m; ++j)
    for (int s = sn.of(column[size_t(j)]); s >= 0; s = sn.parent(s)) on_path.emplace_back(s, int(j));
  std::sort(on_path.begin(), on_path.end());

  Y.setZero(rows_, m);
  for (Eigen::Index j = 0; j < m; ++j) Y(column[size_t(j)], j) = 1;
  // Each supernode: V = its rows of Y in its active columns (its own rows
  // first); V_top = L_ss^-1 V_top, V_below -= L_below V_top; back into Y.
  // Rows below the diagonal block belong to ancestors, which are on the
  // same paths: Y stays exactly zero off them.
  Eigen::MatrixXd V;
  std::vector<int> active;
  for (size_t first = 0; first < on_path.size();) {
    const int s = on_path[first].first;
    active.clear();
    for (; first < on_path.size() && on_path[first].first == s; ++first) active.push_back(on_path[first].second);
    const int nsrow = sn.rows(s), nscol = sn.cols(s), na = int(active.size());
    const int* rows_of_s = sn.Ls + sn.pi[s];
    V.resize(nsrow, na);
    for (int q = 0; q < na; ++q)
      for (int i = 0; i < nsrow; ++i) V(i, q) = Y(rows_of_s[i], active[size_t(q)]);
    const auto block = sn.block(s);
    block.topRows(nscol).triangularView<Eigen::Lower>().solveInPlace(V.topRows(nscol));
    if (nsrow > nscol) V.bottomRows(nsrow - nscol).noalias() -= block.bottomRows(nsrow - nscol) * V.topRows(nscol);
    for (int q = 0; q < na; ++q)
      for (int i = 0; i < nsrow; ++i) Y(rows_of_s[i], active[size_t(q)]) = V(i, q);
  }
}

void Cholesky::forward_vector(const Eigen::VectorXd& b, Eigen::VectorXd& y, SolveWorkspace& ws,
                              HelperThread* helper) const {
  if (!llt_) fail("Cholesky::forward called before factor()");
  if (b.size() != rows_) fail("Cholesky::forward: a vector of size ", b.size(), " for a ", rows_, "-row factor");
  const cholmod_factor* L = llt_->raw();
  if (!L->is_super) {
    Eigen::MatrixXd Y;
    forward_into(b, Y, ws);
    y = Y.col(0);
    return;
  }
  const Supernodes sn(*L);
  const int* perm = static_cast<const int*>(L->Perm);
  y.resize(rows_);
  for (int k = 0; k < rows_; ++k) y[k] = b[perm ? perm[k] : k];
  const int top = sn.count - 1;
  const bool split = splits_top(sn);
  Eigen::VectorXd v;
  for (int s = 0; s < sn.count - (split ? 1 : 0); ++s) {
    const int nsrow = sn.rows(s), nscol = sn.cols(s);
    const int* rows_of_s = sn.Ls + sn.pi[s];
    const auto block = sn.block(s);
    v.resize(nsrow);
    for (int i = 0; i < nsrow; ++i) v[i] = y[rows_of_s[i]];
    block.topRows(nscol).triangularView<Eigen::Lower>().solveInPlace(v.head(nscol));
    if (nsrow > nscol) v.tail(nsrow - nscol).noalias() -= block.bottomRows(nsrow - nscol) * v.head(nscol);
    for (int i = 0; i < nsrow; ++i) y[rows_of_s[i]] = v[i];
  }
  if (!split) return;
  // The top's rows are the last nt of y, in order.
  const auto T = sn.block(top);
  const Eigen::Index nt = T.cols();
  auto yt = y.tail(nt);
  for (Eigen::Index j0 = 0; j0 < nt; j0 += kSplitTop) {
    const Eigen::Index jb = std::min<Eigen::Index>(kSplitTop, nt - j0), r = j0 + jb;
    T.block(j0, j0, jb, jb).triangularView<Eigen::Lower>().solveInPlace(yt.segment(j0, jb));
    row_halves(helper, long(nt - r), [&](Eigen::Index r0, Eigen::Index w) {
      yt.segment(r + r0, w).noalias() -= T.block(r + r0, j0, w, jb) * yt.segment(j0, jb);
    });
  }
}

void Cholesky::backward_vector(const Eigen::VectorXd& y, Eigen::VectorXd& x, SolveWorkspace& ws,
                               HelperThread* helper) const {
  if (!llt_) fail("Cholesky::backward called before factor()");
  if (y.size() != rows_) fail("Cholesky::backward: a vector of size ", y.size(), " for a ", rows_, "-row factor");
  const cholmod_factor* L = llt_->raw();
  if (!L->is_super) {
    backward_into(y, x, ws);
    return;
  }
  const Supernodes sn(*L);
  Eigen::VectorXd t = y;  // L'^-1 y in L's order, finished from the top down
  const int top = sn.count - 1;
  const bool split = splits_top(sn);
  if (split) {
    // Each block: its rows of t less the block's rows below it times their
    // finished values (two partial sums over fixed row halves, added in
    // order), then the transposed triangular solve.
    const auto T = sn.block(top);
    const Eigen::Index nt = T.cols();
    auto tt = t.tail(nt);
    Eigen::VectorXd part[2];
    for (Eigen::Index j0 = (nt - 1) / kSplitTop * kSplitTop; j0 >= 0; j0 -= kSplitTop) {
      const Eigen::Index jb = std::min<Eigen::Index>(kSplitTop, nt - j0), r = j0 + jb;
      part[0].setZero(jb), part[1].setZero(jb);
      row_halves(helper, long(nt - r), [&](Eigen::Index r0, Eigen::Index w) {
        if (w > 0) part[r0 == 0 ? 0 : 1].noalias() = T.block(r + r0, j0, w, jb).transpose() * tt.segment(r + r0, w);
      });
      tt.segment(j0, jb) -= part[0];
      tt.segment(j0, jb) -= part[1];
      T.block(j0, j0, jb, jb).triangularView<Eigen::Lower>().transpose().solveInPlace(tt.segment(j0, jb));
    }
  }
  Eigen::VectorXd v;
  for (int s = sn.count - 1 - (split ? 1 : 0); s >= 0; --s) {
    const int nsrow = sn.rows(s), nscol = sn.cols(s);
    const int* rows_of_s = sn.Ls + sn.pi[s];
    const auto block = sn.block(s);
    auto ts = t.segment(sn.super[s], nscol);
    if (nsrow > nscol) {
      v.resize(nsrow - nscol);
      for (int i = nscol; i < nsrow; ++i) v[i - nscol] = t[rows_of_s[i]];
      ts.noalias() -= block.bottomRows(nsrow - nscol).transpose() * v;
    }
    block.topRows(nscol).triangularView<Eigen::Lower>().transpose().solveInPlace(ts);
  }
  const int* perm = static_cast<const int*>(L->Perm);
  x.resize(rows_);
  for (int k = 0; k < rows_; ++k) x[perm ? perm[k] : k] = t[k];
}

}  // namespace softcut::solve
