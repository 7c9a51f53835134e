#pragma once
// What two BlockSystems share, so that a device copy of the old one can be
// turned into the new one by moving the shared runs on the device and sending
// only the rest. A cut appends nodes at the end of set 1, just before the
// interface nodes, and rewrites the rows near the cut: every other block row
// survives, at the same row (set 1) or shifted by the number of new nodes
// (interface rows), its blocks at a new offset where earlier rows changed
// length, and its block columns past the insertion point renumbered.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "gpu/block_system.hpp"

namespace softcut::gpu {

struct BlockSystemDiff {
  struct Run {
    std::size_t from = 0;   // first unit in the old array
    std::size_t to = 0;     // first unit in the new array
    std::size_t count = 0;  // units
  };
  // Kept blocks (an entry of col and 9 of values each), increasing `to`,
  // and kept rows of diag_inverse (9 entries each), increasing `to`.
  std::vector<Run> blocks, rows;
  // Renumbering of kept block columns: col >= col_threshold gets col_shift
  // added (col_shift = nb_new - nb_old). Old block row I becomes new row I
  // below col_threshold and I + col_shift from there on.
  std::uint32_t col_threshold = 0;
  std::int64_t col_shift = 0;

  std::size_t kept_blocks() const;
  std::size_t kept_rows() const;
};

// The insertion point is found from the longest common suffix and prefix of
// the block arrays (aligned at the ends); then every new row that maps to an
// old row with the same length, renumbered columns and bit-identical values
// is kept (and its diag_inverse row when bit-identical).
BlockSystemDiff diff_block_systems(const BlockSystem& old_system, const BlockSystem& new_system);

}  // namespace softcut::gpu
