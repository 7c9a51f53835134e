#include "render/renderer.hpp"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <algorithm>

#include "core/atomic_file.hpp"
#include "core/timer.hpp"
#include "gl/program.hpp"

namespace softcut::render {
namespace {

constexpr const char* kSurfaceVs = R"(#version 450 core
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec4 a_color;
uniform mat4 u_view;
uniform mat4 u_proj;
out vec3 v_pos;
out vec3 v_normal;
out vec4 v_color;
void main() {
  vec4 p = u_view * vec4(a_pos, 1.0);
  v_pos = p.xyz;
  v_normal = mat3(u_view) * a_normal;  // the view is rigid
  v_color = a_color;
  gl_Position = u_proj * p;
}
)";

// Blinn-Phong in eye space: a head light at the eye (nothing the camera sees
// is unlit) plus a dimmer fill from the upper left; both faces lit.
// u_wet: a wound's glossy highlight (sharper, brighter); u_faint: an
// inclusion seen through the tissue, fading toward its silhouette.
constexpr const char* kSurfaceFs = R"(#version 450 core
in vec3 v_pos;
in vec3 v_normal;
in vec4 v_color;
uniform int u_wet;
uniform int u_faint;
out vec4 o_color;
const vec3 kFill = normalize(vec3(-0.6, 0.7, 0.4));
void main() {
  vec3 n = normalize(v_normal);
  if (!gl_FrontFacing) n = -n;
  vec3 v = normalize(-v_pos);
  float d_head = max(dot(n, v), 0.0);
  float d_fill = max(dot(n, kFill), 0.0);
  float shine = u_wet != 0 ? 90.0 : 40.0, gloss = u_wet != 0 ? 0.45 : 0.22;
  float s_head = pow(d_head, shine);
  float s_fill = pow(max(dot(n, normalize(kFill + v)), 0.0), shine);
  vec3 c = v_color.rgb * (0.20 + 0.70 * d_head + 0.25 * d_fill) + vec3(gloss * s_head + 0.35 * gloss * s_fill);
  float a = v_color.a;
  if (u_faint != 0) a *= mix(0.15, 1.0, d_head * d_head);  // soft toward its silhouette: under a layer, not on it
  o_color = vec4(min(c, vec3(1.0)), a);
}
)";

constexpr const char* kFlatVs = R"(#version 450 core
layout(location = 0) in vec3 a_pos;
layout(location = 2) in vec4 a_color;
uniform mat4 u_view;
uniform mat4 u_proj;
out vec4 v_color;
void main() {
  gl_Position = u_proj * (u_view * vec4(a_pos, 1.0));
  v_color = a_color;
}
)";

// Lines and points become triangles here, so that every driver draws them
// alike: wide lines and point sprites are rasterised differently by Mesa
// and by hardware drivers (an NVIDIA H200 drew outlines and markers wider
// than llvmpipe: 1.7 % of a golden image's pixels), triangles by one rule.
// u_size: the line width or point diameter, pixels; u_viewport: pixels.
constexpr const char* kLineGs = R"(#version 450 core
layout(lines) in;
layout(triangle_strip, max_vertices = 4) out;
in vec4 v_color[];
out vec4 g_color;
out vec2 g_corner;
uniform vec2 u_viewport;
uniform float u_size;
void main() {
  vec4 a = gl_in[0].gl_Position, b = gl_in[1].gl_Position;
  vec4 ca = v_color[0], cb = v_color[1];
  // Cut at the near side of the eye before dividing by w.
  const float eps = 1e-6;
  if (a.w < eps && b.w < eps) return;
  if (a.w < eps) { float t = (eps - a.w) / (b.w - a.w); a = mix(a, b, t); ca = mix(ca, cb, t); }
  if (b.w < eps) { float t = (eps - b.w) / (a.w - b.w); b = mix(b, a, t); cb = mix(cb, ca, t); }
  vec2 d = (b.xy / b.w - a.xy / a.w) * u_viewport;
  float len = length(d);
  vec2 n = len > 0.0 ? vec2(-d.y, d.x) / len : vec2(0.0, 1.0);
  vec2 off = n * u_size / u_viewport;  // half the width, in NDC
  g_corner = vec2(0.0);
  g_color = ca; gl_Position = vec4(a.xy + off * a.w, a.zw); EmitVertex();
  g_color = ca; gl_Position = vec4(a.xy - off * a.w, a.zw); EmitVertex();
  g_color = cb; gl_Position = vec4(b.xy + off * b.w, b.zw); EmitVertex();
  g_color = cb; gl_Position = vec4(b.xy - off * b.w, b.zw); EmitVertex();
  EndPrimitive();
}
)";

