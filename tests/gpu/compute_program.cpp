#include "gpu/compute_program.hpp"

#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "core/error.hpp"
#include "gl/egl_context.hpp"

using namespace softcut;

namespace {

gl::EglContext& context() {
  static gl::EglContext ctx;
  return ctx;
}

// Writes a * i + b into x[i] for i < n.
const char* kAffine = R"(#version 450 core
layout(local_size_x = 64) in;
layout(std430, binding = 0) buffer X { uint x[]; };
uniform uint a;
uniform uint b;
uniform uint n;
void main() { uint i = gl_GlobalInvocationID.x; if (i < n) x[i] = a * i + b; }
)";

std::vector<std::uint32_t> run(const gpu::ComputeProgram& k, gpu::StorageBuffer& buf,
                               std::initializer_list<gpu::UniformValue> u) {
  buf.bind(0);
  k.dispatch(1, u);
  gpu::storage_barrier();
  std::vector<std::uint32_t> out(8);
  buf.download(out.data(), out.size() * 4);
  return out;
}

}  // namespace

TEST_SUITE("gpu/compute_program") {
  TEST_CASE("each dispatch uses its own uniform values, whatever an earlier dispatch set") {
    if (!context().info().compute) return;
    context().make_current();
    const gpu::ComputeProgram k("test.affine", kAffine);
    gpu::StorageBuffer one, two;
    const std::vector<std::uint32_t> zeros(8, 0);
    one.upload(zeros.data(), 32);
    two.upload(zeros.data(), 32);
    // Two users of one kernel, interleaved (two runs of one Model).
    const auto a = run(k, one, {{"a", 2}, {"b", 1}, {"n", 8}});
    const auto b = run(k, two, {{"a", 3}, {"b", 0}, {"n", 4}});
    const auto a2 = run(k, one, {{"a", 2}, {"b", 1}, {"n", 8}});
    for (std::uint32_t i = 0; i < 8; ++i) {
      CHECK(a[i] == 2 * i + 1);
      CHECK(a2[i] == 2 * i + 1);
      CHECK(b[i] == (i < 4 ? 3 * i : 0));
    }
  }

  TEST_CASE("a dispatch that leaves out a uniform the kernel reads is refused, naming it") {
    if (!context().info().compute) return;
    context().make_current();
    const gpu::ComputeProgram k("test.affine", kAffine);
    gpu::StorageBuffer buf;
    buf.allocate(32);
    buf.bind(0);
    try {
      k.dispatch(1, {{"a", 1}, {"n", 8}});
      FAIL("a dispatch without 'b' ran");
    } catch (const Error& e) {
      CHECK(std::string(e.what()).find("'test.affine'") != std::string::npos);
      CHECK(std::string(e.what()).find("uniform 'b'") != std::string::npos);
    }
    // A value the kernel does not read is no error (the driver may drop unread uniforms).
    CHECK_NOTHROW(k.dispatch(1, {{"a", 1}, {"b", 2}, {"n", 8}, {"unused", 5}}));
  }
}
