#include "core/output_budget.hpp"

#include "core/error.hpp"

namespace softcut {

bool OutputBudget::try_charge(std::uint64_t bytes) {
  std::uint64_t now = used_.load();
  do {
    if (limit_ && (bytes > limit_ || now > limit_ - bytes)) return false;
  } while (!used_.compare_exchange_weak(now, now + bytes));
  return true;
}

void OutputBudget::charge(std::uint64_t bytes, const std::string& what) {
  if (!try_charge(bytes))
    fail(what, ": the run's output limit of ", limit_, " bytes is reached (", used(), " bytes written so far, ", bytes,
         " more asked for); write less (fewer frames or log nodes, render every n-th frame) or raise it with "
         "--max-output BYTES (0: no limit)");
}

}  // namespace softcut
