#pragma once
// The bound on what one run writes to disk, all files together (frames, logs,
// VTU, the script's own files): `softcut run --max-output BYTES`. Shared by
// the frame loop, the frame writer's thread and the Lua sandbox.
#include <atomic>
#include <cstdint>
#include <string>

namespace softcut {

class OutputBudget {
 public:
  // limit 0: unlimited.
  explicit OutputBudget(std::uint64_t limit = 0) : limit_(limit) {}

  // Counts `bytes` that `what` is about to write; throws softcut::Error
  // (naming `what`, the limit and --max-output) when they do not fit, and
  // then counts nothing.
  void charge(std::uint64_t bytes, const std::string& what);
  // The same without a message: false (and nothing counted) when they do not fit.
  bool try_charge(std::uint64_t bytes);

  std::uint64_t used() const { return used_.load(); }
  std::uint64_t limit() const { return limit_; }

 private:
  std::uint64_t limit_;
  std::atomic<std::uint64_t> used_{0};
};

}  // namespace softcut
