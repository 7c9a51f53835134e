#pragma once
// A second thread for a frame's bandwidth-bound dense products (stage 4's
// product with a small system's kept inverse, stage 5's (K*^-1 P*) AI) and
// a first touch's backward solve (solve/cholesky: subtrees as items): the
// products come in two fixed halves; the caller takes the first, the helper the
// second when it is awake, and the caller takes whatever is left unclaimed.
// Each half is always the same rows, so a frame gives the same bits whoever
// computed which half, and the rows each core reads stay in its own L2
// (upper leg, 2 cores: 837 x 153 product 12.0 -> 7.3 us).
//
// Under load the caller never waits for a helper that is not running: a
// half the helper has not claimed yet is done by the caller. The helper
// spins for at most kSpinMicroseconds after a job or a wake(), then sleeps
// on a futex (std::atomic::wait); wake() at the start of a frame has it
// spinning by the time the products come.
//
//   HelperThread h;
//   h.wake();                                  // frame starts
//   h.run_halves([&](int half) { ... });       // half 0 and 1, each exactly once
#include <atomic>
#include <cstdint>
#include <functional>
#include <thread>

namespace softcut {

class HelperThread {
 public:
  static constexpr int kSpinMicroseconds = 100;

  HelperThread();
  ~HelperThread();
  HelperThread(const HelperThread&) = delete;
  HelperThread& operator=(const HelperThread&) = delete;

  // Has the helper spin (ready for run_halves) for up to kSpinMicroseconds.
  void wake();
  // Calls fn(0) and fn(1), each exactly once, fn(0) on this thread; returns
  // when both have returned. fn must not throw. One caller at a time.
  void run_halves(const std::function<void(int)>& fn);
  // Calls fn(0) .. fn(count - 1), each exactly once, claimed in that order
  // by this thread and the helper as each finishes its last; returns when
  // all have returned. A helper that gets little of its core (another
  // process's, or a BLAS thread spinning on it) then holds up the caller
  // by at most one item. fn must not throw. One caller at a time.
  void run_items(int count, const std::function<void(int)>& fn);
  // Items (halves included) the helper computed so far (for tests and the bench).
  long helped() const { return helped_.load(std::memory_order_relaxed); }
  // For tests: the caller leaves every item it has not started to the helper
  // and waits for it (run_halves still runs half 0 on the caller), so a test
  // of "the same bits whoever computed what" sees the helper's work on a
  // loaded machine too, where the caller would otherwise often take both.
  void leave_to_helper(bool on) { leave_to_helper_.store(on); }

 private:
  void loop();
  bool claim(uint64_t& job, int& item);
  // Publishes a job of `count` items with the first `taken` already the caller's.
  void publish(int count, int taken, const std::function<void(int)>& fn);
  void finish_and_wait();

  // The job word: job id | item count | items claimed (helper_thread.cpp).
  // A claim is a compare-and-swap on it, so a stale helper can never claim
  // an item of a newer job, nor with an older job's count.
  std::atomic<uint64_t> job_{0};
  std::atomic<int> count_{2};           // items of the current job (the caller's wait)
  std::atomic<int> done_{0};            // items finished of the current job
  std::atomic<bool> sleeping_{false};
  std::atomic<bool> stop_{false};
  std::atomic<long> helped_{0};
  std::atomic<bool> leave_to_helper_{false};
  const std::function<void(int)>* fn_ = nullptr;  // valid while a job runs
  std::thread thread_;
};

// fn(0) and fn(1) through helper->run_halves, or both on this thread when
// there is no helper: the same halves either way.
void run_halves(HelperThread* helper, const std::function<void(int)>& fn);

// work(first, count) over rows [0, n) in two fixed halves split at a
// multiple of 8 (each half's rows start aligned), through run_halves; below
// 64 rows a single call work(0, n). The split depends on n alone: same bits
// with or without a helper.
template <class Work>
void row_halves(HelperThread* helper, long n, const Work& work) {
  if (n < 64) {
    work(0L, n);
    return;
  }
  const long h = (n / 2 + 7) / 8 * 8;
  run_halves(helper, [&](int k) { k == 0 ? work(0L, h) : work(h, n - h); });
}

}  // namespace softcut
