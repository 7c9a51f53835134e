#include "solve/supernodes.hpp"

namespace softcut::solve {

namespace {

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

}  // namespace

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

}  // namespace softcut::solve
