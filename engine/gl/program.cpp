#include "gl/program.hpp"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <algorithm>
#include <cstring>
#include <utility>

#include "core/error.hpp"

namespace softcut::gl {

namespace {

GLenum gl_stage(Stage s) {
  switch (s) {
    case Stage::vertex: return GL_VERTEX_SHADER;
    case Stage::geometry: return GL_GEOMETRY_SHADER;
    case Stage::fragment: return GL_FRAGMENT_SHADER;
    case Stage::compute: return GL_COMPUTE_SHADER;
  }
  return GL_VERTEX_SHADER;
}

std::string shader_log(GLuint shader) {
  GLint len = 0;
  glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &len);
  std::string log(size_t(std::max(len, 1)), '\0');
  glGetShaderInfoLog(shader, GLsizei(log.size()), nullptr, log.data());
  log.resize(std::strlen(log.c_str()));
  return log;
}

std::string program_log(GLuint program) {
  GLint len = 0;
  glGetProgramiv(program, GL_INFO_LOG_LENGTH, &len);
  std::string log(size_t(std::max(len, 1)), '\0');
  glGetProgramInfoLog(program, GLsizei(log.size()), nullptr, log.data());
  log.resize(std::strlen(log.c_str()));
  return log;
}

}  // namespace

const char* to_string(Stage s) {
  switch (s) {
    case Stage::vertex: return "vertex";
    case Stage::geometry: return "geometry";
    case Stage::fragment: return "fragment";
    case Stage::compute: return "compute";
  }
  return "?";
}

Program::Program(std::string name, std::initializer_list<Shader> shaders) : name_(std::move(name)) {
  std::vector<GLuint> compiled;
  auto drop = [&] {
    for (GLuint s : compiled) glDeleteShader(s);
  };
  for (const Shader& sh : shaders) {
    const GLuint s = glCreateShader(gl_stage(sh.stage));
    glShaderSource(s, 1, &sh.source, nullptr);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
      const std::string log = shader_log(s);
      glDeleteShader(s);
      drop();
      fail("shader program '", name_, "': the ", to_string(sh.stage), " shader does not compile on this driver: ", log);
    }
    compiled.push_back(s);
  }
  id_ = glCreateProgram();
  for (GLuint s : compiled) glAttachShader(id_, s);
  glLinkProgram(id_);
  drop();  // flagged for deletion; they go with the program
  GLint ok = 0;
  glGetProgramiv(id_, GL_LINK_STATUS, &ok);
  if (!ok) {
    const std::string log = program_log(id_);
    glDeleteProgram(id_);
    id_ = 0;
    fail("shader program '", name_, "' does not link on this driver: ", log);
  }
  GLint count = 0, longest = 0;
  glGetProgramiv(id_, GL_ACTIVE_UNIFORMS, &count);
  glGetProgramiv(id_, GL_ACTIVE_UNIFORM_MAX_LENGTH, &longest);
  std::string buf(size_t(std::max(longest, 1)), '\0');
  for (GLint i = 0; i < count; ++i) {
    GLsizei len = 0;
    GLint size = 0;
    GLenum type = 0;
    glGetActiveUniform(id_, GLuint(i), GLsizei(buf.size()), &len, &size, &type, buf.data());
    std::string n(buf.data(), size_t(len));
    const GLint loc = glGetUniformLocation(id_, n.c_str());
    if (loc >= 0) uniforms_.push_back({std::move(n), loc});  // -1: a member of a uniform block
  }
  std::sort(uniforms_.begin(), uniforms_.end(), [](const UniformInfo& a, const UniformInfo& b) {
    return a.location < b.location;
  });
}

Program::~Program() {
  if (id_) glDeleteProgram(id_);
}

Program::Program(Program&& o) noexcept
    : id_(std::exchange(o.id_, 0)), name_(std::move(o.name_)), uniforms_(std::move(o.uniforms_)) {}

Program& Program::operator=(Program&& o) noexcept {
  if (this != &o) {
    if (id_) glDeleteProgram(id_);
    id_ = std::exchange(o.id_, 0);
    name_ = std::move(o.name_);
    uniforms_ = std::move(o.uniforms_);
  }
  return *this;
}

int Program::uniform(const char* name) const {
  for (const UniformInfo& u : uniforms_)
    if (u.name == name) return u.location;
  return -1;
}

}  // namespace softcut::gl