constexpr const char* kPointGs = R"(#version 450 core
layout(points) in;
layout(triangle_strip, max_vertices = 4) out;
in vec4 v_color[];
out vec4 g_color;
out vec2 g_corner;
uniform vec2 u_viewport;
uniform float u_size;
void main() {
  vec4 p = gl_in[0].gl_Position;
  if (p.w <= 0.0) return;
  vec2 h = vec2(u_size) / u_viewport;  // half the diameter, in NDC
  for (int k = 0; k < 4; ++k) {
    vec2 c = vec2((k & 1) == 0 ? -1.0 : 1.0, k < 2 ? -1.0 : 1.0);
    g_color = v_color[0];
    g_corner = c;
    gl_Position = vec4(p.xy + c * h * p.w, p.zw);
    EmitVertex();
  }
  EndPrimitive();
}
)";

// The label pass: each fragment's distance along the view axis and its
// triangle's label id, into a float and an unsigned-integer target.
constexpr const char* kLabelVs = R"(#version 450 core
layout(location = 0) in vec3 a_pos;
layout(location = 3) in uint a_label;
uniform mat4 u_view;
uniform mat4 u_proj;
out float v_depth;
flat out uint v_label;
void main() {
  vec4 p = u_view * vec4(a_pos, 1.0);
  v_depth = -p.z;
  v_label = a_label;
  gl_Position = u_proj * p;
}
)";

constexpr const char* kLabelFs = R"(#version 450 core
in float v_depth;
flat in uint v_label;
layout(location = 0) out float o_depth;
layout(location = 1) out uint o_label;
void main() {
  o_depth = v_depth;
  o_label = v_label;
}
)";

// Points are round with a dark rim; lines use the colour as is.
constexpr const char* kFlatFs = R"(#version 450 core
in vec4 g_color;
in vec2 g_corner;
uniform int u_round;
out vec4 o_color;
void main() {
  vec4 c = g_color;
  if (u_round != 0) {
    float r2 = dot(g_corner, g_corner);
    if (r2 > 1.0) discard;
    if (r2 > 0.55) c.rgb *= 0.35;
  }
  o_color = c;
}
)";

// One vertex array with position, normal, colour and label buffers
// (attributes 0, 1, 2, 3; the label an integer attribute).
struct Batch {
  GLuint vao = 0, buf[4] = {0, 0, 0, 0};
  GLsizei count = 0;

  void create() {
    glCreateVertexArrays(1, &vao);
    glCreateBuffers(4, buf);
    const GLint sizes[3] = {3, 3, 4};
    for (GLuint a = 0; a < 3; ++a) {
      glVertexArrayVertexBuffer(vao, a, buf[a], 0, GLsizei(sizes[a] * sizeof(float)));
      glVertexArrayAttribFormat(vao, a, sizes[a], GL_FLOAT, GL_FALSE, 0);
      glVertexArrayAttribBinding(vao, a, a);
    }
    glVertexArrayVertexBuffer(vao, 3, buf[3], 0, GLsizei(sizeof(std::uint32_t)));
    glVertexArrayAttribIFormat(vao, 3, 1, GL_UNSIGNED_INT, 0);
    glVertexArrayAttribBinding(vao, 3, 3);
    glEnableVertexArrayAttrib(vao, 0);
    glEnableVertexArrayAttrib(vao, 2);
  }
  void destroy() {
    glDeleteBuffers(4, buf);
    glDeleteVertexArrays(1, &vao);
  }
  template <class V>
  static void upload(GLuint b, const std::vector<V>& v) {
    // Re-specifying the store orphans last frame's data: no stall on it.
    glNamedBufferData(b, GLsizeiptr(v.size() * sizeof(V)), v.empty() ? nullptr : v.data(), GL_STREAM_DRAW);
  }
  void set(const Triangles& t) {
    upload(buf[0], t.positions);
    upload(buf[1], t.normals);
    upload(buf[2], t.colors);
    glEnableVertexArrayAttrib(vao, 1);
    count = GLsizei(t.positions.size());
  }
  // The label ids, for the label pass (after set() of the same triangles).
  void set_labels(const Triangles& t) {
    if (t.labels.size() != t.positions.size()) fail("render: triangles with ", t.labels.size(), " labels for ",
                                                    t.positions.size(), " corners");
    upload(buf[3], t.labels);
    glEnableVertexArrayAttrib(vao, 3);
  }
  void set(const Primitives& p) {
    upload(buf[0], p.positions);
    upload(buf[2], p.colors);
    glDisableVertexArrayAttrib(vao, 1);
    count = GLsizei(p.positions.size());
  }
};

}  // namespace

