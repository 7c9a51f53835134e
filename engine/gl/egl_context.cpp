#include "gl/egl_context.hpp"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <cstdlib>
#include <mutex>

namespace softcut::gl {
namespace {

const char* egl_error_name(EGLint e) {
  switch (e) {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE: return "EGL_BAD_SURFACE";
    default: return "EGL error";
  }
}

std::string egl_error() {
  const EGLint e = eglGetError();
  return cat(egl_error_name(e), " (0x", std::hex, e, ")");
}

bool has_extension(const char* list, const std::string& name) {
  if (!list) return false;
  const std::string s = std::string(" ") + list + " ";
  return s.find(" " + name + " ") != std::string::npos;
}

std::string gl_string(GLenum name) {
  const GLubyte* s = glGetString(name);
  return s ? reinterpret_cast<const char*>(s) : "";
}

const char* severity_name(GLenum s) {
  switch (s) {
    case GL_DEBUG_SEVERITY_HIGH: return "high";
    case GL_DEBUG_SEVERITY_MEDIUM: return "medium";
    case GL_DEBUG_SEVERITY_LOW: return "low";
    default: return "notification";
  }
}

const char* type_name(GLenum t) {
  switch (t) {
    case GL_DEBUG_TYPE_ERROR: return "GL error";
    case GL_DEBUG_TYPE_DEPRECATED_BEHAVIOR: return "GL deprecated";
    case GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR: return "GL undefined behaviour";
    case GL_DEBUG_TYPE_PORTABILITY: return "GL portability";
    case GL_DEBUG_TYPE_PERFORMANCE: return "GL performance";
    default: return "GL message";
  }
}

const char* source_name(GLenum s) {
  switch (s) {
    case GL_DEBUG_SOURCE_API: return "api";
    case GL_DEBUG_SOURCE_SHADER_COMPILER: return "shader compiler";
    case GL_DEBUG_SOURCE_WINDOW_SYSTEM: return "window system";
    case GL_DEBUG_SOURCE_THIRD_PARTY: return "third party";
    case GL_DEBUG_SOURCE_APPLICATION: return "application";
    default: return "other";
  }
}

constexpr size_t kMaxMessages = 1000;

}  // namespace

Platform parse_platform(const std::string& name, const std::string& what) {
  if (name.empty() || name == "auto" || name == "automatic") return Platform::automatic;
  if (name == "device") return Platform::device;
  if (name == "surfaceless") return Platform::surfaceless;
  fail(what, ": unknown EGL platform '", name, "' (use device, surfaceless or leave it unset)");
}

std::string ContextInfo::summary() const {
  std::string s = cat(version, " on ", renderer, " via EGL ", platform);
  if (!device.empty()) s += cat(" (", device, ")");
  if (software) s += ", software";
  return s;
}

bool DebugMessage::is_error() const { return type == GL_DEBUG_TYPE_ERROR; }

std::string DebugMessage::describe() const {
  return cat(type_name(type), " (", severity_name(severity), ", ", source_name(source), ", id ", id,
             "): ", text);
}

struct EglContext::Impl {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  ContextInfo info;
  std::mutex mutex;  // drivers may call the debug callback from their own threads
  std::vector<DebugMessage> messages;
  size_t dropped = 0;

  static void APIENTRY on_debug(GLenum source, GLenum type, GLuint id, GLenum severity, GLsizei length,
                                const GLchar* text, const void* user) {
    auto* self = const_cast<Impl*>(static_cast<const Impl*>(user));
    std::lock_guard lock(self->mutex);
    if (self->messages.size() >= kMaxMessages) {
      ++self->dropped;
      return;
    }
    self->messages.push_back({source, type, id, severity,
                              length >= 0 ? std::string(text, size_t(length)) : std::string(text)});
  }

