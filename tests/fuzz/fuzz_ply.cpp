// libFuzzer target: the .ply surface reader (CGAL's, after softcut's scan) and the surface checks.
#include "surface_fuzz.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return softcut::fuzz::fuzz_surface_reader(".ply", data, size);
}
