#include "gpu/device_system.hpp"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <cstring>
#include <utility>

#include "core/error.hpp"
#include "gpu/cg_layout.hpp"

namespace softcut::gpu {
namespace L = cg_layout;

std::vector<unsigned char> to_device(const double* v, std::size_t n, bool fp64) {
  std::vector<unsigned char> out(n * (fp64 ? 8 : 4));
  if (fp64) {
    std::memcpy(out.data(), v, n * 8);
  } else {
    auto* f = reinterpret_cast<float*>(out.data());
    for (std::size_t i = 0; i < n; ++i) f[i] = float(v[i]);
  }
  return out;
}

std::vector<double> from_device(const std::vector<unsigned char>& bytes, bool fp64) {
  const std::size_t n = bytes.size() / (fp64 ? 8 : 4);
  std::vector<double> out(n);
  if (fp64) {
    std::memcpy(out.data(), bytes.data(), n * 8);
  } else {
    const auto* f = reinterpret_cast<const float*>(bytes.data());
    for (std::size_t i = 0; i < n; ++i) out[i] = f[i];
  }
  return out;
}

namespace {

std::uint32_t groups_for(std::uint32_t items) { return (items + L::kGroupSize - 1) / L::kGroupSize; }

// Turns the device array `b` into the new one (new_len units of `unit`
// bytes). Kept runs that stay at their offset are left alone; the others
// are staged through `scratch` (GL forbids overlapping copies within one
// buffer, and runs may move either way), all read before any is written.
// When the array outgrows its buffer, every run is copied into a fresh,
// larger one instead. The gaps between runs are sent from the host,
// `gap(first, count, out)` giving their bytes.
template <class Gap>
void apply_runs(StorageBuffer& b, StorageBuffer& scratch, SystemUpload& upload, std::size_t unit, std::size_t new_len,
                const std::vector<BlockSystemDiff::Run>& runs, Gap gap) {
  if (new_len * unit > b.capacity()) {
    StorageBuffer grown;
    grown.allocate(new_len * unit + new_len * unit / 4);
    for (const auto& r : runs) grown.copy_from(b, r.from * unit, r.to * unit, r.count * unit);
    for (const auto& r : runs) upload.moved_bytes += r.count * unit;
    b = std::move(grown);
    upload.reallocated = true;
  } else {
    std::size_t staged = 0;
    for (const auto& r : runs) staged += r.from != r.to ? r.count * unit : 0;
    if (staged > 0) {
      if (scratch.capacity() < staged) scratch.allocate(staged + staged / 4);
      std::size_t at = 0;
      for (const auto& r : runs)
        if (r.from != r.to) {
          scratch.copy_from(b, r.from * unit, at, r.count * unit);
          at += r.count * unit;
        }
      at = 0;
      for (const auto& r : runs)
        if (r.from != r.to) {
          b.copy_from(scratch, at, r.to * unit, r.count * unit);
          at += r.count * unit;
        }
      upload.moved_bytes += staged;
    }
  }
  std::vector<unsigned char> bytes;
  std::size_t next = 0;  // first unit not yet written
  auto send = [&](std::size_t first, std::size_t count) {
    if (count == 0) return;
    gap(first, count, bytes);
    b.upload_range(first * unit, bytes.data(), bytes.size());
    upload.sent_bytes += bytes.size();
  };
  for (const auto& r : runs) {
    send(next, r.to - next);
    next = r.to + r.count;
  }
  send(next, new_len - next);
}

// Bytes an incremental update sends (row_ptr whole, the gaps; dense as a full upload would).
std::size_t incremental_bytes(const BlockSystem& s, const BlockSystemDiff& d, std::size_t scalar) {
  return 4 * s.row_ptr.size() + (s.col.size() - d.kept_blocks()) * (4 + 9 * scalar) +
         (std::size_t(s.num_blocks) - d.kept_rows()) * 9 * scalar;
}

}  // namespace

// Uploads only the runs of `run` values (9-value blocks, or dense rows) that differ.
std::size_t DeviceSystem::upload_changed(StorageBuffer& dst, const std::vector<double>& old_v,
                                         const std::vector<double>& new_v, std::size_t run) {
  std::size_t sent = 0;
  const std::size_t units = new_v.size() / run;
  std::size_t u = 0;
  while (u < units) {
    if (std::memcmp(&old_v[u * run], &new_v[u * run], run * sizeof(double)) == 0) {
      ++u;
      continue;
    }
    std::size_t e = u + 1;
    while (e < units && std::memcmp(&old_v[e * run], &new_v[e * run], run * sizeof(double)) != 0) ++e;
    const auto bytes = to_device(&new_v[u * run], (e - u) * run, fp64_);
    dst.upload_range(u * run * scalar(), bytes.data(), bytes.size());
    sent += bytes.size();
    u = e;
  }
  return sent;
}

// Room for `bytes`, with 25% spare so that a growing system (cut after
// cut) does not reallocate every time; contents are dropped when it grows.
void DeviceSystem::reserve(StorageBuffer& b, std::size_t bytes) {
  if (b.capacity() < bytes || b.capacity() == 0) {
    b.allocate(bytes + bytes / 4);
    upload_.reallocated = true;
  }
}

void DeviceSystem::upload_full(StorageBuffer& b, const void* data, std::size_t bytes) {
  reserve(b, bytes);
  b.upload_range(0, data, bytes);
  upload_.sent_bytes += bytes;
}

void DeviceSystem::set_incremental(const BlockSystem& s, const BlockSystemDiff& d, const ComputeProgram& shift) {
  upload_full(row_ptr_, s.row_ptr.data(), 4 * s.row_ptr.size());
  // Renumbers every block column of the old array on the device (kept runs
  // need it; the others are overwritten).
  const std::size_t count = cached_.col.size();
  if (d.col_shift != 0 && d.col_threshold < std::uint32_t(cached_.num_blocks) && count > 0) {
    col_.bind(L::kCol);
    shift.dispatch(groups_for(std::uint32_t(count)),
                   {{"k_first", 0}, {"k_last", std::uint32_t(count)}, {"threshold", d.col_threshold},
                    {"delta", std::uint32_t(d.col_shift)}});  // modulo 2^32: negative shifts wrap
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);  // before the copies read it
  }
  apply_runs(col_, scratch_, upload_, 4, s.col.size(), d.blocks,
             [&](std::size_t first, std::size_t n, std::vector<unsigned char>& out) {
               out.resize(4 * n);
               std::memcpy(out.data(), s.col.data() + first, 4 * n);
             });
  apply_runs(values_, scratch_, upload_, 9 * scalar(), s.col.size(), d.blocks,
             [&](std::size_t first, std::size_t n, std::vector<unsigned char>& out) {
               out = to_device(s.values.data() + 9 * first, 9 * n, fp64_);
             });
  apply_runs(diag_inv_, scratch_, upload_, 9 * scalar(), std::size_t(s.num_blocks), d.rows,
             [&](std::size_t first, std::size_t n, std::vector<unsigned char>& out) {
               out = to_device(s.diag_inverse.data() + 9 * first, 9 * n, fp64_);
             });
}