FrameTimings& FrameTimings::operator+=(const FrameTimings& o) {
  extract_ms += o.extract_ms;
  upload_ms += o.upload_ms;
  draw_ms += o.draw_ms;
  readback_ms += o.readback_ms;
  encode_ms += o.encode_ms;
  write_ms += o.write_ms;
  labels_draw_ms += o.labels_draw_ms;
  labels_encode_ms += o.labels_encode_ms;
  labels_write_ms += o.labels_write_ms;
  video_ms += o.video_ms;
  return *this;
}

struct Renderer::Impl {
  gl::EglContext& ctx;
  gl::Program surface_prog, line_prog, point_prog, label_prog;
  Batch tissue, wound, inclusions, tools, wire, outline, lines, arrows, ipoints, mpoints;
  // Framebuffers: `ms` multisampled (when samples > 1), `single` the resolve
  // target and readback source (and draw target without MSAA).
  GLuint ms_fbo = 0, ms_color = 0, ms_depth = 0, fbo = 0, color = 0, depth = 0;
  int width = 0, height = 0, samples = -1;
  // The label pass's single-sample targets: distance (R32F), label (R8UI), depth.
  GLuint aux_fbo = 0, aux_dist = 0, aux_label = 0, aux_depth = 0;
  int aux_width = 0, aux_height = 0;
  std::vector<std::uint8_t> readback;
  std::vector<float> readback_depth;
  Diagnostics warnings;
  long frame = 0;

  explicit Impl(gl::EglContext& c) : ctx(c) {
    ctx.make_current();
    using gl::Stage;
    surface_prog = gl::Program("render.surface", {{Stage::vertex, kSurfaceVs}, {Stage::fragment, kSurfaceFs}});
    line_prog = gl::Program("render.line",
                            {{Stage::vertex, kFlatVs}, {Stage::geometry, kLineGs}, {Stage::fragment, kFlatFs}});
    point_prog = gl::Program("render.point",
                             {{Stage::vertex, kFlatVs}, {Stage::geometry, kPointGs}, {Stage::fragment, kFlatFs}});
    label_prog = gl::Program("render.labels", {{Stage::vertex, kLabelVs}, {Stage::fragment, kLabelFs}});
    for (Batch* b : {&tissue, &wound, &inclusions, &tools, &wire, &outline, &lines, &arrows, &ipoints, &mpoints})
      b->create();
    check("renderer setup");
  }

  ~Impl() {
    // Best effort: with the context current on another thread the GL objects
    // go with the context instead (a destructor must not throw).
    try {
      ctx.make_current();
    } catch (const Error&) {
      for (gl::Program* p : {&surface_prog, &line_prog, &point_prog, &label_prog}) p->release();  // they go with the context
      return;
    }
    for (Batch* b : {&tissue, &wound, &inclusions, &tools, &wire, &outline, &lines, &arrows, &ipoints, &mpoints})
      b->destroy();
    free_targets();
    free_aux_targets();
    ctx.take_messages();
  }

  void free_aux_targets() {
    glDeleteFramebuffers(1, &aux_fbo);
    const GLuint rbs[3] = {aux_dist, aux_label, aux_depth};
    glDeleteRenderbuffers(3, rbs);
    aux_fbo = aux_dist = aux_label = aux_depth = 0;
    aux_width = aux_height = 0;
  }

