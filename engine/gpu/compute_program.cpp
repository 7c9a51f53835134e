#include "gpu/compute_program.hpp"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <algorithm>
#include <utility>

#include "core/error.hpp"

namespace softcut::gpu {

ComputeProgram::ComputeProgram(const std::string& name, const std::string& source)
    : program_(name, {{gl::Stage::compute, source.c_str()}}) {}

void ComputeProgram::dispatch(std::uint32_t groups, std::initializer_list<UniformValue> uniforms) const {
  // Every uniform the kernel reads is set here, from this call's values:
  // nothing an earlier dispatch (another run's) left on the program is used.
  for (const gl::UniformInfo& u : program_.uniforms()) {
    const UniformValue* given = nullptr;
    for (const UniformValue& v : uniforms)
      if (u.name == v.name) given = &v;
    if (!given) fail("compute kernel '", program_.name(), "': dispatched without a value for its uniform '", u.name, "'");
    glProgramUniform1ui(program_.id(), u.location, given->value);
  }
  glUseProgram(program_.id());
  glDispatchCompute(std::max<std::uint32_t>(groups, 1), 1, 1);
}

StorageBuffer::~StorageBuffer() {
  if (id_) glDeleteBuffers(1, &id_);
}

StorageBuffer::StorageBuffer(StorageBuffer&& o) noexcept
    : id_(std::exchange(o.id_, 0)), capacity_(std::exchange(o.capacity_, 0)) {}

StorageBuffer& StorageBuffer::operator=(StorageBuffer&& o) noexcept {
  if (this != &o) {
    if (id_) glDeleteBuffers(1, &id_);
    id_ = std::exchange(o.id_, 0);
    capacity_ = std::exchange(o.capacity_, 0);
  }
  return *this;
}

std::size_t StorageBuffer::upload(const void* data, std::size_t bytes) {
  // The allocation is never zero-sized, but only `bytes` are read from `data`
  // (a 1x1 matrix is 8 bytes: reading 16 overran the host array, found by ASan).
  const std::size_t alloc = std::max<std::size_t>(bytes, 16);
  if (!id_ || alloc > capacity_) {
    if (id_) glDeleteBuffers(1, &id_);
    glCreateBuffers(1, &id_);
    glNamedBufferData(id_, GLsizeiptr(alloc), nullptr, GL_DYNAMIC_DRAW);
    capacity_ = alloc;
  } else if (data && bytes) {
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  }
  if (data && bytes) glNamedBufferSubData(id_, 0, GLsizeiptr(bytes), data);
  return data ? bytes : 0;
}

// Buffer reads and writes through the API see (and wait for) earlier shader
// writes only after GL_BUFFER_UPDATE_BARRIER_BIT (GL 4.6 §7.13.2); the
// shader-storage barrier alone orders shader accesses only.
void StorageBuffer::upload_range(std::size_t offset, const void* data, std::size_t bytes) {
  if (offset + bytes > capacity_) fail("StorageBuffer::upload_range past the allocation");
  if (!bytes) return;
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  glNamedBufferSubData(id_, GLintptr(offset), GLsizeiptr(bytes), data);
}

void StorageBuffer::allocate(std::size_t bytes) {
  bytes = std::max<std::size_t>(bytes, 16);
  if (id_) glDeleteBuffers(1, &id_);
  glCreateBuffers(1, &id_);
  glNamedBufferData(id_, GLsizeiptr(bytes), nullptr, GL_DYNAMIC_DRAW);
  capacity_ = bytes;
}

void StorageBuffer::copy_from(const StorageBuffer& src, std::size_t src_offset, std::size_t dst_offset,
                              std::size_t bytes) {
  if (!bytes) return;
  if (src_offset + bytes > src.capacity_ || dst_offset + bytes > capacity_)
    fail("StorageBuffer::copy_from past the allocation");
  if (&src == this && src_offset < dst_offset + bytes && dst_offset < src_offset + bytes)
    fail("StorageBuffer::copy_from with overlapping ranges of one buffer");
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  glCopyNamedBufferSubData(src.id_, id_, GLintptr(src_offset), GLintptr(dst_offset), GLsizeiptr(bytes));
}

void StorageBuffer::download(void* data, std::size_t bytes, std::size_t offset) const {
  if (offset + bytes > capacity_) fail("StorageBuffer::download past the allocation");
  if (!bytes) return;
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  glGetNamedBufferSubData(id_, GLintptr(offset), GLsizeiptr(bytes), data);
}

void StorageBuffer::bind(std::uint32_t binding) const { glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, id_); }

void storage_barrier() { glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT); }

}  // namespace softcut::gpu
