// libFuzzer target: the vtu reader (.vtu) on arbitrary bytes.
#include "mesh_fuzz.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return softcut::fuzz::fuzz_mesh_reader(softcut::mesh::io::read_vtu, "fuzz.vtu", data, size);
}
