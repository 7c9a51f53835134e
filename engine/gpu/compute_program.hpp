#pragma once
// Compute work in the application's EGL context: a compute kernel (a
// gl::Program of one compute shader) and a shader storage buffer. The
// context must be current.
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <string>

#include "gl/program.hpp"

namespace softcut::gpu {

// A value for one uint uniform of a kernel, given with each dispatch.
struct UniformValue {
  const char* name;
  std::uint32_t value;
};

// A compiled kernel. It holds no per-use state: every dispatch gives a value
// for each uniform the kernel reads (an omission is an error), so no value
// carries over from an earlier dispatch, and kernels compiled once (a
// Model's) serve any number of runs, each with its own sizes and buffers.
class ComputeProgram {
 public:
  ComputeProgram() = default;
  // Compiles and links; throws softcut::Error with the driver's log and `name`.
  ComputeProgram(const std::string& name, const std::string& source);

  std::uint32_t id() const { return program_.id(); }
  // Forgets the program without deleting it (for a destructor that finds its
  // context current on another thread: the context frees it with itself).
  void release() noexcept { program_.release(); }
  // Sets `uniforms` (every active uniform of the kernel, each once; throws
  // naming a missing or unknown one), binds the program and dispatches
  // `groups` work groups along x.
  void dispatch(std::uint32_t groups, std::initializer_list<UniformValue> uniforms = {}) const;

 private:
  gl::Program program_;
};

class StorageBuffer {
 public:
  // Forgets the buffer without deleting it (see ComputeProgram::release).
  void release() noexcept { id_ = 0, capacity_ = 0; }
  StorageBuffer() = default;
  ~StorageBuffer();
  StorageBuffer(StorageBuffer&& o) noexcept;
  StorageBuffer& operator=(StorageBuffer&& o) noexcept;
  StorageBuffer(const StorageBuffer&) = delete;
  StorageBuffer& operator=(const StorageBuffer&) = delete;

  // (Re)allocates when `bytes` exceeds the capacity, then uploads `data`
  // (nullptr: contents undefined). Returns the bytes transferred.
  std::size_t upload(const void* data, std::size_t bytes);
  // Uploads [offset, offset + bytes) into an existing allocation.
  void upload_range(std::size_t offset, const void* data, std::size_t bytes);
  // Fresh allocation of `bytes` (at least 16), contents undefined; the old
  // contents are dropped.
  void allocate(std::size_t bytes);
  // Device-side copy of src[src_offset, + bytes) to [dst_offset, + bytes).
  // Throws on ranges past either allocation or overlapping ranges of one
  // buffer (GL forbids them; go through a scratch buffer).
  void copy_from(const StorageBuffer& src, std::size_t src_offset, std::size_t dst_offset, std::size_t bytes);
  void download(void* data, std::size_t bytes, std::size_t offset = 0) const;
  void bind(std::uint32_t binding) const;
  std::size_t capacity() const { return capacity_; }

 private:
  std::uint32_t id_ = 0;
  std::size_t capacity_ = 0;
};

// glMemoryBarrier for shader storage writes followed by reads.
void storage_barrier();

}  // namespace softcut::gpu
