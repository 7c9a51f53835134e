#pragma once
// The one OpenGL context the application owns: headless EGL, OpenGL 4.5 core,
// no window and no surface (EGL_KHR_surfaceless_context; draw into FBOs,
// compute into buffers). Rendering and compute-shader CG share it.
//
// Platforms, tried in order: the EGL device platform (EGL_EXT_platform_device;
// NVIDIA's headless path, hardware devices before Mesa's software device), then
// Mesa's surfaceless platform (llvmpipe on machines without a GPU). GL entry
// points are called directly through <GL/glcorearb.h> with GL_GLEXT_PROTOTYPES:
// glvnd's libOpenGL exports the whole 4.5 core API and dispatches to the vendor
// of the current context, so no loader is needed.
//
// A context is current on one thread at a time; the constructor makes it
// current on the calling thread. Not copyable or movable (GL debug callbacks
// keep a pointer to it).
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/error.hpp"

namespace softcut::gl {

enum class Platform {
  automatic,    // device, then surfaceless (the default)
  device,       // EGL_EXT_platform_device only
  surfaceless,  // EGL_MESA_platform_surfaceless only
};

// "device" / "surfaceless" / "" (automatic) -> Platform; anything else throws
// softcut::Error naming the accepted values. `what` names the source in
// messages (an option or environment variable).
Platform parse_platform(const std::string& name, const std::string& what);

struct ContextOptions {
  // automatic also honours SOFTCUT_EGL_PLATFORM=device|surfaceless.
  Platform platform = Platform::automatic;
  int major = 4, minor = 5;  // minimum OpenGL core version
  bool debug = true;         // debug context; messages collected (see messages())
};

struct ComputeLimits {
  int work_group_count[3] = {0, 0, 0};  // GL_MAX_COMPUTE_WORK_GROUP_COUNT per axis
  int work_group_size[3] = {0, 0, 0};   // GL_MAX_COMPUTE_WORK_GROUP_SIZE per axis
  int work_group_invocations = 0;       // GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS
  int shared_memory_bytes = 0;          // GL_MAX_COMPUTE_SHARED_MEMORY_SIZE
  int ssbo_bindings = 0;                // GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS
  std::int64_t ssbo_block_bytes = 0;    // GL_MAX_SHADER_STORAGE_BLOCK_SIZE
};

struct ContextInfo {
  std::string platform;      // "device" or "surfaceless"
  std::string device;        // device platform: DRM node or "software"; else empty
  std::string egl_vendor;    // EGL_VENDOR
  std::string egl_version;   // EGL_VERSION
  std::string vendor;        // GL_VENDOR
  std::string renderer;      // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
  std::string version;       // GL_VERSION
  std::string glsl_version;  // GL_SHADING_LANGUAGE_VERSION
  int gl_major = 0, gl_minor = 0;
  bool software = false;     // a CPU rasteriser (llvmpipe, softpipe, swrast)
  bool compute = false;      // compute shaders available (GL >= 4.3)
  bool debug_output = false; // debug messages are being captured
  int max_samples = 0;       // GL_MAX_SAMPLES (MSAA)
  ComputeLimits limits;

  // One line for logs: "OpenGL 4.5 (Core Profile) Mesa 22.3.6 on llvmpipe (...) via surfaceless, software".
  std::string summary() const;
};

// One message from the GL debug output (KHR_debug).
struct DebugMessage {
  std::uint32_t source = 0, type = 0, id = 0, severity = 0;  // GL enums
  std::string text;

  bool is_error() const;         // type GL_DEBUG_TYPE_ERROR
  std::string describe() const;  // "GL error (high, api): ..."
};

class EglContext {
 public:
  // Throws softcut::Error listing what each platform said when none gives an
  // OpenGL >= major.minor core context (and suggesting --no-render).
  explicit EglContext(const ContextOptions& options = {});
  ~EglContext();
  EglContext(const EglContext&) = delete;
  EglContext& operator=(const EglContext&) = delete;

  const ContextInfo& info() const;

  // Makes the context current on the calling thread (no-op if it already is).
  void make_current() const;
  bool is_current() const;
  // Detaches the context from the calling thread (no-op if it is not current
  // there), so that another thread can make it current.
  void release_current() const;

  // Debug messages captured since the last take_messages() (notifications are
  // filtered out at the source). Capped at 1000; later ones are counted only.
  std::vector<DebugMessage> take_messages();
  // Moves the captured messages into `diag` as warnings, prefixed by `where`.
  // Returns how many were GL errors.
  int drain_messages(Diagnostics& diag, const std::string& where);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace softcut::gl
