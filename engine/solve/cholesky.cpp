#include "solve/cholesky.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <functional>
#include <mutex>
#include <vector>

#include "core/helper_thread.hpp"

#include "core/binary_io.hpp"
#include "core/error.hpp"

namespace softcut::solve {

class Cholesky::Llt : public Eigen::CholmodDecomposition<Eigen::SparseMatrix<double>, Eigen::Lower> {
 public:
  cholmod_factor* raw() const { return m_cholmodFactor; }
  // Takes ownership of a numeric factor made outside Eigen (load()).
  void adopt(cholmod_factor* L) {
    if (m_cholmodFactor) cholmod_free_factor(&m_cholmodFactor, &cholmod());
    m_cholmodFactor = L;
    m_isInitialized = true;
    m_info = Eigen::Success;
    m_analysisIsOk = true;
    m_factorizationIsOk = true;
  }
};

SolveWorkspace::SolveWorkspace() {
  cholmod_start(&c_);
  c_.print = 0;
}

SolveWorkspace::~SolveWorkspace() {
  for (cholmod_dense** d : {&X, &Y, &E})
    if (*d) cholmod_free_dense(d, &c_);
  cholmod_finish(&c_);
}

namespace {

cholmod_dense dense_view(const double* data, Eigen::Index rows, Eigen::Index cols) {
  cholmod_dense d{};
  d.nrow = size_t(rows);
  d.ncol = size_t(cols);
  d.nzmax = d.nrow * d.ncol;
  d.d = d.nrow;
  d.x = const_cast<double*>(data);  // read only (CHOLMOD's API is not const)
  d.xtype = CHOLMOD_REAL;
  d.dtype = CHOLMOD_DOUBLE;
  return d;
}

// CHOLMOD's supernodal factor (int, real LL') as arrays. Supernode s holds
// columns super[s] .. super[s+1]-1 of L; its rows are Ls[pi[s] ..] (its own
// columns first, then increasing), its values a rows(s) x cols(s)
// column-major block at Lx[px[s]]. The parent of s is the supernode of its
// first row below the diagonal block; parents come after children.
struct Supernodes {
  explicit Supernodes(const cholmod_factor& L)
      : super(static_cast<const int*>(L.super)), pi(static_cast<const int*>(L.pi)),
        px(static_cast<const int*>(L.px)), Ls(static_cast<const int*>(L.s)), Lx(static_cast<const double*>(L.x)),
        count(int(L.nsuper)) {}
  const int *super, *pi, *px, *Ls;
  const double* Lx;
  int count;
  int cols(int s) const { return super[s + 1] - super[s]; }
  int rows(int s) const { return pi[s + 1] - pi[s]; }
  Eigen::Map<const Eigen::MatrixXd, 0, Eigen::OuterStride<>> block(int s) const {
    return {Lx + px[s], rows(s), cols(s), Eigen::OuterStride<>(rows(s))};
  }
  // The supernode holding column `col`.
  int of(int col) const { return int(std::upper_bound(super, super + count + 1, col) - super) - 1; }
  // The parent of s, -1 for a root (no rows below its diagonal block).
  int parent(int s) const { return rows(s) > cols(s) ? of(Ls[pi[s] + cols(s)]) : -1; }
};

// The one-vector solves take the last supernode in blocks of kSplitTop when
// it is a dense top (no rows below its columns) of that many columns or more.
bool splits_top(const Supernodes& sn) {
  const int top = sn.count - 1;
  return sn.rows(top) == sn.cols(top) && sn.cols(top) >= Cholesky::kSplitTop;
}

using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// sum[k] = a[from..to) . v_k[from..to) for K (1 or 3) vectors v_k, reading
// a once, eight lanes at a time. Each vector's sum is formed the same way
// whatever K and its place among them, so a column of the solution has the
// same bits solved alone or among others. The accumulators are named
// locals: in an array, GCC kept them in memory, and each lane's addition
// then waited on the last one's store (a first touch's backward solve ran
// at a third of the factor's streaming speed).
template <int K>
void dots(const double* a, int from, int to, double* const* v, double* sum) {
  static_assert(K == 1 || K == 3);
  using P = Eigen::Array<double, 8, 1>;
  using Map = Eigen::Map<const P>;
  P acc0 = P::Zero(), acc1 = P::Zero(), acc2 = P::Zero();
  int i = from;
  for (; i + 8 <= to; i += 8) {
    const P x = Map(a + i);
    acc0 += x * Map(v[0] + i);
    if constexpr (K == 3) {
      acc1 += x * Map(v[1] + i);
      acc2 += x * Map(v[2] + i);
    }
  }
  const P* acc[3] = {&acc0, &acc1, &acc2};
  for (int k = 0; k < K; ++k) {
    sum[k] = acc[k]->sum();
    for (int j = i; j < to; ++j) sum[k] += a[j] * v[k][j];
  }
}

// sum(c, k) = a_c[from..to) . V(from..to, k) for column c of a block
// (leading dimension ld) and every column of V, three at a time.
void block_dots(const double* block, int ld, int c, int from, int to, Eigen::MatrixXd& V, double* sum) {
  const double* a = block + size_t(c) * size_t(ld);
  Eigen::Index k = 0;
  for (; k + 3 <= V.cols(); k += 3) {
    double* const v[3] = {&V(0, k), &V(0, k + 1), &V(0, k + 2)};
    dots<3>(a, from, to, v, sum + k);
  }
  for (; k < V.cols(); ++k) {
    double* const v[1] = {&V(0, k)};
    dots<1>(a, from, to, v, sum + k);
  }
}

// The backward solve's step at supernode s: V = its rows of T, its own
// columns' first (still to finish), then the rows below them (final: they
// belong to ancestors). Column c of the block, read once from memory,
// finishes V's row c; the finished rows go back to T.
void backward_supernode(const Supernodes& sn, int s, RowMajorMatrix& T, Eigen::MatrixXd& V,
                        std::vector<double>& sum) {
  const int nscol = sn.cols(s), nsrow = sn.rows(s);
  const Eigen::Index m = T.cols();
  const int* rows_of_s = sn.Ls + sn.pi[s];
  const double* block = sn.Lx + sn.px[s];
  V.resize(nsrow, m);
  for (int i = 0; i < nsrow; ++i) V.row(i) = T.row(rows_of_s[i]);
  sum.resize(size_t(m));
  for (int c = nscol - 1; c >= 0; --c) {
    block_dots(block, nsrow, c, c + 1, nsrow, V, sum.data());
    const double d = block[size_t(c) * size_t(nsrow) + size_t(c)];
    for (Eigen::Index k = 0; k < m; ++k) V(c, k) = (V(c, k) - sum[size_t(k)]) / d;
  }
  T.middleRows(sn.super[s], nscol) = V.topRows(nscol);
}

// How a backward solve shares the supernodes out between two threads:
// item[s] = 0 for the top of the elimination tree (solved first, on the
// caller), k >= 1 for the whole subtrees below it, item k-1 of a job the
// two threads claim from (HelperThread::run_items), largest first. The top
// grows from the roots, the heaviest subtree split first, until no subtree
// holds more than an eighth of the entries of L read (in a nested
// dissection tree: a few levels of separators down) or the top a quarter.
std::vector<int> subtree_items(const Supernodes& sn) {
  const size_t n = size_t(sn.count);
  std::vector<int> parent(n, -1);
  std::vector<double> own(n), weight(n);  // entries of L read at the supernode, in its subtree
  std::vector<std::vector<int>> children(n);
  for (int s = 0; s < sn.count; ++s) {  // children come before parents
    const double cols = sn.cols(s);
    own[size_t(s)] = cols * sn.rows(s) - cols * (cols - 1) / 2;
    weight[size_t(s)] += own[size_t(s)];
    if (const int p = sn.parent(s); p >= 0) {
      parent[size_t(s)] = p;
      weight[size_t(p)] += weight[size_t(s)];
      children[size_t(p)].push_back(s);
    }
  }
  std::vector<int> item(n, -1), frontier;
  double top = 0, total = 0;
  for (int s = 0; s < sn.count; ++s)
    if (parent[size_t(s)] < 0) frontier.push_back(s), total += weight[size_t(s)];
  auto heavier = [&](int x, int y) { return weight[size_t(x)] > weight[size_t(y)] || (weight[size_t(x)] == weight[size_t(y)] && x > y); };
  for (;;) {
    std::sort(frontier.begin(), frontier.end(), heavier);
    if (frontier.empty() || weight[size_t(frontier.front())] <= total / 8 || top >= total / 4) break;
    const int s = frontier.front();
    item[size_t(s)] = 0;
    top += own[size_t(s)];
    frontier.erase(frontier.begin());
    frontier.insert(frontier.end(), children[size_t(s)].begin(), children[size_t(s)].end());
  }
  for (size_t k = 0; k < frontier.size(); ++k) item[size_t(frontier[k])] = int(k) + 1;
  for (int s = sn.count - 1; s >= 0; --s)  // parents first: a subtree's members follow its root
    if (item[size_t(s)] < 0) item[size_t(s)] = item[size_t(parent[size_t(s)])];
  return item;
}

}  // namespace

Cholesky::Cholesky(const Eigen::SparseMatrix<double>& A, const std::string& what) { factor(A, what); }

void Cholesky::factor(const Eigen::SparseMatrix<double>& A, const std::string& what, double max_bytes) {
  if (A.rows() != A.cols()) fail(what, ": Cholesky needs a square matrix, got ", A.rows(), "x", A.cols());
  llt_.reset();  // a failed factor() leaves the object unfactored, not holding a stale factor
  item_.clear();
  items_ = 0;
  rows_ = 0;
  lnz_ = 0;
  flops_ = 0;
  auto llt = std::make_shared<Llt>();
  llt->cholmod().print = 0;  // CHOLMOD must not print; failures become softcut::Error
  // Eigen's default (final_asis) keeps CHOLMOD's simplicial LDL' for small
  // matrices, which factors indefinite matrices without complaint; asking for
  // a final LL' makes every non-positive pivot an error, in both the
  // simplicial and the supernodal path (tested).
  llt->cholmod().final_asis = 0;
  llt->cholmod().final_ll = 1;
  llt->analyzePattern(A);
  // The factor's nonzeros are known after the symbolic analysis: 8 bytes of
  // value and 4-8 of index each (supernodal storage pads a little more).
  const double bytes = 16.0 * llt->cholmod().lnz;
  if (bytes > max_bytes)
    fail(what, ": its Cholesky factor would take about ", int(bytes / (1 << 20)), " MiB (", A.rows(),
         " unknowns), more than the ", int(max_bytes / (1 << 20)), " MiB allowed (the sandbox's memory budget); "
         "use a coarser mesh or run with --trust");
  llt->factorize(A);
  if (llt->info() != Eigen::Success)
    fail(what, ": the stiffness matrix is singular or not positive definite; every connected part of "
               "the body needs fixed nodes");
  lnz_ = llt->cholmod().lnz;
  flops_ = llt->cholmod().fl;
  llt_ = std::move(llt);
  if (llt_->raw()->is_super) set_items();
  rows_ = int(A.rows());
}

double Cholesky::symbolic_nonzeros(const Eigen::SparseMatrix<double>& A) {
  if (A.rows() == 0) return 0;
  Llt llt;
  llt.cholmod().print = 0;
  llt.cholmod().final_asis = 0;  // as factor() asks
  llt.cholmod().final_ll = 1;
  llt.analyzePattern(A);
  return double(llt.cholmod().lnz);
}

Eigen::VectorXd Cholesky::solve(const Eigen::VectorXd& b) const {
  if (!llt_) fail("Cholesky::solve called before factor()");
  if (b.size() != rows_) fail("Cholesky::solve: right-hand side of size ", b.size(), " for a ", rows_, "-row factor");
  return llt_->solve(b);
}

Eigen::MatrixXd Cholesky::solve(const Eigen::MatrixXd& B) const {
  if (!llt_) fail("Cholesky::solve called before factor()");
  if (B.rows() != rows_) fail("Cholesky::solve: right-hand sides with ", B.rows(), " rows for a ", rows_, "-row factor");
  return llt_->solve(B);
}

Eigen::MatrixXd Cholesky::solve(const Eigen::MatrixXd& B, SolveWorkspace& ws) const {
  if (!llt_) fail("Cholesky::solve called before factor()");
  if (B.rows() != rows_) fail("Cholesky::solve: right-hand sides with ", B.rows(), " rows for a ", rows_, "-row factor");
  if (B.cols() == 0) return Eigen::MatrixXd(rows_, 0);
  cholmod_dense b{};
  b.nrow = size_t(B.rows());
  b.ncol = size_t(B.cols());
  b.nzmax = b.nrow * b.ncol;
  b.d = b.nrow;
  b.x = const_cast<double*>(B.data());  // read only (CHOLMOD's API is not const)
  b.xtype = CHOLMOD_REAL;
  b.dtype = CHOLMOD_DOUBLE;
  cholmod_dense* x = cholmod_solve(CHOLMOD_A, llt_->raw(), &b, &ws.common());
  if (!x) fail("Cholesky::solve: CHOLMOD failed (status ", ws.common().status, "; out of memory?)");
  Eigen::MatrixXd X = Eigen::Map<const Eigen::MatrixXd>(static_cast<const double*>(x->x), B.rows(), B.cols());
  cholmod_free_dense(&x, &ws.common());
  return X;
}

void Cholesky::solve_into(const Eigen::VectorXd& b, Eigen::VectorXd& x, SolveWorkspace& ws) const {
  if (!llt_) fail("Cholesky::solve called before factor()");
  if (b.size() != rows_) fail("Cholesky::solve: right-hand side of size ", b.size(), " for a ", rows_, "-row factor");
  cholmod_dense B{};
  B.nrow = size_t(b.size());
  B.ncol = 1;
  B.nzmax = B.d = B.nrow;
  B.x = const_cast<double*>(b.data());  // read only
  B.xtype = CHOLMOD_REAL;
  B.dtype = CHOLMOD_DOUBLE;
  if (!cholmod_solve2(CHOLMOD_A, llt_->raw(), &B, nullptr, &ws.X, nullptr, &ws.Y, &ws.E, &ws.common()))
    fail("Cholesky::solve: CHOLMOD failed (status ", ws.common().status, "; out of memory?)");
  x = Eigen::Map<const Eigen::VectorXd>(static_cast<const double*>(ws.X->x), b.size());
}


void Cholesky::forward_into(const Eigen::MatrixXd& B, Eigen::MatrixXd& Y, SolveWorkspace& ws) const {
  if (!llt_) fail("Cholesky::forward called before factor()");
  if (B.rows() != rows_) fail("Cholesky::forward: right-hand sides with ", B.rows(), " rows for a ", rows_, "-row factor");
  if (!llt_->raw()->is_ll) fail("Cholesky::forward: the factor is not LL' (an LDL' factor would need D)");
  const int* perm = static_cast<const int*>(llt_->raw()->Perm);
  Y.resize(B.rows(), B.cols());
  if (B.cols() == 0) return;
  for (Eigen::Index k = 0; k < B.rows(); ++k) Y.row(k) = B.row(perm ? perm[k] : k);
  cholmod_dense in = dense_view(Y.data(), Y.rows(), Y.cols());
  cholmod_dense* out = cholmod_solve(CHOLMOD_L, llt_->raw(), &in, &ws.common());
  if (!out) fail("Cholesky::forward: CHOLMOD failed (status ", ws.common().status, "; out of memory?)");
  Y = Eigen::Map<const Eigen::MatrixXd>(static_cast<const double*>(out->x), B.rows(), B.cols());
  cholmod_free_dense(&out, &ws.common());
}

void Cholesky::backward_into(const Eigen::VectorXd& y, Eigen::VectorXd& x, SolveWorkspace& ws) const {
  if (!llt_) fail("Cholesky::backward called before factor()");
  if (y.size() != rows_) fail("Cholesky::backward: a vector of size ", y.size(), " for a ", rows_, "-row factor");
  if (!llt_->raw()->is_ll) fail("Cholesky::backward: the factor is not LL' (an LDL' factor would need D)");
  cholmod_dense in = dense_view(y.data(), y.size(), 1);
  if (!cholmod_solve2(CHOLMOD_Lt, llt_->raw(), &in, nullptr, &ws.X, nullptr, &ws.Y, &ws.E, &ws.common()))
    fail("Cholesky::backward: CHOLMOD failed (status ", ws.common().status, "; out of memory?)");
  const double* t = static_cast<const double*>(ws.X->x);
  const int* perm = static_cast<const int*>(llt_->raw()->Perm);
  x.resize(y.size());
  for (Eigen::Index k = 0; k < y.size(); ++k) x[perm ? perm[k] : k] = t[k];
}

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

void Cholesky::set_items() {
  item_ = subtree_items(Supernodes(*llt_->raw()));
  items_ = item_.empty() ? 0 : *std::max_element(item_.begin(), item_.end());
}

bool Cholesky::supernodal() const { return llt_ && llt_->raw()->is_super; }

Eigen::MatrixXd Cholesky::solve(const Eigen::SparseMatrix<double>& B) const {
  return solve(Eigen::MatrixXd(B));
}

}  // namespace softcut::solve

