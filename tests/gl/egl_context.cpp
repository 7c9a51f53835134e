#include "gl/egl_context.hpp"
#include "gl/program.hpp"

#include <doctest/doctest.h>

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <string>
#include <vector>

using softcut::gl::ContextOptions;
using softcut::gl::EglContext;
using softcut::gl::Platform;

TEST_SUITE("gl/egl_context") {
  TEST_CASE("a headless OpenGL 4.5 core context with compute shaders") {
    EglContext ctx;
    const auto& info = ctx.info();
    MESSAGE(info.summary());
    CHECK(ctx.is_current());
    CHECK((info.platform == "device" || info.platform == "surfaceless"));
    CHECK(info.gl_major * 10 + info.gl_minor >= 45);
    CHECK(info.version.find("4.") != std::string::npos);
    CHECK(info.compute);
    // OpenGL 4.5 minimums (spec table 23.75).
    CHECK(info.limits.work_group_invocations >= 1024);
    CHECK(info.limits.work_group_size[0] >= 1024);
    CHECK(info.limits.work_group_count[0] >= 65535);
    CHECK(info.limits.shared_memory_bytes >= 32768);
    CHECK(info.limits.ssbo_bindings >= 8);
    CHECK(info.limits.ssbo_block_bytes >= (std::int64_t(1) << 27));
    CHECK(info.max_samples >= 4);
    CHECK(info.software == (info.renderer.find("llvmpipe") != std::string::npos ||
                            info.renderer.find("softpipe") != std::string::npos));
    CHECK(info.summary().find(info.renderer) != std::string::npos);
  }

  TEST_CASE("a compute shader runs and its result reads back") {
    EglContext ctx;
    const char* src = R"(#version 450 core
      layout(local_size_x = 64) in;
      layout(std430, binding = 0) buffer Data { float x[]; };
      void main() { uint i = gl_GlobalInvocationID.x; if (i < x.length()) x[i] = 2.0 * x[i] + 1.0; })";
    const softcut::gl::Program prog("double", {{softcut::gl::Stage::compute, src}});
    std::vector<float> data(1000);
    for (size_t i = 0; i < data.size(); ++i) data[i] = float(i) * 0.5f;
    GLuint buf = 0;
    glCreateBuffers(1, &buf);
    glNamedBufferStorage(buf, GLsizeiptr(data.size() * sizeof(float)), data.data(), GL_DYNAMIC_STORAGE_BIT);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buf);
    glUseProgram(prog.id());
    glDispatchCompute((GLuint(data.size()) + 63) / 64, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<float> out(data.size());
    glGetNamedBufferSubData(buf, 0, GLsizeiptr(out.size() * sizeof(float)), out.data());
    int wrong = 0;
    for (size_t i = 0; i < out.size(); ++i) wrong += out[i] != 2.0f * data[i] + 1.0f;
    CHECK(wrong == 0);
    glDeleteBuffers(1, &buf);
    for (const auto& m : ctx.take_messages()) CHECK_MESSAGE(!m.is_error(), m.describe());
  }

  TEST_CASE("GL errors are captured as debug messages and drained into diagnostics") {
    EglContext ctx;
    REQUIRE(ctx.info().debug_output);
    CHECK(ctx.take_messages().empty());
    glEnable(0x1234);  // not a capability: GL_INVALID_ENUM
    // Drivers may add low-severity notes of their own; exactly one error is ours.
    std::vector<softcut::gl::DebugMessage> errors;
    for (const auto& m : ctx.take_messages())
      if (m.is_error()) errors.push_back(m);
    REQUIRE(errors.size() == 1);
    CHECK(errors[0].describe().find("GL error") == 0);
    CHECK(ctx.take_messages().empty());
    CHECK(glGetError() == GL_INVALID_ENUM);

    glBindBuffer(GL_ARRAY_BUFFER, 987654);  // never generated: GL_INVALID_OPERATION
    softcut::Diagnostics diag;
    CHECK(ctx.drain_messages(diag, "render") == 1);
    REQUIRE(diag.warnings.size() >= 1);
    int ours = 0;
    for (const auto& w : diag.warnings) ours += w.find("render: GL error") == 0;
    CHECK(ours == 1);
    while (glGetError() != GL_NO_ERROR) {
    }
  }

  TEST_CASE("contexts come and go and the last one created stays usable") {
    auto a = std::make_unique<EglContext>();
    EglContext b;
    CHECK(b.is_current());
    CHECK_FALSE(a->is_current());
    a->make_current();
    CHECK(a->is_current());
    a.reset();
    b.make_current();
    GLuint buf = 0;
    glCreateBuffers(1, &buf);
    CHECK(buf != 0);
    glDeleteBuffers(1, &buf);
    for (const auto& m : b.take_messages()) CHECK_MESSAGE(!m.is_error(), m.describe());
  }

  TEST_CASE("each platform can be asked for and a missing one is a clear error") {
    ContextOptions opt;
    opt.platform = Platform::surfaceless;
    EglContext s(opt);
    CHECK(s.info().platform == "surfaceless");
    opt.platform = Platform::device;
    try {
      EglContext d(opt);
      CHECK(d.info().platform == "device");
      MESSAGE("device platform: ", d.info().summary());
    } catch (const softcut::Error& e) {
      const std::string what = e.what();
      CHECK(what.find("EGL device platform") != std::string::npos);
      CHECK(what.find("--no-render") != std::string::npos);
    }
  }

  TEST_CASE("a version no driver offers is refused with the reason") {
    ContextOptions opt;
    opt.major = 9;
    opt.minor = 9;
    try {
      EglContext c(opt);
      FAIL("expected an error");
    } catch (const softcut::Error& e) {
      const std::string what = e.what();
      CHECK(what.find("OpenGL 9.9 core") != std::string::npos);
      CHECK(what.find("surfaceless") != std::string::npos);
      CHECK(what.find("--no-render") != std::string::npos);
    }
  }

  TEST_CASE("platform names parse and unknown ones name the source") {
    CHECK(softcut::gl::parse_platform("", "x") == Platform::automatic);
    CHECK(softcut::gl::parse_platform("device", "x") == Platform::device);
    CHECK(softcut::gl::parse_platform("surfaceless", "x") == Platform::surfaceless);
    CHECK_THROWS_WITH_AS(softcut::gl::parse_platform("x11", "SOFTCUT_EGL_PLATFORM"),
                         doctest::Contains("SOFTCUT_EGL_PLATFORM: unknown EGL platform 'x11'"),
                         softcut::Error);
  }
}
