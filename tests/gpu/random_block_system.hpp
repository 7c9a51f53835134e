#pragma once
// Random SPD block systems built from a node graph, and the edits a cut makes
// to one (nodes inserted in the middle, appended, removed; a few edges
// rewired), for the incremental-upload tests. Each edge's coupling comes from
// its own seed, so an edge that survives an edit keeps its exact values.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <algorithm>
#include <random>
#include <vector>

#include "gpu/block_system.hpp"

namespace softcut::test {

struct NodeGraph {
  int num_nodes = 0;
  struct Edge {
    int a, b;
    unsigned seed;
  };
  std::vector<Edge> edges;
  int dense_nodes = 0;  // dense SPD block on the last dense_nodes nodes (fixed values)
};

inline NodeGraph random_graph(std::mt19937& rng, int nodes, int dense_nodes) {
  NodeGraph g;
  g.num_nodes = nodes;
  g.dense_nodes = dense_nodes;
  for (int a = 0; a < nodes; ++a)
    for (int k = 0; k < 3; ++k) {
      const int b = int(rng() % unsigned(nodes));
      if (b != a) g.edges.push_back({a, b, unsigned(rng())});
    }
  return g;
}

// Inserts `count` nodes before node `at` (at = num_nodes appends), each tied
// to two nodes near `at` (as cut nodes are tied to their neighbours).
inline void insert_nodes(NodeGraph& g, std::mt19937& rng, int at, int count) {
  for (auto& e : g.edges) {
    if (e.a >= at) e.a += count;
    if (e.b >= at) e.b += count;
  }
  g.num_nodes += count;
  for (int k = 0; k < count; ++k)
    for (int t = 0; t < 2; ++t) {
      const int lo = std::max(at - 3, 0), hi = std::min(at + count + 3, g.num_nodes);
      int b = lo + int(rng() % unsigned(hi - lo));
      if (b == at + k) b = b + 1 < hi ? b + 1 : lo;
      if (b != at + k) g.edges.push_back({at + k, b, unsigned(rng())});
    }
}

// Removes nodes [at, at + count) and their edges.
inline void remove_nodes(NodeGraph& g, int at, int count) {
  std::vector<NodeGraph::Edge> kept;
  for (auto e : g.edges) {
    if ((e.a >= at && e.a < at + count) || (e.b >= at && e.b < at + count)) continue;
    if (e.a >= at + count) e.a -= count;
    if (e.b >= at + count) e.b -= count;
    kept.push_back(e);
  }
  g.edges = std::move(kept);
  g.num_nodes -= count;
}

// K = sum over edges of [C -C; -C C] (C = B B^T + I, B from the edge's seed)
// + 10 I, plus the dense block.
inline gpu::BlockSystem block_system(const NodeGraph& g) {
  std::vector<Eigen::Triplet<double>> trips;
  for (int i = 0; i < 3 * g.num_nodes; ++i) trips.emplace_back(i, i, 10.0);
  for (const auto& e : g.edges) {
    std::mt19937 r(e.seed);
    std::uniform_real_distribution<double> u(-1, 1);
    Eigen::Matrix3d B;
    for (int i = 0; i < 9; ++i) B(i / 3, i % 3) = u(r);
    const Eigen::Matrix3d C = B * B.transpose() + Eigen::Matrix3d::Identity();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        trips.emplace_back(3 * e.a + i, 3 * e.a + j, C(i, j));
        trips.emplace_back(3 * e.b + i, 3 * e.b + j, C(i, j));
        trips.emplace_back(3 * e.a + i, 3 * e.b + j, -C(i, j));
        trips.emplace_back(3 * e.b + i, 3 * e.a + j, -C(i, j));
      }
  }
  Eigen::SparseMatrix<double> K(3 * g.num_nodes, 3 * g.num_nodes);
  K.setFromTriplets(trips.begin(), trips.end());
  const int m = 3 * g.dense_nodes;
  Eigen::MatrixXd D = Eigen::MatrixXd::Identity(m, m) * 5.0;
  for (int i = 0; i + 1 < m; ++i) D(i, i + 1) = D(i + 1, i) = -1.0;
  return gpu::make_block_system(K, m > 0 ? &D : nullptr);
}

}  // namespace softcut::test
