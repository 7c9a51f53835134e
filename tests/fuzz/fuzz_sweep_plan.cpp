// libFuzzer target: the sweep_plan.json reader of softcut sweep / sweep
// merge; a plan read back must write the same plan again.
#include "app_fuzz.hpp"
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  softcut::fuzz_app::feed_sweep_plan(softcut::fuzz::as_text(data, size));
  return 0;
}
