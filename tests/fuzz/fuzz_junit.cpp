// libFuzzer target: softcut check's JUnit writer. The input's NUL-separated
// fields become scenario names, files, reasons and expectation messages;
// the XML written must be well-formed (app_fuzz.hpp checks it and traps).
#include "app_fuzz.hpp"
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  softcut::fuzz_app::feed_junit(softcut::fuzz::as_text(data, size));
  return 0;
}