  void ensure_aux_targets(int w, int h) {
    if (w == aux_width && h == aux_height) return;
    free_aux_targets();
    glCreateRenderbuffers(1, &aux_dist);
    glNamedRenderbufferStorage(aux_dist, GL_R32F, w, h);
    glCreateRenderbuffers(1, &aux_label);
    glNamedRenderbufferStorage(aux_label, GL_R8UI, w, h);
    glCreateRenderbuffers(1, &aux_depth);
    glNamedRenderbufferStorage(aux_depth, GL_DEPTH_COMPONENT24, w, h);
    glCreateFramebuffers(1, &aux_fbo);
    glNamedFramebufferRenderbuffer(aux_fbo, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, aux_dist);
    glNamedFramebufferRenderbuffer(aux_fbo, GL_COLOR_ATTACHMENT1, GL_RENDERBUFFER, aux_label);
    glNamedFramebufferRenderbuffer(aux_fbo, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, aux_depth);
    const GLenum bufs[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glNamedFramebufferDrawBuffers(aux_fbo, 2, bufs);
    if (glCheckNamedFramebufferStatus(aux_fbo, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      fail("render: the driver cannot make a ", w, " x ", h, " depth and label framebuffer");
    aux_width = w, aux_height = h;
  }

  // Depth and labels of the tissue and tools: no multisampling, no blending,
  // back faces culled as in the colour pass, so a pixel holds the surface its
  // centre's ray meets first.
  void draw_labels(const Scene& scene, LabelImages& out, FrameTimings* t) {
    Timer timer;
    tissue.set_labels(scene.tissue);
    wound.set_labels(scene.wound);
    tools.set_labels(scene.tools);
    ensure_aux_targets(width, height);
    glBindFramebuffer(GL_FRAMEBUFFER, aux_fbo);
    glViewport(0, 0, width, height);
    const GLfloat zero_f[4] = {0, 0, 0, 0};
    const GLuint zero_u[4] = {0, 0, 0, 0};
    glClearNamedFramebufferfv(aux_fbo, GL_COLOR, 0, zero_f);
    glClearNamedFramebufferuiv(aux_fbo, GL_COLOR, 1, zero_u);
    glClearDepth(1.0);
    glDepthMask(GL_TRUE);
    glClear(GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDisable(GL_BLEND);
    glDisable(GL_POLYGON_OFFSET_FILL);
    glDisable(GL_MULTISAMPLE);
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    glFrontFace(GL_CCW);
    set_camera(label_prog, scene.camera);
    glUseProgram(label_prog.id());
    for (const Batch* b : {&tissue, &wound, &tools})
      if (b->count) {
        glBindVertexArray(b->vao);
        glDrawArrays(GL_TRIANGLES, 0, b->count);
      }
    glBindVertexArray(0);
    glDisable(GL_CULL_FACE);
    out.width = width, out.height = height;
    const size_t n = size_t(width) * size_t(height);
    readback_depth.resize(n);
    readback.resize(std::max(readback.size(), n));
    glBindFramebuffer(GL_READ_FRAMEBUFFER, aux_fbo);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glReadPixels(0, 0, width, height, GL_RED, GL_FLOAT, readback_depth.data());
    glReadBuffer(GL_COLOR_ATTACHMENT1);
    glReadPixels(0, 0, width, height, GL_RED_INTEGER, GL_UNSIGNED_BYTE, readback.data());
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    out.depth.resize(n);
    out.labels.resize(n);
    const size_t row = size_t(width);
    for (int y = 0; y < height; ++y) {  // GL rows run bottom-up
      std::copy_n(readback_depth.data() + size_t(height - 1 - y) * row, row, out.depth.data() + size_t(y) * row);
      std::copy_n(readback.data() + size_t(height - 1 - y) * row, row, out.labels.data() + size_t(y) * row);
    }
    if (t) t->labels_draw_ms = timer.ms();
  }

  void free_targets() {
    const GLuint fbos[2] = {ms_fbo, fbo}, rbs[4] = {ms_color, ms_depth, color, depth};
    glDeleteFramebuffers(2, fbos);
    glDeleteRenderbuffers(4, rbs);
    ms_fbo = ms_color = ms_depth = fbo = color = depth = 0;
  }

  // Throws on GL errors since the last check; keeps other messages as warnings.
  void check(const std::string& where) {
    std::string errors;
    for (const gl::DebugMessage& m : ctx.take_messages()) {
      if (m.is_error()) errors += (errors.empty() ? "" : "; ") + m.describe();
      else warnings.warn(where, ": ", m.describe());
    }
    for (GLenum e; (e = glGetError()) != GL_NO_ERROR;)
      if (errors.empty()) errors = cat("glGetError 0x", std::hex, e);
    if (!errors.empty()) fail("render: OpenGL failed during ", where, ": ", errors);
  }

  void ensure_targets(int w, int h, int requested) {
    const int s = requested > 1 ? std::min(requested, std::max(1, ctx.info().max_samples)) : 0;
    if (w == width && h == height && s == samples) return;
    free_targets();
    glCreateRenderbuffers(1, &color);
    glNamedRenderbufferStorage(color, GL_RGBA8, w, h);
    glCreateFramebuffers(1, &fbo);
    glNamedFramebufferRenderbuffer(fbo, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color);
    if (s > 1) {
      glCreateRenderbuffers(1, &ms_color);
      glNamedRenderbufferStorageMultisample(ms_color, s, GL_RGBA8, w, h);
      glCreateRenderbuffers(1, &ms_depth);
      glNamedRenderbufferStorageMultisample(ms_depth, s, GL_DEPTH_COMPONENT24, w, h);
      glCreateFramebuffers(1, &ms_fbo);
      glNamedFramebufferRenderbuffer(ms_fbo, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, ms_color);
      glNamedFramebufferRenderbuffer(ms_fbo, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, ms_depth);
    } else {
      glCreateRenderbuffers(1, &depth);
      glNamedRenderbufferStorage(depth, GL_DEPTH_COMPONENT24, w, h);
      glNamedFramebufferRenderbuffer(fbo, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
    }
    for (GLuint f : {fbo, ms_fbo})
      if (f && glCheckNamedFramebufferStatus(f, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        fail("render: the driver cannot make a ", w, " x ", h, " framebuffer with ", s,
             " samples (try fewer msaa_samples or a smaller frame)");
    width = w, height = h, samples = s;
  }

  void set_camera(const gl::Program& prog, const Camera& cam) {
    const Eigen::Matrix4f view = cam.view.cast<float>(), proj = cam.projection.cast<float>();
    glProgramUniformMatrix4fv(prog.id(), prog.uniform("u_view"), 1, GL_FALSE, view.data());
    glProgramUniformMatrix4fv(prog.id(), prog.uniform("u_proj"), 1, GL_FALSE, proj.data());
  }

  void draw_flat(const Batch& b, GLenum mode, float size, bool on_top) {
    if (!b.count) return;
    if (on_top) glDisable(GL_DEPTH_TEST);
    else glEnable(GL_DEPTH_TEST);
    const gl::Program& prog = mode == GL_POINTS ? point_prog : line_prog;
    glUseProgram(prog.id());
    glProgramUniform1f(prog.id(), prog.uniform("u_size"), size);
    glProgramUniform2f(prog.id(), prog.uniform("u_viewport"), float(width), float(height));
    glProgramUniform1i(prog.id(), prog.uniform("u_round"), mode == GL_POINTS);
    glBindVertexArray(b.vao);
    glDrawArrays(mode, 0, b.count);
  }

  Image draw(const Scene& scene, FrameTimings* t, LabelImages* aux) {
    ctx.make_current();
    ++frame;
    const std::string where = cat("frame ", frame);
    Timer timer;
    ensure_targets(scene.width, scene.height, scene.msaa_samples);
    tissue.set(scene.tissue);
    wound.set(scene.wound);
    inclusions.set(scene.inclusions);
    tools.set(scene.tools);
    wire.set(scene.wire);
    outline.set(scene.outline);
    arrows.set(scene.arrows);
    lines.set(scene.force_lines);
    ipoints.set(scene.interface_points);
    mpoints.set(scene.manipulated_points);
    if (t) t->upload_ms = timer.ms();

    timer.reset();
    glBindFramebuffer(GL_FRAMEBUFFER, samples > 1 ? ms_fbo : fbo);
    glViewport(0, 0, width, height);
    glClearColor(scene.background[0], scene.background[1], scene.background[2], scene.background[3]);
    glClearDepth(1.0);
    glDepthMask(GL_TRUE);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LEQUAL);
    // The context is shared (compute CG): set every state the passes rely on.
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_STENCIL_TEST);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    if (samples > 1) glEnable(GL_MULTISAMPLE);

    set_camera(surface_prog, scene.camera);
    set_camera(line_prog, scene.camera);
    set_camera(point_prog, scene.camera);
    // Tissue and tools are closed, outward-wound surfaces (a tet mesh's
    // boundary stays closed through cuts: each side of a cut is a face), so
    // only back faces are culled, nothing visible: llvmpipe shades about half
    // the fragments it would otherwise.
    // Order: tissue; then the inclusions, blended over it without depth test
    // or depth writes (their front faces only: one faint layer); then the
    // lines and points (those drawn on top write no depth, so they show
    // through tissue); then the tools, depth-tested against the tissue: an
    // instrument is never covered by an inclusion, a point or a line.
    // faint: blended over what is drawn, without depth test or polygon offset.
    auto draw_surface = [&](const Batch& b, bool faint, bool wet = false) {
      if (!b.count) return;
      glUseProgram(surface_prog.id());
      glProgramUniform1i(surface_prog.id(), surface_prog.uniform("u_wet"), wet);
      glProgramUniform1i(surface_prog.id(), surface_prog.uniform("u_faint"), faint);
      glEnable(GL_CULL_FACE);
      glCullFace(GL_BACK);
      glFrontFace(GL_CCW);
      if (faint) {
        glDisable(GL_DEPTH_TEST);
        glEnable(GL_BLEND);
        glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);  // the image keeps its alpha
      } else {
        glEnable(GL_POLYGON_OFFSET_FILL);  // pushes faces back so their edges win the depth test
        glPolygonOffset(1.0f, 1.0f);
        glEnable(GL_DEPTH_TEST);
      }
      glBindVertexArray(b.vao);
      glDrawArrays(GL_TRIANGLES, 0, b.count);
      glDisable(GL_POLYGON_OFFSET_FILL);
      glDisable(GL_BLEND);
      glDisable(GL_CULL_FACE);
      glEnable(GL_DEPTH_TEST);
    };
    draw_surface(tissue, false);
    draw_surface(wound, false, true);
    draw_surface(inclusions, true);
    draw_flat(wire, GL_LINES, scene.wire.size_px, scene.wire.on_top);
    draw_flat(outline, GL_LINES, scene.outline.size_px, scene.outline.on_top);
    draw_flat(ipoints, GL_POINTS, scene.interface_points.size_px, scene.interface_points.on_top);
    draw_flat(lines, GL_LINES, scene.force_lines.size_px, scene.force_lines.on_top);
    draw_flat(arrows, GL_LINES, scene.arrows.size_px, scene.arrows.on_top);
    draw_flat(mpoints, GL_POINTS, scene.manipulated_points.size_px, scene.manipulated_points.on_top);
    draw_surface(tools, false);
    glBindVertexArray(0);
    if (samples > 1)
      glBlitNamedFramebuffer(ms_fbo, fbo, 0, 0, width, height, 0, 0, width, height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glFinish();
    if (t) t->draw_ms = timer.ms();

    timer.reset();
    Image img;
    img.width = width;
    img.height = height;
    img.rgba.resize(size_t(width) * size_t(height) * 4);
    readback.resize(img.rgba.size());
    glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, readback.data());
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    const size_t row = size_t(width) * 4;
    for (int y = 0; y < height; ++y)  // GL rows run bottom-up, PNG rows top-down
      std::copy_n(readback.data() + size_t(height - 1 - y) * row, row, img.rgba.data() + size_t(y) * row);
    if (t) t->readback_ms = timer.ms();
    if (aux) draw_labels(scene, *aux, t);
    check(where);
    return img;
  }
};

Renderer::Renderer(gl::EglContext& context) : impl_(std::make_unique<Impl>(context)) {}
Renderer::~Renderer() = default;

Image Renderer::draw(const Scene& scene, FrameTimings* timings) { return impl_->draw(scene, timings, nullptr); }
Image Renderer::draw(const Scene& scene, FrameTimings* timings, LabelImages* aux) {
  return impl_->draw(scene, timings, aux);
}

FrameTimings Renderer::render_png(const mesh::TetMesh& mesh, const Eigen::MatrixX3d& positions,
                                  const SceneContent& content, const RenderSettings& settings,
                                  const std::filesystem::path& path) {
  FrameTimings t;
  Timer timer;
  const Scene scene = extract_scene(mesh, positions, content, settings);
  t.extract_ms = timer.ms();
  const Image img = impl_->draw(scene, &t, nullptr);
  timer.reset();
  const std::string png = encode_png(img);
  t.encode_ms = timer.ms();
  timer.reset();
  write_file_atomic(path, png);
  t.write_ms = timer.ms();
  return t;
}

int Renderer::samples() const { return std::max(0, impl_->samples); }
Diagnostics& Renderer::warnings() { return impl_->warnings; }

}  // namespace softcut::render
