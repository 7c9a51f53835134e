// libFuzzer target: a run's render_record.bin, as `softcut render` reads it
// (every chunk, every frame's scene extracted; no GL).
#include "fuzz_support.hpp"
#include "render_record_fuzz.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  softcut::fuzz::expect_clean([&] { softcut::fuzz::read_render_record(softcut::fuzz::as_text(data, size)); });
  return 0;
}
