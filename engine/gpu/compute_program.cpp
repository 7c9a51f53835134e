#include "gpu/compute_program.hpp"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <utility>
#include <vector>

#include "core/error.hpp"

namespace softcut::gpu {

ComputeProgram::ComputeProgram(const std::string& name, const std::string& source) {
  const GLuint shader = glCreateShader(GL_COMPUTE_SHADER);
  const char* src = source.c_str();
  glShaderSource(shader, 1, &src, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    GLint len = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &len);
    std::string log(size_t(std::max(len, 1)), '\0');
    glGetShaderInfoLog(shader, len, nullptr, log.data());
    glDeleteShader(shader);
    fail("compute shader '", name, "' does not compile: ", log);
  }
  id_ = glCreateProgram();
  glAttachShader(id_, shader);
  glLinkProgram(id_);
  glDeleteShader(shader);
  glGetProgramiv(id_, GL_LINK_STATUS, &ok);
  if (!ok) {
    GLint len = 0;
    glGetProgramiv(id_, GL_INFO_LOG_LENGTH, &len);
    std::string log(size_t(std::max(len, 1)), '\0');
    glGetProgramInfoLog(id_, len, nullptr, log.data());
    glDeleteProgram(id_);
    id_ = 0;
    fail("compute program '", name, "' does not link: ", log);
  }
}

ComputeProgram::~ComputeProgram() {
  if (id_) glDeleteProgram(id_);
}

ComputeProgram::ComputeProgram(ComputeProgram&& o) noexcept : id_(std::exchange(o.id_, 0)) {}

ComputeProgram& ComputeProgram::operator=(ComputeProgram&& o) noexcept {
  if (this != &o) {
    if (id_) glDeleteProgram(id_);
    id_ = std::exchange(o.id_, 0);
  }
  return *this;
}

void ComputeProgram::set_uint(const char* uniform, std::uint32_t value) const {
  const GLint loc = glGetUniformLocation(id_, uniform);
  if (loc >= 0) glProgramUniform1ui(id_, loc, value);
}

void ComputeProgram::dispatch(std::uint32_t groups) const {
  glUseProgram(id_);
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
