#include "hybrid/columns.hpp"

#include <algorithm>

#include "core/error.hpp"
#include "core/timer.hpp"
#include "hybrid/precompute.hpp"

namespace softcut::hybrid {

namespace {
enum : char { absent = 0, queued = 1, computing = 2, cached = 3 };
}  // namespace

ColumnCache::ColumnCache(const Model& model, double max_bytes) : model_(model), max_bytes_(max_bytes) {
  const size_t ns = size_t(model.ns());
  cols_.resize(ns);
  last_use_.assign(ns, 0);
  state_.assign(ns, absent);
  stats_.max_bytes = max_bytes;
}

ColumnCache::~ColumnCache() {
  {
    std::lock_guard lk(mu_);
    stop_ = true;
  }
  cv_.notify_all();
  if (worker_.joinable()) worker_.join();
}

std::vector<std::shared_ptr<NodeColumns>> ColumnCache::compute(std::span<const int> pos, solve::SolveWorkspace& ws,
                                                                HelperThread* helper) const {
  // K22^-1 on unit right-hand sides at the nodes' DOFs (surface position p
  // is K22 node p: surface nodes come first in the K22 order). The forward
  // half walks only the elimination-tree paths of those DOFs, so a batch
  // costs about one backward solve, not a whole solve.
  // A simplicial factor (a small K22) is solved node by node: CHOLMOD's
  // solve takes its right-hand sides in groups whose loops sum differently.
  if (pos.size() > 1 && !model_.K22.supernodal()) {
    std::vector<std::shared_ptr<NodeColumns>> out;
    for (const int& p : pos) out.push_back(compute(std::span<const int>(&p, 1), ws, helper).front());
    return out;
  }
  std::vector<int> dofs;
  for (int p : pos) dofs.insert(dofs.end(), {3 * p, 3 * p + 1, 3 * p + 2});
  Eigen::MatrixXd Y, X;
  model_.K22.forward_unit_into(dofs, Y, ws);
  model_.K22.backward_into(Y, X, ws, helper);
  std::vector<std::shared_ptr<NodeColumns>> out;
  for (size_t j = 0; j < pos.size(); ++j) {
    auto c = std::make_shared<NodeColumns>();
    const auto Xj = X.middleCols<3>(3 * Eigen::Index(j));
    c->Kstar_inv = Xj.topRows(3 * Eigen::Index(model_.ns()));
    c->KI2_K22inv = model_.KI2 * Xj;
    out.push_back(std::move(c));
  }
  return out;
}

void ColumnCache::insert_locked(int pos, std::shared_ptr<const NodeColumns> c) {
  stats_.bytes += c->bytes();
  ++stats_.cached_nodes;
  cols_[size_t(pos)] = std::move(c);
  state_[size_t(pos)] = cached;
  last_use_[size_t(pos)] = ++stamp_;
  while (stats_.bytes > max_bytes_ && stats_.cached_nodes > 1) {
    int lru = -1;
    for (size_t q = 0; q < cols_.size(); ++q)
      if (state_[q] == cached && int(q) != pos && (lru < 0 || last_use_[q] < last_use_[size_t(lru)])) lru = int(q);
    if (lru < 0) break;
    stats_.bytes -= cols_[size_t(lru)]->bytes();
    --stats_.cached_nodes;
    ++stats_.evicted;
    cols_[size_t(lru)].reset();
    state_[size_t(lru)] = absent;
  }
}

bool ColumnCache::take_locked(int pos, std::unique_lock<std::mutex>& lk) {
  if (state_[size_t(pos)] == queued) {  // not started by the worker: computed here, now
    queue_.erase(std::find(queue_.begin(), queue_.end(), pos));
    state_[size_t(pos)] = absent;
  }
  if (state_[size_t(pos)] == computing) {
    ++stats_.waited;
    cv_.wait(lk, [&] { return state_[size_t(pos)] != computing; });
  }
  if (state_[size_t(pos)] != absent) return false;
  state_[size_t(pos)] = computing;  // by this thread: prefetch() and the worker leave it alone
  return true;
}

void ColumnCache::release(std::span<const int> positions) {
  std::lock_guard lk(mu_);
  for (int pos : positions) state_[size_t(pos)] = absent;
  cv_.notify_all();
}

std::vector<std::shared_ptr<NodeColumns>> ColumnCache::compute_taken(std::span<const int> positions) {
  Timer t;
  std::vector<std::shared_ptr<NodeColumns>> cols;
  try {
    cols = compute(positions, frame_ws_, helper_.get());
  } catch (...) {
    release(positions);
    throw;
  }
  std::lock_guard lk(mu_);
  stats_.first_touches += long(positions.size());
  stats_.first_touch_ms += t.ms();
  for (size_t j = 0; j < positions.size(); ++j) insert_locked(positions[j], cols[j]);
  cv_.notify_all();
  return cols;
}

void ColumnCache::check_range(int pos) const {
  if (pos < 0 || pos >= model_.ns()) fail("column cache: surface position ", pos, " out of range [0, ", model_.ns(), ")");
}

std::shared_ptr<const NodeColumns> ColumnCache::get(int pos) {
  check_range(pos);
  {
    std::unique_lock lk(mu_);
    if (!take_locked(pos, lk)) {  // cached
      ++stats_.hits;
      last_use_[size_t(pos)] = ++stamp_;
      return cols_[size_t(pos)];
    }
  }
  const int one[1] = {pos};
  return compute_taken(one).front();
}

void ColumnCache::ensure(std::span<const int> positions) {
  for (int pos : positions) check_range(pos);
  std::vector<int> todo;
  todo.reserve(positions.size());  // no allocation once positions are marked computing
  {
    std::unique_lock lk(mu_);
    for (int pos : positions)
      if (std::find(todo.begin(), todo.end(), pos) == todo.end() && take_locked(pos, lk)) todo.push_back(pos);
  }
  for (size_t b = 0; b < todo.size(); b += kMaxBatch) {
    const size_t w = std::min<size_t>(kMaxBatch, todo.size() - b);
    try {
      compute_taken(std::span<const int>(todo).subspan(b, w));
    } catch (...) {
      release(std::span<const int>(todo).subspan(b + w));  // the batches not reached
      throw;
    }
  }
}

void ColumnCache::prefetch(const std::vector<int>& positions) {
  {
    std::lock_guard lk(mu_);
    for (int pos : positions) {
      if (pos < 0 || pos >= model_.ns())
        fail("column cache: prefetch of surface position ", pos, " out of range [0, ", model_.ns(), ")");
      if (state_[size_t(pos)] != absent) continue;
      state_[size_t(pos)] = queued;
      queue_.push_back(pos);
    }
    if (queue_.empty() || worker_.joinable()) {
      cv_.notify_all();
      return;
    }
  }
  worker_ = std::thread([this] { worker_loop(); });
}

void ColumnCache::worker_loop() {
  std::unique_lock lk(mu_);
  for (;;) {
    cv_.wait(lk, [&] { return stop_ || !queue_.empty(); });
    if (stop_) return;
    const int pos = queue_.front();
    queue_.pop_front();
    state_[size_t(pos)] = computing;
    lk.unlock();
    Timer t;
    std::shared_ptr<NodeColumns> c;
    try {
      const int one[1] = {pos};
      c = compute(one, worker_ws_, nullptr).front();
    } catch (...) {
      c.reset();  // get() recomputes on the frame thread and reports the error there
    }
    lk.lock();
    stats_.prefetch_ms += t.ms();
    if (c) {
      insert_locked(pos, std::move(c));
      ++stats_.prefetched;
    } else {
      state_[size_t(pos)] = absent;
    }
    cv_.notify_all();
  }
}

void ColumnCache::wait_idle() {
  std::unique_lock lk(mu_);
  cv_.wait(lk, [&] {
    return queue_.empty() && std::none_of(state_.begin(), state_.end(), [](char s) { return s == computing; });
  });
}

ColumnStats ColumnCache::stats() const {
  std::lock_guard lk(mu_);
  return stats_;
}

}  // namespace softcut::hybrid
