#include "gpu/block_system_diff.hpp"

#include <doctest/doctest.h>

#include <random>

#include "random_block_system.hpp"

using namespace softcut;

namespace {

// What the device does with a diff: the new system, with the kept runs copied
// over from the old one (columns renumbered). Must give the new arrays exactly.
gpu::BlockSystem rebuild(const gpu::BlockSystem& o, const gpu::BlockSystem& n, const gpu::BlockSystemDiff& d) {
  gpu::BlockSystem r = n;
  std::size_t last_to = 0;
  for (const auto& run : d.blocks) {
    CHECK(run.to >= last_to);  // increasing, not overlapping
    last_to = run.to + run.count;
    for (std::size_t k = 0; k < run.count; ++k) {
      std::uint32_t c = o.col[run.from + k];
      if (c >= d.col_threshold) c = std::uint32_t(std::int64_t(c) + d.col_shift);
      r.col[run.to + k] = c;
      std::copy_n(o.values.begin() + std::ptrdiff_t(9 * (run.from + k)), 9,
                  r.values.begin() + std::ptrdiff_t(9 * (run.to + k)));
    }
  }
  last_to = 0;
  for (const auto& run : d.rows) {
    CHECK(run.to >= last_to);
    last_to = run.to + run.count;
    for (std::size_t i = 0; i < run.count; ++i)
      std::copy_n(o.diag_inverse.begin() + std::ptrdiff_t(9 * (run.from + i)), 9,
                  r.diag_inverse.begin() + std::ptrdiff_t(9 * (run.to + i)));
  }
  CHECK(std::uint64_t(last_to) <= std::uint64_t(n.num_blocks));
  return r;
}

}  // namespace

TEST_SUITE("gpu/block_system_diff") {
  TEST_CASE("the same system is kept whole") {
    std::mt19937 rng(1);
    const auto s = test::block_system(test::random_graph(rng, 30, 2));
    const auto d = gpu::diff_block_systems(s, s);
    CHECK(d.kept_blocks() == s.col.size());
    CHECK(d.kept_rows() == std::size_t(s.num_blocks));
    CHECK(d.blocks.size() == 1);
    CHECK(d.col_shift == 0);
  }

  TEST_CASE("kept runs rebuild the new system exactly, and an insertion keeps most of it") {
    std::mt19937 rng(2);
    int local_edits = 0;
    for (int trial = 0; trial < 60; ++trial) {
      test::NodeGraph g = test::random_graph(rng, 20 + int(rng() % 40), int(rng() % 3));
      const auto before = test::block_system(g);
      const int kind = trial % 3, count = 1 + int(rng() % 4);
      const int free_nodes = g.num_nodes - g.dense_nodes;
      const int at = kind == 1 ? free_nodes : int(rng() % unsigned(free_nodes - count));
      if (kind == 2) test::remove_nodes(g, at, count);
      else test::insert_nodes(g, rng, at, count);
      const auto after = test::block_system(g);
      const auto d = gpu::diff_block_systems(before, after);
      CAPTURE(trial);
      CAPTURE(kind);
      const auto r = rebuild(before, after, d);
      CHECK(r.col == after.col);
      CHECK(r.values == after.values);
      CHECK(r.diag_inverse == after.diag_inverse);
      if (kind != 2) {  // an insertion touches rows near `at` and those of its neighbours only
        ++local_edits;
        CHECK(d.col_shift == count);
        CHECK(double(d.kept_blocks()) >= 0.8 * double(before.col.size()));
      }
    }
    CHECK(local_edits == 40);
  }
}
