#include "core/helper_thread.hpp"

#include <algorithm>
#include <chrono>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#define SOFTCUT_PAUSE() _mm_pause()
#else
#define SOFTCUT_PAUSE() std::this_thread::yield()
#endif

namespace softcut {

namespace {
// The job word: id (high 32 bits) | item count (bits 16..31) | items claimed
// (low 16 bits). The count is part of the word a claim compares and swaps,
// so a claim can only succeed on the job it read the count of.
constexpr uint64_t kIdUnit = uint64_t(1) << 32;
constexpr uint64_t kCountUnit = uint64_t(1) << 16;
uint64_t next_id(uint64_t job) { return ((job >> 32) + 1) << 32; }
uint64_t claimed(uint64_t job) { return job & (kCountUnit - 1); }
uint64_t count_of(uint64_t job) { return (job >> 16) & (kCountUnit - 1); }
}  // namespace

HelperThread::HelperThread() : thread_([this] { loop(); }) {}

HelperThread::~HelperThread() {
  stop_.store(true);
  job_.store(next_id(job_.load()));  // a job with nothing to claim
  job_.notify_one();
  thread_.join();
}

bool HelperThread::claim(uint64_t& job, int& item) {
  // job: the last word read; on return, the last word this thread saw.
  while (claimed(job) < count_of(job))
    if (job_.compare_exchange_weak(job, job + 1, std::memory_order_acq_rel, std::memory_order_acquire)) {
      item = int(claimed(job));
      ++job;
      return true;
    }
  return false;
}

void HelperThread::wake() {
  job_.store(next_id(job_.load(std::memory_order_relaxed)));  // nothing to claim
  if (sleeping_.load()) job_.notify_one();
}

void HelperThread::publish(int count, int taken, const std::function<void(int)>& fn) {
  fn_ = &fn;
  done_.store(0, std::memory_order_relaxed);
  count_.store(count, std::memory_order_relaxed);
  // Publishes fn_, count_ and done_ (a seq_cst store releases them).
  job_.store(next_id(job_.load(std::memory_order_relaxed)) | (uint64_t(count) << 16) | uint64_t(taken));
  if (sleeping_.load()) job_.notify_one();
}

void HelperThread::finish_and_wait() {
  int item = 0;
  for (uint64_t job = job_.load(std::memory_order_acquire); !leave_to_helper_.load() && claim(job, item);) {
    // what the helper has not taken
    (*fn_)(item);
    done_.fetch_add(1, std::memory_order_release);
  }
  // The helper holds the rest: it is running it now.
  const int count = count_.load(std::memory_order_relaxed);
  for (int spins = 0; done_.load(std::memory_order_acquire) < count; ++spins)
    if (spins < 4096) SOFTCUT_PAUSE();
    else std::this_thread::yield();
}

void HelperThread::run_halves(const std::function<void(int)>& fn) {
  // Published with half 0 already taken: it is the caller's, so each core
  // keeps reading the same rows.
  publish(2, 1, fn);
  fn(0);
  done_.fetch_add(1, std::memory_order_release);
  finish_and_wait();
}

void HelperThread::run_items(int count, const std::function<void(int)>& fn) {
  constexpr int kMaxItems = int(kCountUnit - 1);  // per job word; more come in rounds
  for (int base = 0; base < count; base += kMaxItems) {
    const int n = std::min(kMaxItems, count - base);
    const std::function<void(int)> shifted = [&](int k) { fn(base + k); };
    publish(n, 0, base == 0 ? fn : shifted);
    finish_and_wait();
  }
}

void HelperThread::loop() {
  using Clock = std::chrono::steady_clock;
  // The word job_ was constructed with: a job published before this thread
  // first looks is new to it (it was taken as seen, and left to the caller).
  uint64_t seen = 0;
  while (!stop_.load()) {
    Clock::time_point since = Clock::now();
    for (int spins = 0;; ++spins) {
      const uint64_t job = job_.load(std::memory_order_acquire);
      if (job != seen) {
        int item = 0;
        uint64_t w = job;
        while (claim(w, item)) {
          (*fn_)(item);
          helped_.fetch_add(1, std::memory_order_relaxed);
          done_.fetch_add(1, std::memory_order_release);
        }
        seen = w;  // the last word seen: a job published after it is noticed
        since = Clock::now();
        spins = 0;
        continue;
      }
      if (stop_.load(std::memory_order_relaxed)) return;
      SOFTCUT_PAUSE();
      if (spins % 64 == 63 &&
          Clock::now() - since > std::chrono::microseconds(kSpinMicroseconds))
        break;
    }
    // Sleep until the next job (or wake): the store of sleeping_ and the
    // caller's store of job_ are both seq_cst, so either the caller sees
    // sleeping_ and notifies, or this thread sees the new job and skips the wait.
    sleeping_.store(true);
    if (job_.load() == seen && !stop_.load()) job_.wait(seen);
    sleeping_.store(false);
  }
}

void run_halves(HelperThread* helper, const std::function<void(int)>& fn) {
  if (helper) {
    helper->run_halves(fn);
  } else {
    fn(0);
    fn(1);
  }
}

}  // namespace softcut
