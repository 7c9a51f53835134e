#include "render/frame_writer.hpp"

#include <pthread.h>

#include <algorithm>
#include <csignal>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <optional>
#include <thread>
#include <utility>

#include "core/atomic_file.hpp"
#include "core/output_budget.hpp"
#include "core/error.hpp"
#include "core/timer.hpp"
#include "render/gray_png.hpp"

namespace softcut::render {

struct FrameWriter::Impl {
  struct Job {
    Scene scene;
    FramePaths paths;
  };
  // A frame drawn and read back, waiting for its PNGs (worker mode: the
  // encoder thread encodes and writes frame N while the drawing thread draws
  // N + 1; on llvmpipe the PNG was a third of the drawing side's time).
  struct Drawn {
    Image image;
    LabelImages aux;
    FramePaths paths;
    FrameTimings timings;  // of the drawing so far
    int samples = 0;
  };

  gl::EglContext& ctx;
  OutputBudget* budget = nullptr;  // bytes written, all outputs of the run (optional)
  const Mode mode;
  const size_t max_pending;
  std::optional<Renderer> renderer;  // inline mode; the worker keeps its own
  std::unique_ptr<VideoEncoder> video;  // used by whoever draws; finished by finish()
  std::uintmax_t video_bytes = 0;

  mutable std::mutex mutex;
  std::condition_variable changed;  // a queue, busy or failure changed
  std::deque<Job> queue;            // to draw
  std::optional<Drawn> drawn;       // to encode and write (one waits at most)
  bool busy = false, encoding = false, stop = false;
  std::exception_ptr failure;
  FrameWriterStats stats;
  int samples = 0;
  std::thread worker, encoder;

  Impl(gl::EglContext& c, Mode m, int pending, OutputBudget* b)
      : ctx(c), budget(b), mode(m), max_pending(size_t(std::max(1, pending))) {
    if (mode == Mode::inline_draw) {
      renderer.emplace(ctx);
      return;
    }
    // The renderer is made on the worker (GL objects belong to the thread
    // that has the context current); wait for it so a shader or context
    // failure surfaces here, in the constructor.
    ctx.release_current();
    std::exception_ptr setup_failure;
    bool ready = false;
    {
      // The worker never takes SIGINT / SIGTERM: the frame thread's handler
      // decides, and a second signal (which kills) lands there, not mid-write.
      sigset_t block, old;
      sigemptyset(&block);
      sigaddset(&block, SIGINT);
      sigaddset(&block, SIGTERM);
      pthread_sigmask(SIG_BLOCK, &block, &old);
      worker = std::thread([this, &setup_failure, &ready] { run(setup_failure, ready); });
      encoder = std::thread([this] { encode_loop(); });
      pthread_sigmask(SIG_SETMASK, &old, nullptr);
    }
    std::unique_lock lock(mutex);
    changed.wait(lock, [&] { return ready; });
    if (setup_failure) {
      stop = true;
      lock.unlock();
      changed.notify_all();
      worker.join();
      encoder.join();
      std::rethrow_exception(setup_failure);
    }
  }

  ~Impl() {
    if (!worker.joinable()) return;
    {
      std::lock_guard lock(mutex);
      stop = true;
      queue.clear();
      drawn.reset();
    }
    changed.notify_all();
    worker.join();
    encoder.join();
  }

  // Draws one frame and reads it back (its depth and label images too, when asked).
  static Drawn draw_frame(Renderer& r, Job& job) {
    try {
      Drawn d;
      const bool want_aux = !job.paths.depth.empty() || !job.paths.labels.empty();
      d.image = r.draw(job.scene, &d.timings, want_aux ? &d.aux : nullptr);
      d.samples = r.samples();
      d.paths = std::move(job.paths);  // after the draw: a failure names the file
      return d;
    } catch (const Error& e) {
      fail("frame ", job.paths.rgb.string(), ": ", e.what());
    }
  }

  // Encodes and writes a drawn frame's PNGs (and hands it to the video);
  // returns its timings, the drawing's included.
  static FrameTimings write_frame(const Drawn& d, OutputBudget* budget, VideoEncoder* video) {
    const FramePaths& p = d.paths;
    try {
      FrameTimings t = d.timings;
      Timer timer;
      const std::string png = encode_png(d.image);
      t.encode_ms = timer.ms();
      timer.reset();
      if (budget) budget->charge(png.size(), p.rgb.filename().string());
      write_file_atomic(p.rgb, png);
      t.write_ms = timer.ms();
      for (const auto& [path, depth] : {std::pair{&p.depth, true}, std::pair{&p.labels, false}}) {
        if (path->empty()) continue;
        timer.reset();
        const std::string gray = depth ? encode_png(depth_image(d.aux)) : encode_png(label_image(d.aux));
        t.labels_encode_ms += timer.ms();
        timer.reset();
        if (budget) budget->charge(gray.size(), path->filename().string());
        write_file_atomic(*path, gray);
        t.labels_write_ms += timer.ms();
      }
      if (video) {
        timer.reset();
        video->add(d.image);
        t.video_ms = timer.ms();
      }
      return t;
    } catch (const Error& e) {
      fail("frame ", p.rgb.string(), ": ", e.what());
    }
  }