namespace softcut::solve {

namespace {

// Why a loaded supernodal factor cannot be used, or "" when it can: what the
// solves read, in one pass over its row indices: Perm a permutation and the
// column counts in range; the supernodes tile 0..n-1, each one's rows start
// with its own columns and the rows below them increase within 0..n-1; each
// block is exactly rows x columns values and the arrays end where the last
// one does (CHOLMOD's own layout); and maxesize covers every supernode's rows
// below its columns, since cholmod_solve sizes its workspace by it.
// cholmod_check_factor is not used here: it visits every stored entry (66 ms
// of box_111132's 340 ms cache hit), lets a first supernode start past 0, the
// last end before n or a row index equal n, and does not check maxesize. A
// loaded factor is never refactored (factor() starts afresh), so maxcsize is
// not read.
std::string supernodal_problem(const cholmod_factor& L) {
  const long n = long(L.n);
  const int* perm = static_cast<const int*>(L.Perm);
  const int* count = static_cast<const int*>(L.ColCount);
  std::vector<char> seen(size_t(n), 0);
  for (long k = 0; k < n; ++k) {
    if (perm[k] < 0 || perm[k] >= n || seen[size_t(perm[k])]) return "its permutation repeats or leaves out a row";
    seen[size_t(perm[k])] = 1;
    if (count[k] < 0 || count[k] > n - k) return cat("column ", k, "'s count is out of range");
  }
  // First the small arrays, so that the pass over the row indices stays
  // inside them: supernode s's columns, rows and values follow s-1's.
  const Supernodes sn(L);
  if (sn.count < 1 && n > 0) return "it has no supernodes";
  if (sn.super[0] != 0 || sn.pi[0] != 0 || sn.px[0] != 0) return "its first supernode does not start at 0";
  long below = 0;
  for (int s = 0; s < sn.count; ++s) {
    const long nscol = sn.cols(s), nsrow = sn.rows(s);
    if (nscol < 1 || nsrow < nscol) return cat("supernode ", s, " has fewer rows than columns");
    if (long(sn.px[s + 1]) - sn.px[s] != nsrow * nscol) return cat("supernode ", s, "'s values are not rows x columns");
    below = std::max(below, nsrow - nscol);
  }
  if (sn.super[sn.count] != n) return "its supernodes do not cover its columns";
  if (size_t(std::max(1, sn.pi[sn.count])) != L.ssize || size_t(std::max(1, sn.px[sn.count])) != L.xsize)
    return "its row or value arrays do not end where its last supernode does";
  for (int s = 0; s < sn.count; ++s) {
    const int* rows = sn.Ls + sn.pi[s];
    for (long i = 0; i < sn.rows(s); ++i)
      if (i < sn.cols(s) ? rows[i] != sn.super[s] + i : (rows[i] >= n || rows[i] <= rows[i - 1]))
        return cat("supernode ", s, "'s row indices are out of place");
  }
  if (size_t(below) > L.maxesize) return "its maxesize is smaller than a supernode's rows below its columns";
  return {};
}

// The factor's layout, as saved (CHOLMOD int version, real LL').
struct FactorHeader {
  std::int64_t n = 0, minor = 0, is_super = 0, ordering = 0, is_monotonic = 0;
  std::int64_t nzmax = 0;                                           // simplicial
  std::int64_t nsuper = 0, ssize = 0, xsize = 0, maxcsize = 0, maxesize = 0;  // supernodal
};

template <class T>
T* alloc(size_t n, cholmod_common& c) {
  void* p = cholmod_malloc(std::max<size_t>(n, 1), sizeof(T), &c);
  if (!p) fail("Cholesky::load: out of memory for ", n, " entries");
  return static_cast<T*>(p);
}

}  // namespace

void Cholesky::save(BinaryWriter& w) const {
  if (!llt_) fail("Cholesky::save called before factor()");
  const cholmod_factor* L = llt_->raw();
  if (!L->is_ll || L->xtype != CHOLMOD_REAL || L->itype != CHOLMOD_INT)
    fail("Cholesky::save: only real LL' factors with int indices are saved");
  FactorHeader h;
  h.n = std::int64_t(L->n), h.minor = std::int64_t(L->minor), h.is_super = L->is_super, h.ordering = L->ordering;
  h.is_monotonic = L->is_monotonic;
  h.nzmax = std::int64_t(L->nzmax), h.nsuper = std::int64_t(L->nsuper), h.ssize = std::int64_t(L->ssize);
  h.xsize = std::int64_t(L->xsize), h.maxcsize = std::int64_t(L->maxcsize), h.maxesize = std::int64_t(L->maxesize);
  w.pod(h);
  const size_t n = size_t(L->n);
  w.array(static_cast<const int*>(L->Perm), n);
  w.array(static_cast<const int*>(L->ColCount), n);
  if (L->is_super) {
    const size_t ns = size_t(L->nsuper) + 1;
    w.array(static_cast<const int*>(L->super), ns);
    w.array(static_cast<const int*>(L->pi), ns);
    w.array(static_cast<const int*>(L->px), ns);
    w.array(static_cast<const int*>(L->s), size_t(L->ssize));
    w.array(static_cast<const double*>(L->x), size_t(L->xsize));
  } else {
    w.array(static_cast<const int*>(L->p), n + 1);
    w.array(static_cast<const int*>(L->i), size_t(L->nzmax));
    w.array(static_cast<const double*>(L->x), size_t(L->nzmax));
    w.array(static_cast<const int*>(L->nz), n);
    w.array(static_cast<const int*>(L->next), n + 2);
    w.array(static_cast<const int*>(L->prev), n + 2);
  }
  w.pod(lnz_);
}

void Cholesky::load(BinaryReader& r) {
  llt_.reset();
  item_.clear();
  items_ = 0;
  rows_ = 0;
  lnz_ = 0;
  flops_ = 0;
  FactorHeader h;
  r.pod(h);
  const std::string& what = r.what();
  // Every size is checked against the bytes left in the file before it is
  // allocated (BinaryReader::count), so a corrupt header cannot ask for more.
  if (h.n < 0 || h.n > (std::int64_t(1) << 31) - 3 || h.minor != h.n || (h.is_super != 0 && h.is_super != 1) ||
      h.nzmax < 0 || h.nsuper < 0 || h.ssize < 0 || h.xsize < 0 || h.maxcsize < 0 || h.maxesize < 0)
    fail(what, ": the saved Cholesky factor has an impossible header");
  auto llt = std::make_shared<Llt>();
  llt->cholmod().print = 0;
  cholmod_common& c = llt->cholmod();
  const size_t n = size_t(h.n);
  cholmod_factor* L = cholmod_allocate_factor(n, &c);
  if (!L) fail(what, ": out of memory for a factor of ", n, " rows");
  auto read_ints = [&](void*& dst, size_t count) {
    if (r.count(sizeof(int)) != count) fail(what, ": an array of the saved factor has the wrong size");
    int* p = alloc<int>(count, c);
    dst = p;
    r.bytes(p, count * sizeof(int));
  };
  auto read_doubles = [&](void*& dst, size_t count) {
    if (r.count(sizeof(double)) != count) fail(what, ": an array of the saved factor has the wrong size");
    double* p = alloc<double>(count, c);
    dst = p;
    r.bytes(p, count * sizeof(double));
  };
  try {
    r.array_into(static_cast<int*>(L->Perm), n);
    r.array_into(static_cast<int*>(L->ColCount), n);
    L->ordering = int(h.ordering);
    L->is_monotonic = int(h.is_monotonic);
    L->is_ll = 1;
    L->xtype = CHOLMOD_REAL;
    if (h.is_super) {
      L->is_super = 1;
      L->nsuper = size_t(h.nsuper), L->ssize = size_t(h.ssize), L->xsize = size_t(h.xsize);
      L->maxcsize = size_t(h.maxcsize), L->maxesize = size_t(h.maxesize);
      read_ints(L->super, L->nsuper + 1);
      read_ints(L->pi, L->nsuper + 1);
      read_ints(L->px, L->nsuper + 1);
      read_ints(L->s, L->ssize);
      read_doubles(L->x, L->xsize);
    } else {
      L->nzmax = size_t(h.nzmax);
      read_ints(L->p, n + 1);
      read_ints(L->i, L->nzmax);
      read_doubles(L->x, L->nzmax);
      read_ints(L->nz, n);
      read_ints(L->next, n + 2);
      read_ints(L->prev, n + 2);
    }
    L->minor = n;
    double lnz = 0;
    r.pod(lnz);
    if (L->is_super) {
      const std::string why = supernodal_problem(*L);
      if (!why.empty()) fail(what, ": the saved Cholesky factor is inconsistent: ", why);
    } else if (!cholmod_check_factor(L, &c)) {  // simplicial: small factors, one pass
      fail(what, ": the saved Cholesky factor is inconsistent (CHOLMOD status ", c.status, ")");
    }
    llt->adopt(L);
    L = nullptr;
    llt_ = std::move(llt);
    if (llt_->raw()->is_super) set_items();
    rows_ = int(n);
    lnz_ = lnz;
  } catch (...) {
    // A partly filled factor: cholmod_free_factor frees by the fields set so
    // far; arrays not read yet are null.
    if (L) cholmod_free_factor(&L, &c);
    throw;
  }
}

}  // namespace softcut::solve
