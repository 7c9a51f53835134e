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

  gl::EglContext& ctx;
  OutputBudget* budget = nullptr;  // bytes written, all outputs of the run (optional)
  const Mode mode;
  const size_t max_pending;
  std::optional<Renderer> renderer;  // inline mode; the worker keeps its own
  std::unique_ptr<VideoEncoder> video;  // used by whoever draws; finished by finish()
  std::uintmax_t video_bytes = 0;

  mutable std::mutex mutex;
  std::condition_variable changed;  // queue, busy or failure changed
  std::deque<Job> queue;
  bool busy = false, stop = false;
  std::exception_ptr failure;
  FrameWriterStats stats;
  int samples = 0;
  std::thread worker;

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
      pthread_sigmask(SIG_SETMASK, &old, nullptr);
    }
    std::unique_lock lock(mutex);
    changed.wait(lock, [&] { return ready; });
    if (setup_failure) {
      lock.unlock();
      worker.join();
      std::rethrow_exception(setup_failure);
    }
  }

  ~Impl() {
    if (!worker.joinable()) return;
    {
      std::lock_guard lock(mutex);
      stop = true;
      queue.clear();
    }
    changed.notify_all();
    worker.join();
  }

  // Draws, encodes and writes one frame (its depth and label images and its
  // video frame too, when asked); returns its timings.
  static FrameTimings write_frame(Renderer& r, const Job& job, OutputBudget* budget, VideoEncoder* video) {
    const FramePaths& p = job.paths;
    try {
      FrameTimings t;
      LabelImages aux;
      const bool want_aux = !p.depth.empty() || !p.labels.empty();
      const Image img = r.draw(job.scene, &t, want_aux ? &aux : nullptr);
      Timer timer;
      const std::string png = encode_png(img);
      t.encode_ms = timer.ms();
      timer.reset();
      if (budget) budget->charge(png.size(), p.rgb.filename().string());
      write_file_atomic(p.rgb, png);
      t.write_ms = timer.ms();
      for (const auto& [path, depth] : {std::pair{&p.depth, true}, std::pair{&p.labels, false}}) {
        if (path->empty()) continue;
        timer.reset();
        const std::string gray = depth ? encode_png(depth_image(aux)) : encode_png(label_image(aux));
        t.labels_encode_ms += timer.ms();
        timer.reset();
        if (budget) budget->charge(gray.size(), path->filename().string());
        write_file_atomic(*path, gray);
        t.labels_write_ms += timer.ms();
      }
      if (video) {
        timer.reset();
        video->add(img);
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
      FrameTimings t;
      try {
        t = write_frame(*r, job, budget, video.get());
      } catch (...) {
        error = std::current_exception();
      }
      lock.lock();
      busy = false;
      if (error) {
        failure = error;
        queue.clear();  // later frames would only repeat the failure
      } else {
        account(t, r->samples());
      }
      lock.unlock();
      changed.notify_all();
    }
    r.reset();  // GL objects go while the context is still current here
    ctx.release_current();
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
      const FrameTimings t = write_frame(*renderer, Job{std::move(scene), std::move(paths)}, budget, video.get());
      stats.wait_ms += timer.ms();
      account(t, renderer->samples());
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
      changed.wait(lock, [&] { return failure || (queue.empty() && !busy); });
      stats.wait_ms += timer.ms();
      rethrow_failure(lock);
    }
    // Every frame is in the video now (the worker is idle): end it.
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
