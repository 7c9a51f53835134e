#include "gl/program.hpp"

#include <doctest/doctest.h>

#include <string>

#include "core/error.hpp"
#include "gl/egl_context.hpp"

using namespace softcut;

namespace {

gl::EglContext& context() {
  static gl::EglContext ctx;
  return ctx;
}

const char* kVs = R"(#version 450 core
layout(location = 0) in vec3 a_pos;
uniform mat4 u_view;
uniform float u_unused;  // read by nothing: the linker drops it
void main() { gl_Position = u_view * vec4(a_pos, 1.0); }
)";
const char* kFs = R"(#version 450 core
uniform vec4 u_color;
out vec4 o;
void main() { o = u_color; }
)";

}  // namespace

TEST_SUITE("gl/program") {
  TEST_CASE("a vertex and fragment program links and lists the uniforms it reads") {
    context().make_current();
    const gl::Program p("test.draw", {{gl::Stage::vertex, kVs}, {gl::Stage::fragment, kFs}});
    CHECK(p.id() != 0);
    CHECK(p.name() == "test.draw");
    REQUIRE(p.uniforms().size() == 2);
    CHECK(p.uniform("u_view") >= 0);
    CHECK(p.uniform("u_color") >= 0);
    CHECK(p.uniform("u_view") != p.uniform("u_color"));
    CHECK(p.uniform("u_unused") == -1);
    CHECK(p.uniform("nothing") == -1);
  }

  TEST_CASE("a shader that does not compile is refused naming the program, the stage and the driver's log") {
    context().make_current();
    const char* broken = "#version 450 core\nvoid main() { undeclared = 1.0; }\n";
    try {
      gl::Program p("test.broken", {{gl::Stage::vertex, kVs}, {gl::Stage::fragment, broken}});
      FAIL("a broken shader compiled");
    } catch (const Error& e) {
      const std::string msg = e.what();
      CHECK(msg.find("'test.broken'") != std::string::npos);
      CHECK(msg.find("fragment shader does not compile") != std::string::npos);
      CHECK(msg.find("undeclared") != std::string::npos);
    }
  }

  TEST_CASE("stages that do not fit together are refused at link time") {
    context().make_current();
    // The fragment shader reads a varying no vertex shader writes.
    const char* fs = "#version 450 core\nin vec4 v_missing;\nout vec4 o;\nvoid main() { o = v_missing; }\n";
    const char* vs = "#version 450 core\nvoid main() { gl_Position = vec4(0.0); }\n";
    try {
      gl::Program p("test.mismatch", {{gl::Stage::vertex, vs}, {gl::Stage::fragment, fs}});
      FAIL("mismatched stages linked");
    } catch (const Error& e) {
      const std::string msg = e.what();
      CHECK(msg.find("'test.mismatch' does not link") != std::string::npos);
    }
  }

  TEST_CASE("a moved program keeps its object, and the moved-from one holds none") {
    context().make_current();
    gl::Program a("test.move", {{gl::Stage::vertex, kVs}, {gl::Stage::fragment, kFs}});
    const std::uint32_t id = a.id();
    gl::Program b(std::move(a));
    CHECK(b.id() == id);
    CHECK(a.id() == 0);  // NOLINT(bugprone-use-after-move): that is the point
    CHECK(b.uniform("u_color") >= 0);
  }
}
