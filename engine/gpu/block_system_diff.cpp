#include "gpu/block_system_diff.hpp"

#include <algorithm>
#include <cstring>

namespace softcut::gpu {

namespace {

// The kept blocks must agree on one renumbering col -> col + shift for
// col >= T: T lies in (max unshifted old column, min shifted old column].
struct ColumnMap {
  std::int64_t shift;
  std::int64_t max_unshifted = -1;
  std::int64_t min_shifted;

  // Whether old block (col co) may become new block (col cn) under the map so
  // far; narrows the map when it may.
  bool accept(std::uint32_t co, std::uint32_t cn) {
    if (shift == 0) return co == cn;
    if (cn == co) {
      if (std::int64_t(co) >= min_shifted) return false;
      max_unshifted = std::max(max_unshifted, std::int64_t(co));
      return true;
    }
    if (std::int64_t(cn) == std::int64_t(co) + shift) {
      if (std::int64_t(co) <= max_unshifted) return false;
      min_shifted = std::min(min_shifted, std::int64_t(co));
      return true;
    }
    return false;
  }
};

bool same9(const std::vector<double>& a, std::size_t i, const std::vector<double>& b, std::size_t j) {
  return std::memcmp(a.data() + 9 * i, b.data() + 9 * j, 9 * sizeof(double)) == 0;
}

// Appends old [from, + count) -> new [to, + count), merged with the last run when contiguous.
void add_run(std::vector<BlockSystemDiff::Run>& runs, std::size_t from, std::size_t to, std::size_t count) {
  if (count == 0) return;
  if (!runs.empty() && runs.back().from + runs.back().count == from && runs.back().to + runs.back().count == to)
    runs.back().count += count;
  else
    runs.push_back({from, to, count});
}

std::size_t total(const std::vector<BlockSystemDiff::Run>& runs) {
  std::size_t n = 0;
  for (const auto& r : runs) n += r.count;
  return n;
}

}  // namespace

std::size_t BlockSystemDiff::kept_blocks() const { return total(blocks); }
std::size_t BlockSystemDiff::kept_rows() const { return total(rows); }

BlockSystemDiff diff_block_systems(const BlockSystem& o, const BlockSystem& n) {
  BlockSystemDiff d;
  const std::size_t nnz_o = o.col.size(), nnz_n = n.col.size();
  const std::int64_t shift = std::int64_t(n.num_blocks) - std::int64_t(o.num_blocks);
  ColumnMap map{shift, -1, std::int64_t(o.num_blocks)};
  const std::size_t lim = std::min(nnz_o, nnz_n);
  auto match = [&](std::size_t ko, std::size_t kn) {
    return same9(o.values, ko, n.values, kn) && map.accept(o.col[ko], n.col[kn]);
  };
  std::size_t suffix = 0, prefix = 0;
  while (suffix < lim && match(nnz_o - 1 - suffix, nnz_n - 1 - suffix)) ++suffix;
  while (prefix < lim - suffix && match(prefix, prefix)) ++prefix;
  d.col_shift = shift;
  d.col_threshold = std::uint32_t(map.min_shifted);

  // Every new row against the old row it comes from under the renumbering.
  const std::int64_t T = map.min_shifted;
  auto renumber = [&](std::uint32_t c) { return std::int64_t(c) >= T ? std::int64_t(c) + shift : std::int64_t(c); };
  for (std::int64_t I = 0; I < n.num_blocks; ++I) {
    const std::int64_t Io = I < T ? I : I - shift;
    if (Io < 0 || Io >= o.num_blocks || (I >= T && Io < T)) continue;  // a row inserted at T
    if (same9(o.diag_inverse, std::size_t(Io), n.diag_inverse, std::size_t(I)))
      add_run(d.rows, std::size_t(Io), std::size_t(I), 1);
    const std::size_t ko = o.row_ptr[std::size_t(Io)], kn = n.row_ptr[std::size_t(I)];
    const std::size_t len = o.row_ptr[std::size_t(Io) + 1] - ko;
    if (n.row_ptr[std::size_t(I) + 1] - kn != len) continue;
    bool same = true;
    for (std::size_t k = 0; k < len && same; ++k)
      same = renumber(o.col[ko + k]) == std::int64_t(n.col[kn + k]) && same9(o.values, ko + k, n.values, kn + k);
    if (same) add_run(d.blocks, ko, kn, len);
  }
  return d;
}

}  // namespace softcut::gpu
