// libFuzzer target: the reference-log reader (header and rows) of softcut
// check, the input being the reference, compared with a small log.
#include "app_fuzz.hpp"
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  softcut::fuzz_app::feed_reflog(softcut::fuzz::as_text(data, size), softcut::fuzz::scratch());
  return 0;
}