  // Tries to create and make current a core context on an initialised display.
  // Returns an empty string on success, otherwise why not.
  std::string create_on(EGLDisplay dpy, const ContextOptions& opt) {
    EGLint major = 0, minor = 0;
    if (!eglInitialize(dpy, &major, &minor)) return cat("eglInitialize failed: ", egl_error());
    const char* ext = eglQueryString(dpy, EGL_EXTENSIONS);
    if (!has_extension(ext, "EGL_KHR_surfaceless_context"))
      return "the display lacks EGL_KHR_surfaceless_context";
    if (!eglBindAPI(EGL_OPENGL_API)) return cat("eglBindAPI(EGL_OPENGL_API) failed: ", egl_error());

    EGLConfig config = EGL_NO_CONFIG_KHR;
    if (!has_extension(ext, "EGL_KHR_no_config_context") && !has_extension(ext, "EGL_MESA_configless_context")) {
      // Surface type is irrelevant (we never make a surface), but the default
      // EGL_WINDOW_BIT matches nothing on the device platform.
      const EGLint attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, EGL_PBUFFER_BIT,
                                EGL_NONE};
      EGLint count = 0;
      if (!eglChooseConfig(dpy, attribs, &config, 1, &count) || count < 1)
        return cat("no EGL config renders OpenGL: ", egl_error());
    }
    const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, opt.major,
                              EGL_CONTEXT_MINOR_VERSION, opt.minor,
                              EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                              EGL_CONTEXT_OPENGL_DEBUG, opt.debug ? EGL_TRUE : EGL_FALSE,
                              EGL_NONE};
    EGLContext ctx = eglCreateContext(dpy, config, EGL_NO_CONTEXT, attribs);
    if (ctx == EGL_NO_CONTEXT)
      return cat("no OpenGL ", opt.major, ".", opt.minor, " core context: ", egl_error());
    if (!eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx)) {
      const std::string why = egl_error();
      eglDestroyContext(dpy, ctx);
      return cat("eglMakeCurrent without a surface failed: ", why);
    }
    display = dpy;
    context = ctx;
    info.egl_vendor = eglQueryString(dpy, EGL_VENDOR) ? eglQueryString(dpy, EGL_VENDOR) : "";
    info.egl_version = eglQueryString(dpy, EGL_VERSION) ? eglQueryString(dpy, EGL_VERSION) : "";
    return "";
  }

  std::string try_device(const ContextOptions& opt) {
    const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!has_extension(client, "EGL_EXT_platform_device") || !has_extension(client, "EGL_EXT_device_enumeration"))
      return "EGL_EXT_platform_device / EGL_EXT_device_enumeration not offered by libEGL";
    auto query_devices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    auto query_string =
        reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
    auto platform_display =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (!query_devices || !query_string || !platform_display) return "device entry points missing";
    EGLDeviceEXT devices[16];
    EGLint count = 0;
    if (!query_devices(16, devices, &count) || count < 1) return cat("no EGL devices (", egl_error(), ")");
    // Hardware devices first; Mesa's software device last.
    std::vector<std::pair<EGLDeviceEXT, std::string>> order;
    for (int pass = 0; pass < 2; ++pass)
      for (EGLint i = 0; i < count; ++i) {
        const char* dext = query_string(devices[i], EGL_EXTENSIONS);
        const bool soft = has_extension(dext, "EGL_MESA_device_software");
        if (soft != (pass == 1)) continue;
        std::string name = "software";
        if (!soft) {
          const char* node = has_extension(dext, "EGL_EXT_device_drm")
                                 ? query_string(devices[i], EGL_DRM_DEVICE_FILE_EXT) : nullptr;
          name = node ? node : cat("device ", i);
        }
        order.emplace_back(devices[i], name);
      }
    std::string why;
    for (auto& [dev, name] : order) {
      EGLDisplay dpy = platform_display(EGL_PLATFORM_DEVICE_EXT, dev, nullptr);
      const std::string r = dpy == EGL_NO_DISPLAY ? cat("no display: ", egl_error()) : create_on(dpy, opt);
      if (r.empty()) {
        info.platform = "device";
        info.device = name;
        return "";
      }
      why += cat(why.empty() ? "" : "; ", name, ": ", r);
    }
    return why;
  }

  std::string try_surfaceless(const ContextOptions& opt) {
    const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!has_extension(client, "EGL_MESA_platform_surfaceless"))
      return "EGL_MESA_platform_surfaceless not offered by libEGL (Mesa not installed?)";
    auto platform_display =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (!platform_display) return "eglGetPlatformDisplayEXT missing";
    EGLDisplay dpy = platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (dpy == EGL_NO_DISPLAY) return cat("no display: ", egl_error());
    const std::string r = create_on(dpy, opt);
    if (r.empty()) info.platform = "surfaceless";
    return r;
  }

  void query_info(const ContextOptions& opt) {
    info.vendor = gl_string(GL_VENDOR);
    info.renderer = gl_string(GL_RENDERER);
    info.version = gl_string(GL_VERSION);
    info.glsl_version = gl_string(GL_SHADING_LANGUAGE_VERSION);
    glGetIntegerv(GL_MAJOR_VERSION, &info.gl_major);
    glGetIntegerv(GL_MINOR_VERSION, &info.gl_minor);
    for (const char* soft : {"llvmpipe", "softpipe", "swrast", "lavapipe", "Software Rasterizer"})
      if (info.renderer.find(soft) != std::string::npos) info.software = true;
    glGetIntegerv(GL_MAX_SAMPLES, &info.max_samples);
    info.compute = info.gl_major > 4 || (info.gl_major == 4 && info.gl_minor >= 3);
    if (info.compute) {
      ComputeLimits& l = info.limits;
      for (GLuint a = 0; a < 3; ++a) {
        glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, a, &l.work_group_count[a]);
        glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_SIZE, a, &l.work_group_size[a]);
      }
      glGetIntegerv(GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS, &l.work_group_invocations);
      glGetIntegerv(GL_MAX_COMPUTE_SHARED_MEMORY_SIZE, &l.shared_memory_bytes);
      glGetIntegerv(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS, &l.ssbo_bindings);
      GLint64 block = 0;
      glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &block);
      l.ssbo_block_bytes = block;
    }
    GLint flags = 0;
    glGetIntegerv(GL_CONTEXT_FLAGS, &flags);
    if (opt.debug && (flags & GL_CONTEXT_FLAG_DEBUG_BIT)) {
      glEnable(GL_DEBUG_OUTPUT);
      // Synchronous: a message arrives inside the call that caused it, so the
      // caller can attribute it (and tests can expect it).
      glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
      glDebugMessageCallback(&Impl::on_debug, this);
      glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DEBUG_SEVERITY_NOTIFICATION, 0, nullptr, GL_FALSE);
      info.debug_output = true;
    }
    while (glGetError() != GL_NO_ERROR) {
    }
  }
};

