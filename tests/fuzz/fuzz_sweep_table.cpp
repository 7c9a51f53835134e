// libFuzzer target: softcut sweep's --table reader (a CSV file).
#include "app_fuzz.hpp"
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  softcut::fuzz_app::feed_sweep_table(softcut::fuzz::as_text(data, size), softcut::fuzz::scratch());
  return 0;
}
