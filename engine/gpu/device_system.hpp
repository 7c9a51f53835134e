#pragma once
// The device's copy of a BlockSystem for the compute-shader CG: its matrix
// buffers (block row pointers, block columns, 3x3 block values, inverse
// diagonal blocks, the dense block) at the binding points of cg_layout, kept
// in step with the host's system by sending what changed only: the changed
// value runs of an unchanged pattern; after a cut, the block rows both
// systems share moved on the device and the rest sent (DESIGN.md §3).
#include <cstddef>
#include <vector>

#include "gpu/block_system.hpp"
#include "gpu/block_system_diff.hpp"
#include "gpu/compute_program.hpp"

namespace softcut::gpu {

// What the last DeviceSystem::set did to the device copy of the matrix.
struct SystemUpload {
  std::size_t sent_bytes = 0;   // host -> device
  std::size_t moved_bytes = 0;  // device -> device (kept rows copied to their new place)
  std::size_t full_bytes = 0;   // what a full upload of the new system sends
  bool incremental = false;     // kept the shared rows of a changed pattern
  bool reallocated = false;     // some device buffer was (re)allocated
};

// Host doubles as device scalars (float, or double with fp64), and back.
std::vector<unsigned char> to_device(const double* v, std::size_t n, bool fp64);
std::vector<double> from_device(const std::vector<unsigned char>& bytes, bool fp64);

class DeviceSystem {
 public:
  explicit DeviceSystem(bool fp64) : fp64_(fp64) {}

  // Makes the device copy equal `s` (the context must be current). When the
  // block pattern is unchanged only the changed byte ranges of the values and
  // the dense block are sent. When it changed, the block rows both systems
  // share (diff_block_systems) stay on the device: those whose offset changed
  // are moved through a scratch buffer, their block columns renumbered by
  // `shift` (cg_shaders::shift_cols); only row_ptr and the other rows are
  // sent, and the dense block stays when its size did. Buffers grow with 25%
  // spare capacity. A full upload is made when that is not cheaper. Returns
  // the bytes sent.
  std::size_t set(const BlockSystem& s, const ComputeProgram& shift);

  bool has_system() const { return have_; }
  const BlockSystem& host() const { return cached_; }  // what the device holds, values in double
  const SystemUpload& last_upload() const { return upload_; }
  // The solver's vectors for the new system needed a fresh allocation too.
  void note_reallocated() { upload_.reallocated = true; }
  // The matrix as the device holds it (values in device precision, as double).
  BlockSystem read_back() const;
  // Binds the matrix buffers to their cg_layout binding points.
  void bind() const;

 private:
  std::size_t scalar() const { return fp64_ ? 8 : 4; }
  std::size_t upload_changed(StorageBuffer& dst, const std::vector<double>& old_v, const std::vector<double>& new_v,
                             std::size_t run);
  void reserve(StorageBuffer& b, std::size_t bytes);
  void upload_full(StorageBuffer& b, const void* data, std::size_t bytes);
  void set_incremental(const BlockSystem& s, const BlockSystemDiff& d, const ComputeProgram& shift);

  bool fp64_;
  StorageBuffer row_ptr_, col_, values_, dense_, diag_inv_;
  StorageBuffer scratch_;  // staging for kept runs that move within a buffer
  BlockSystem cached_;
  bool have_ = false;
  SystemUpload upload_;
};

}  // namespace softcut::gpu
