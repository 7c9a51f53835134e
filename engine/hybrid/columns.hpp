#pragma once
// Columns on demand (DESIGN.md "Only what a frame needs"): the columns of
// K*^-1 and of (KI2 K22^-1)[:, s] that belong to one surface node, computed
// from the K22 factor the first time the node is loaded (one 3-column solve)
// and kept in a bounded per-run cache, so the dense K*^-1 (3|s| x 3|s|) is
// never needed. Nodes that scripted tools will reach can be prefetched on a
// worker thread with its own CHOLMOD workspace while frames run.
//
//   cache.prefetch({12, 40});                  // surface positions, async
//   const auto c = cache.get(model, 12);       // waits for or computes it
//   As_loads += c->Kstar_inv * dF;  P' += c->KI2_K22inv * dF;
#include <Eigen/Core>
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <span>
#include <thread>
#include <vector>

#include "core/helper_thread.hpp"
#include "solve/cholesky.hpp"

namespace softcut::hybrid {

struct Model;

struct NodeColumns {
  Eigen::Matrix<double, Eigen::Dynamic, 3> Kstar_inv;   // (3|s| x 3) m/N: (K22^-1)[s, the node's DOFs]
  Eigen::Matrix<double, Eigen::Dynamic, 3> KI2_K22inv;  // (3|I| x 3): KI2 (K22^-1)[:, the node's DOFs]
  double bytes() const { return 8.0 * double(Kstar_inv.size() + KI2_K22inv.size()); }
};

struct ColumnStats {
  long hits = 0;              // get() found the node cached
  long first_touches = 0;     // get() computed the node on the calling (frame) thread
  long waited = 0;            // get() waited for the worker to finish the node
  long prefetched = 0;        // nodes computed by the worker
  long evicted = 0;           // nodes dropped to stay within max_bytes
  double first_touch_ms = 0;  // total time of the first touches
  double prefetch_ms = 0;     // total worker time
  int cached_nodes = 0;
  double bytes = 0;           // held now
  double max_bytes = 0;       // the bound
};

class ColumnCache {
 public:
  // `model` must outlive the cache. `max_bytes` bounds what is kept: the
  // least recently used nodes are dropped past it (a caller's shared_ptr
  // keeps its columns alive).
  ColumnCache(const Model& model, double max_bytes);
  ~ColumnCache();  // stops and joins the worker
  ColumnCache(const ColumnCache&) = delete;
  ColumnCache& operator=(const ColumnCache&) = delete;

  // The columns of surface position `pos` (0 <= pos < |s|).
  std::shared_ptr<const NodeColumns> get(int pos);
  // Makes sure these positions are cached (a frame's loaded nodes, before
  // their get()s): those absent are computed together, kMaxBatch nodes per
  // solve, so a frame that first touches a tool's whole contact patch reads
  // the factor once per batch, not once per node. Same bits as get() alone.
  void ensure(std::span<const int> positions);
  static constexpr int kMaxBatch = 16;
  // Queues surface positions for the worker thread (started on first use);
  // positions cached or queued already are skipped.
  void prefetch(const std::vector<int>& positions);
  // First touches on the calling thread use this helper for half of the
  // backward solve (the run's helper thread, hybrid::State; the prefetch
  // worker solves alone). The columns' bits do not depend on it.
  void share_helper(std::shared_ptr<HelperThread> helper) { helper_ = std::move(helper); }
  // Blocks until the worker's queue is empty (tests, benchmarks).
  void wait_idle();
  ColumnStats stats() const;

 private:
  // Columns of these surface positions, one 3-column-per-node solve with
  // workspace ws: a node's columns have the same bits whichever thread
  // computes them and whichever nodes come with them, so a run's results do
  // not depend on how far the prefetch got.
  std::vector<std::shared_ptr<NodeColumns>> compute(std::span<const int> pos, solve::SolveWorkspace& ws,
                                                    HelperThread* helper) const;
  void insert_locked(int pos, std::shared_ptr<const NodeColumns> c);
  void check_range(int pos) const;  // 0 <= pos < |s|, else softcut::Error
  // With mu_ held: takes pos off the worker's queue and waits while another
  // thread computes it; then, if it is absent, marks it computing for the
  // caller and returns true (false: it is cached).
  bool take_locked(int pos, std::unique_lock<std::mutex>& lk);
  // Computes positions the caller took, on the calling thread, and caches
  // them; on failure they are absent again.
  std::vector<std::shared_ptr<NodeColumns>> compute_taken(std::span<const int> positions);
  void release(std::span<const int> positions);  // taken -> absent, waiters woken
  void worker_loop();

  const Model& model_;
  double max_bytes_;
  mutable std::mutex mu_;
  std::condition_variable cv_;       // worker: work queued or stop; callers: a node finished
  std::vector<std::shared_ptr<const NodeColumns>> cols_;  // (|s|) by surface position, null if absent
  std::vector<long> last_use_;       // (|s|) use stamp for LRU eviction
  std::vector<char> state_;          // (|s|) 0 absent, 1 queued, 2 being computed, 3 cached
  long stamp_ = 0;
  std::deque<int> queue_;
  bool stop_ = false;
  ColumnStats stats_;
  solve::SolveWorkspace frame_ws_;   // for get()'s first touches (frame thread)
  solve::SolveWorkspace worker_ws_;  // for the worker
  std::shared_ptr<HelperThread> helper_;  // for get()'s first touches; may be null
  std::thread worker_;
};

}  // namespace softcut::hybrid