std::size_t DeviceSystem::set(const BlockSystem& s, const ComputeProgram& shift) {
  upload_ = {};
  upload_.full_bytes = s.bytes(scalar());
  // K' stays when rows are inserted before it: only its offset (a uniform) moves.
  const bool same_dense = have_ && s.dense_size == cached_.dense_size;
  const bool same_pattern =
      same_dense && s.dense_offset == cached_.dense_offset && s.row_ptr == cached_.row_ptr && s.col == cached_.col;
  if (same_pattern) {
    upload_.sent_bytes += upload_changed(values_, cached_.values, s.values, 9);
    upload_.sent_bytes += upload_changed(diag_inv_, cached_.diag_inverse, s.diag_inverse, 9);
  } else {
    bool incremental = false;
    if (have_) {
      const BlockSystemDiff d = diff_block_systems(cached_, s);
      const std::size_t dense_bytes = same_dense ? 0 : s.dense.size() * scalar();
      incremental = incremental_bytes(s, d, scalar()) + dense_bytes < upload_.full_bytes;
      if (incremental) set_incremental(s, d, shift);
    }
    if (!incremental) {
      upload_full(row_ptr_, s.row_ptr.data(), 4 * s.row_ptr.size());
      upload_full(col_, s.col.data(), 4 * s.col.size());
      auto v = to_device(s.values.data(), s.values.size(), fp64_);
      upload_full(values_, v.data(), v.size());
      v = to_device(s.diag_inverse.data(), s.diag_inverse.size(), fp64_);
      upload_full(diag_inv_, v.data(), v.size());
    }
    upload_.incremental = incremental;
  }
  if (s.dense_size > 0) {
    if (same_dense) {
      upload_.sent_bytes += upload_changed(dense_, cached_.dense, s.dense, std::size_t(s.dense_size));
    } else {
      const auto v = to_device(s.dense.data(), s.dense.size(), fp64_);
      upload_full(dense_, v.data(), v.size());
    }
  } else {
    reserve(dense_, 16);
  }
  cached_ = s;
  have_ = true;
  return upload_.sent_bytes;
}

BlockSystem DeviceSystem::read_back() const {
  if (!have_) fail("GPU solver: device_system before set_system");
  BlockSystem s;
  s.num_blocks = cached_.num_blocks;
  s.dense_offset = cached_.dense_offset;
  s.dense_size = cached_.dense_size;
  s.row_ptr.resize(cached_.row_ptr.size());
  row_ptr_.download(s.row_ptr.data(), 4 * s.row_ptr.size());
  s.col.resize(cached_.col.size());
  col_.download(s.col.data(), 4 * s.col.size());
  auto read = [&](const StorageBuffer& b, std::size_t count) {
    std::vector<unsigned char> bytes(count * scalar());
    b.download(bytes.data(), bytes.size());
    return from_device(bytes, fp64_);
  };
  s.values = read(values_, cached_.values.size());
  s.dense = read(dense_, cached_.dense.size());
  s.diag_inverse = read(diag_inv_, cached_.diag_inverse.size());
  return s;
}

void DeviceSystem::bind() const {
  row_ptr_.bind(L::kRowPtr);
  col_.bind(L::kCol);
  values_.bind(L::kValues);
  dense_.bind(L::kDense);
  diag_inv_.bind(L::kDiagInv);
}

}  // namespace softcut::gpu
