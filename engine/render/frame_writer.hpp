#pragma once
// Turns extracted scenes into PNG files, off the simulation's thread when it
// may: rasterising and reading back frame N run on a worker thread while the
// simulation computes frame N + 1, and its PNG encoding, atomic file writes
// and video frame on an encoder thread while the worker draws N + 1.
//
// The worker owns the renderer and makes the application's EGL context
// current on itself, so the worker mode needs a context nobody else uses
// while frames are in flight; with the GPU solver in the same context the
// writer draws inline, on the caller's thread (the old behaviour).
//
// At most `max_pending` scenes wait (bounded memory); submit() blocks while
// the queue is full. A failure on the worker (a GL error, a full disk) is
// rethrown by the next submit() or by finish(), with the frame's file named.
#include <exception>
#include <filesystem>
#include <memory>

#include "render/renderer.hpp"
#include "render/scene.hpp"
#include "render/video_encoder.hpp"

namespace softcut {
class OutputBudget;
}
namespace softcut::render {

struct FrameWriterStats {
  int frames = 0;           // written
  FrameTimings work;        // summed upload, draw, readback, encode and write, ms (extract_ms stays 0)
  double max_work_ms = 0;   // the slowest frame's work.total_ms()
  double wait_ms = 0;       // caller blocked on a full queue (or drawing, inline), summed
};

// Where one frame's images go: the colour PNG, and optionally its depth
// and label PNGs (gray_png.hpp; empty path: not made).
struct FramePaths {
  std::filesystem::path rgb, depth, labels;
};

class FrameWriter {
 public:
  enum class Mode { inline_draw, worker };

  // `context` must outlive the writer. In worker mode it is detached from the
  // calling thread (made current again by whoever uses it next).
  // `budget` (optional, outlives the writer) bounds the bytes of all outputs.
  FrameWriter(gl::EglContext& context, Mode mode, int max_pending = 2, OutputBudget* budget = nullptr);
  // Stops after the frame in progress; frames still queued are dropped (no
  // partial files: every write is atomic). Call finish() to keep them.
  ~FrameWriter();
  FrameWriter(const FrameWriter&) = delete;
  FrameWriter& operator=(const FrameWriter&) = delete;

  // Queues the scene for `png` (inline: draws and writes it now).
  void submit(Scene scene, std::filesystem::path png);
  // The same with depth and label images when their paths are given.
  void submit(Scene scene, FramePaths paths);
  // Every frame submitted from now on also goes to `video`, from the thread
  // that draws (the worker: encoding stays off the simulation's thread).
  void attach_video(std::unique_ptr<VideoEncoder> video);
  // Waits until every submitted frame is written, then finishes the video;
  // rethrows the first failure.
  void finish();
  // The video's bytes after finish() (0: none).
  std::uintmax_t video_bytes() const;

  Mode mode() const;
  FrameWriterStats stats() const;  // consistent snapshot (after finish(): final)
  int samples() const;             // MSAA samples of the last frame drawn (0: none)

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace softcut::render
