// libFuzzer target: softcut sweep merge's reader of a run's summary.json.
#include "app_fuzz.hpp"
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  softcut::fuzz_app::feed_summary(softcut::fuzz::as_text(data, size));
  return 0;
}
