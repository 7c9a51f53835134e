#include "hybrid/columns.hpp"

#include <doctest/doctest.h>

#include <random>

#include "fixtures.hpp"
#include "hybrid/precompute.hpp"

using namespace softcut;
using namespace softcut::hybrid;
using softcut::test::HybridCase;

namespace {

double rel(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return b.norm() > 0 ? (a - b).norm() / b.norm() : (a - b).norm();
}

// A case with surface and interface nodes, and its dense-storage model (the
// independent truth: columns of the precomputed K*^-1 and (KI2 K22^-1)[:, s]).
struct Pair {
  HybridCase c;
  Model dense, product;
};

Pair make_pair(std::mt19937& rng) {
  for (;;) {
    HybridCase c = test::random_case(rng, 0);
    if (c.partition.surface.size() < 8 || c.partition.interface.empty()) continue;
    PrecomputeOptions pd, pp;
    pd.storage = Storage::dense;
    pp.storage = Storage::product;
    Model d = precompute(c.mesh, c.material, c.partition, pd);
    Model p = precompute(c.mesh, c.material, c.partition, pp);
    return {std::move(c), std::move(d), std::move(p)};
  }
}

}  // namespace

TEST_SUITE("hybrid/columns") {
  TEST_CASE("columns on demand equal the dense precomputed columns, first touch and cached") {
    std::mt19937 rng(77);
    for (int trial = 0; trial < 5; ++trial) {
      const Pair P = make_pair(rng);
      ColumnCache cache(P.product, 1e9);
      for (int round = 0; round < 2; ++round)
        for (int pos = 0; pos < P.product.ns(); pos += 3) {
          const auto col = cache.get(pos);
          CHECK(rel(col->Kstar_inv, P.dense.Kstar_inv.middleCols<3>(3 * pos)) <= 1e-12);
          CHECK(rel(col->KI2_K22inv, P.dense.KI2_K22inv_s.middleCols<3>(3 * pos)) <= 1e-12);
        }
      const ColumnStats st = cache.stats();
      const int touched = (P.product.ns() + 2) / 3;
      CHECK(st.first_touches == touched);
      CHECK(st.hits == touched);
      CHECK(st.cached_nodes == touched);
      CHECK(st.evicted == 0);
      CHECK(st.bytes == doctest::Approx(touched * 8.0 * 3 * (3 * P.product.ns() + 3 * P.product.ni())));
    }
  }

  TEST_CASE("prefetched columns are computed off the calling thread and equal the first-touch ones") {
    std::mt19937 rng(78);
    const Pair P = make_pair(rng);
    ColumnCache a(P.product, 1e9), b(P.product, 1e9);
    std::vector<int> all(size_t(P.product.ns()));
    for (size_t k = 0; k < all.size(); ++k) all[k] = int(k);
    a.prefetch(all);
    a.prefetch(all);  // queued twice: computed once
    a.wait_idle();
    ColumnStats st = a.stats();
    CHECK(st.prefetched == P.product.ns());
    CHECK(st.cached_nodes == P.product.ns());
    for (int pos : all) {
      const auto x = a.get(pos), y = b.get(pos);
      CHECK(x->Kstar_inv == y->Kstar_inv);  // the same bits on either thread: runs stay deterministic
      CHECK(x->KI2_K22inv == y->KI2_K22inv);
    }
    st = a.stats();
    CHECK(st.hits == P.product.ns());
    CHECK(st.first_touches == 0);
    // get() of a queued node does not wait for the queue: it takes the node.
    ColumnCache c(P.product, 1e9);
    c.prefetch(all);
    const auto last = c.get(all.back());
    CHECK(rel(last->Kstar_inv, P.dense.Kstar_inv.middleCols<3>(3 * all.back())) <= 1e-12);
    c.wait_idle();
    CHECK(c.stats().cached_nodes == P.product.ns());
  }

  TEST_CASE("the cache stays within its bound and evicts the least recently used node") {
    std::mt19937 rng(79);
    const Pair P = make_pair(rng);
    const double per_node = 8.0 * 3 * (3 * P.product.ns() + 3 * P.product.ni());
    ColumnCache cache(P.product, 3.5 * per_node);  // room for 3 nodes
    for (int pos : {0, 1, 2}) cache.get(pos);
    cache.get(0);  // 1 is now the least recently used
    cache.get(3);
    ColumnStats st = cache.stats();
    CHECK(st.cached_nodes == 3);
    CHECK(st.evicted == 1);
    CHECK(st.bytes <= st.max_bytes);
    cache.get(0), cache.get(2), cache.get(3);
    CHECK(cache.stats().hits == 1 + 3);
    cache.get(1);  // evicted: computed again, and still right
    st = cache.stats();
    CHECK(st.first_touches == 5);
    CHECK(rel(cache.get(1)->Kstar_inv, P.dense.Kstar_inv.middleCols<3>(3)) <= 1e-12);
    CHECK_THROWS_WITH(cache.get(P.product.ns()), doctest::Contains("out of range"));
    CHECK_THROWS_WITH(cache.prefetch({-1}), doctest::Contains("out of range"));
  }

  TEST_CASE("a frame's first touches come in batches, each node with the bits it has alone") {
    // A box large enough for a supernodal K22 (the two-thread backward) and
    // a random case (simplicial); more nodes than one batch holds.
    const HybridCase b = test::supernodal_case(12, fem::Material{3e3, 0.45});
    PrecomputeOptions pd, pp;
    pd.storage = Storage::dense;
    pp.storage = Storage::product;
    const Model box_dense = precompute(b.mesh, b.material, b.partition, pd);
    const Model box = precompute(b.mesh, b.material, b.partition, pp);
    REQUIRE(box.K22.supernodal());
    std::mt19937 rng(80);
    const Pair P = make_pair(rng);
    for (const auto& [model, dense] : {std::pair{&box, &box_dense}, std::pair{&P.product, &P.dense}}) {
      std::vector<int> nodes;
      for (int pos = 0; pos < model->ns() && int(nodes.size()) < ColumnCache::kMaxBatch + 5; pos += 5)
        nodes.push_back(pos);
      nodes.push_back(nodes.front());  // named twice: computed once
      ColumnCache batched(*model, 1e9), alone(*model, 1e9);
      batched.share_helper(std::make_shared<HelperThread>());
      batched.ensure(nodes);
      CHECK(batched.stats().first_touches == long(nodes.size()) - 1);
      CHECK(batched.stats().cached_nodes == int(nodes.size()) - 1);
      batched.ensure(nodes);  // all cached: nothing to do
      CHECK(batched.stats().first_touches == long(nodes.size()) - 1);
      for (int pos : nodes) {
        const auto x = batched.get(pos), y = alone.get(pos);
        CHECK(x->Kstar_inv == y->Kstar_inv);
        CHECK(x->KI2_K22inv == y->KI2_K22inv);
        CHECK(rel(x->Kstar_inv, dense->Kstar_inv.middleCols<3>(3 * pos)) <= 1e-12);
        CHECK(rel(x->KI2_K22inv, dense->KI2_K22inv_s.middleCols<3>(3 * pos)) <= 1e-12);
      }
      CHECK(batched.stats().hits == long(nodes.size()));
      CHECK_THROWS_WITH(batched.ensure(std::vector<int>{0, model->ns()}), doctest::Contains("out of range"));
      CHECK(batched.stats().cached_nodes == int(nodes.size()) - 1);
    }
  }
}
