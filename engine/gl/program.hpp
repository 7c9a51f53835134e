#pragma once
// One OpenGL program object: shaders of any stages compiled and linked in
// the current context. The renderer's draw programs and the compute kernels
// of gpu/ are all made here, so compiling, linking and reporting a driver's
// log are written once.
#include <cstdint>
#include <initializer_list>
#include <string>
#include <vector>

namespace softcut::gl {

enum class Stage { vertex, geometry, fragment, compute };
const char* to_string(Stage s);

struct Shader {
  Stage stage;
  const char* source;  // GLSL, NUL-terminated
};

// An active uniform of a linked program: its name and location.
struct UniformInfo {
  std::string name;
  int location = -1;
};

class Program {
 public:
  Program() = default;
  // Compiles each shader and links them (the context must be current).
  // Throws softcut::Error naming `name`, the failing stage and the driver's log.
  Program(std::string name, std::initializer_list<Shader> shaders);
  ~Program();
  Program(Program&& o) noexcept;
  Program& operator=(Program&& o) noexcept;
  Program(const Program&) = delete;
  Program& operator=(const Program&) = delete;

  std::uint32_t id() const { return id_; }
  const std::string& name() const { return name_; }
  // The program's active uniforms outside blocks (what the linker kept: a
  // uniform the shaders never read is not among them), in location order.
  const std::vector<UniformInfo>& uniforms() const { return uniforms_; }
  // Location of an active uniform, -1 when there is none of that name.
  int uniform(const char* name) const;
  // Forgets the program without deleting it (for a destructor that finds the
  // context current on another thread: the context frees it with itself).
  void release() noexcept { id_ = 0; }

 private:
  std::uint32_t id_ = 0;
  std::string name_;
  std::vector<UniformInfo> uniforms_;
};

}  // namespace softcut::gl