EglContext::EglContext(const ContextOptions& options) : impl_(std::make_unique<Impl>()) {
  Platform platform = options.platform;
  if (platform == Platform::automatic) {
    const char* env = std::getenv("SOFTCUT_EGL_PLATFORM");
    platform = parse_platform(env ? env : "", "environment variable SOFTCUT_EGL_PLATFORM");
  }
  std::string why;
  bool ok = false;
  if (platform != Platform::surfaceless) {
    const std::string r = impl_->try_device(options);
    ok = r.empty();
    if (!ok) why += cat("EGL device platform: ", r);
  }
  if (!ok && platform != Platform::device) {
    const std::string r = impl_->try_surfaceless(options);
    ok = r.empty();
    if (!ok) why += cat(why.empty() ? "" : "; ", "Mesa surfaceless platform: ", r);
  }
  if (!ok)
    fail("cannot create a headless OpenGL ", options.major, ".", options.minor,
         " core context through EGL (", why,
         "). Install a GPU driver with EGL or Mesa's EGL (libegl-mesa0, llvmpipe), or run with --no-render.");
  impl_->query_info(options);
  const ContextInfo& i = impl_->info;
  if (i.gl_major < options.major || (i.gl_major == options.major && i.gl_minor < options.minor)) {
    const std::string got = i.version;
    impl_.reset();
    fail("EGL gave OpenGL ", got, " but ", options.major, ".", options.minor,
         " core is needed (update the driver, or run with --no-render)");
  }
}

EglContext::~EglContext() {
  if (!impl_ || impl_->context == EGL_NO_CONTEXT) return;
  if (eglGetCurrentContext() == impl_->context) {
    glDebugMessageCallback(nullptr, nullptr);
    eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  }
  eglDestroyContext(impl_->display, impl_->context);
  // No eglTerminate: an EGLDisplay is shared by every context of the process on
  // that platform, and terminating it would pull it from under the others.
}

const ContextInfo& EglContext::info() const { return impl_->info; }

bool EglContext::is_current() const { return eglGetCurrentContext() == impl_->context; }

void EglContext::make_current() const {
  if (is_current()) return;
  if (!eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, impl_->context))
    fail("cannot make the OpenGL context current on this thread: ", egl_error(),
         " (is it current on another thread?)");
}

void EglContext::release_current() const {
  if (is_current()) eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
}

std::vector<DebugMessage> EglContext::take_messages() {
  std::lock_guard lock(impl_->mutex);
  std::vector<DebugMessage> out;
  out.swap(impl_->messages);
  if (impl_->dropped) {
    out.push_back({0, 0, 0, GL_DEBUG_SEVERITY_LOW, cat(impl_->dropped, " further messages dropped")});
    impl_->dropped = 0;
  }
  return out;
}

int EglContext::drain_messages(Diagnostics& diag, const std::string& where) {
  int errors = 0;
  for (const DebugMessage& m : take_messages()) {
    errors += m.is_error();
    diag.warn(where, ": ", m.describe());
  }
  return errors;
}

}  // namespace softcut::gl
