#pragma once
// OpenGL drawing of a Scene into an off-screen framebuffer, read back as an
// Image. Created once per run on the application's EGL context and reused for
// every frame: shaders, buffers and framebuffers are made once and resized
// only when the frame size or sample count changes.
//
// Passes: multisampled colour + depth renderbuffers (resolved by a blit into a
// single-sample one); tissue and tool triangles (closed surfaces, back faces
// culled) lit by Blinn-Phong with a head light and a fill light; wireframe
// lines over a polygon-offset fill; points and force lines,
// optionally on top of everything; glReadPixels, rows flipped to top-down.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <vector>

#include "core/error.hpp"
#include "gl/egl_context.hpp"
#include "render/image.hpp"
#include "render/scene.hpp"

namespace softcut::render {

// Milliseconds spent per stage of one frame (zero for stages not run).
struct FrameTimings {
  double extract_ms = 0;   // extract_scene (CPU)
  double upload_ms = 0;    // vertex data to GL buffers
  double draw_ms = 0;      // draw calls, MSAA resolve, glFinish
  double readback_ms = 0;  // glReadPixels and row flip
  double encode_ms = 0;    // PNG encoding
  double write_ms = 0;     // atomic file write
  // Depth and label images (when asked): their pass (draw and read-back),
  // their PNG encoding and their files' writes; the video: handing the frame to ffmpeg.
  double labels_draw_ms = 0, labels_encode_ms = 0, labels_write_ms = 0;
  double video_ms = 0;

  double rgb_ms() const { return upload_ms + draw_ms + readback_ms + encode_ms + write_ms; }
  double labels_ms() const { return labels_draw_ms + labels_encode_ms + labels_write_ms; }
  double total_ms() const { return extract_ms + rgb_ms() + labels_ms() + video_ms; }
  FrameTimings& operator+=(const FrameTimings& o);
};

// What each pixel shows, from a pass without multisampling (so nothing is
// averaged across an edge: a pixel is the surface its centre's ray meets
// first). Rows top to bottom, like Image.
struct LabelImages {
  int width = 0, height = 0;
  std::vector<float> depth;            // distance along the view axis, m (eye-space -z); 0: background
  std::vector<std::uint8_t> labels;    // Triangles::labels of that surface; 0: background
};

class Renderer {
 public:
  // Makes `context` current and builds the GL objects; the context must
  // outlive the renderer. Throws softcut::Error when a shader does not build.
  explicit Renderer(gl::EglContext& context);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Draws the scene; the image has scene.width x scene.height pixels, top row
  // first. A GL error during the frame throws softcut::Error with the driver's
  // message; other driver messages go to warnings().
  Image draw(const Scene& scene, FrameTimings* timings = nullptr);
  // The same, and with `aux` the depth and label images of the tissue and
  // tools (inclusions, lines and points are not in them) from a second pass.
  Image draw(const Scene& scene, FrameTimings* timings, LabelImages* aux);

  // extract_scene + draw + write_png(path) in one call; returns the timings.
  FrameTimings render_png(const mesh::TetMesh& mesh, const Eigen::MatrixX3d& positions, const SceneContent& content,
                          const RenderSettings& settings, const std::filesystem::path& path);

  int samples() const;                // MSAA samples of the last frame (0: none)
  Diagnostics& warnings();            // non-error driver messages, with the frame they came from

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace softcut::render