  void account(const FrameTimings& t, int drawn_samples) {
    stats.frames++;
    stats.work += t;
    stats.max_work_ms = std::max(stats.max_work_ms, t.total_ms());
    samples = drawn_samples;
  }

  void run(std::exception_ptr& setup_failure, bool& ready) {
    std::optional<Renderer> r;
    try {
      r.emplace(ctx);
    } catch (...) {
      setup_failure = std::current_exception();
    }
    {
      std::lock_guard lock(mutex);
      ready = true;
    }
    changed.notify_all();
    if (!r) {
      ctx.release_current();
      return;
    }
    for (;;) {
      std::unique_lock lock(mutex);
      changed.wait(lock, [&] { return stop || !queue.empty(); });
      if (stop) break;
      Job job = std::move(queue.front());
      queue.pop_front();
      busy = true;
      lock.unlock();
      std::exception_ptr error;
      std::optional<Drawn> d;
      try {
        d = draw_frame(*r, job);
      } catch (...) {
        error = std::current_exception();
      }
      lock.lock();
      if (error) {
        fail_all(error);
      } else {
        // One drawn frame waits at most: the next draw overlaps its encoding.
        changed.wait(lock, [&] { return stop || failure || !drawn; });
        if (!stop && !failure) drawn = std::move(d);
      }
      busy = false;
      lock.unlock();
      changed.notify_all();
    }
    r.reset();  // GL objects go while the context is still current here
    ctx.release_current();
  }

  // A failure on either thread: later frames would only repeat it.
  void fail_all(std::exception_ptr error) {
    if (!failure) failure = error;
    queue.clear();
    drawn.reset();
  }

  // The encoder thread: PNGs, files and the video of drawn frames, in order.
  void encode_loop() {
    for (;;) {
      std::unique_lock lock(mutex);
      changed.wait(lock, [&] { return stop || drawn; });
      if (stop) break;
      Drawn d = std::move(*drawn);
      drawn.reset();
      encoding = true;
      lock.unlock();
      changed.notify_all();  // the drawing thread may hand over the next
      std::exception_ptr error;
      FrameTimings t;
      try {
        t = write_frame(d, budget, video.get());
      } catch (...) {
        error = std::current_exception();
      }
      lock.lock();
      encoding = false;
      if (error) fail_all(error);
      else account(t, d.samples);
      lock.unlock();
      changed.notify_all();
    }
  }

  void rethrow_failure(std::unique_lock<std::mutex>& lock) {
    if (!failure) return;
    std::exception_ptr e = failure;
    lock.unlock();
    std::rethrow_exception(e);
  }

  void submit(Scene scene, FramePaths paths) {
    if (mode == Mode::inline_draw) {
      Timer timer;
      Job job{std::move(scene), std::move(paths)};
      const Drawn d = draw_frame(*renderer, job);
      const FrameTimings t = write_frame(d, budget, video.get());
      stats.wait_ms += timer.ms();
      account(t, d.samples);
      return;
    }
    Timer timer;
    std::unique_lock lock(mutex);
    changed.wait(lock, [&] { return failure || queue.size() < max_pending; });
    stats.wait_ms += timer.ms();
    rethrow_failure(lock);
    queue.push_back(Job{std::move(scene), std::move(paths)});
    lock.unlock();
    changed.notify_all();
  }

  void finish() {
    if (mode == Mode::worker) {
      Timer timer;
      std::unique_lock lock(mutex);
      changed.wait(lock, [&] { return failure || (queue.empty() && !busy && !drawn && !encoding); });
      stats.wait_ms += timer.ms();
      rethrow_failure(lock);
    }
    // Every frame is in the video now (both threads are idle): end it.
    if (video) {
      std::unique_ptr<VideoEncoder> v = std::move(video);
      video_bytes = v->finish();
      if (budget) budget->charge(video_bytes, v->path().filename().string());
    }
  }
};

FrameWriter::FrameWriter(gl::EglContext& context, Mode mode, int max_pending, OutputBudget* budget)
    : impl_(std::make_unique<Impl>(context, mode, max_pending, budget)) {}
FrameWriter::~FrameWriter() = default;

void FrameWriter::submit(Scene scene, std::filesystem::path png) {
  impl_->submit(std::move(scene), FramePaths{std::move(png), {}, {}});
}
void FrameWriter::submit(Scene scene, FramePaths paths) { impl_->submit(std::move(scene), std::move(paths)); }

void FrameWriter::attach_video(std::unique_ptr<VideoEncoder> video) {
  // Before the next frame is queued: the worker reads `video` only while it draws a queued frame.
  impl_->finish();
  impl_->video = std::move(video);
}

std::uintmax_t FrameWriter::video_bytes() const { return impl_->video_bytes; }
void FrameWriter::finish() { impl_->finish(); }
FrameWriter::Mode FrameWriter::mode() const { return impl_->mode; }

FrameWriterStats FrameWriter::stats() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->stats;
}

int FrameWriter::samples() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->samples;
}

}  // namespace softcut::render
