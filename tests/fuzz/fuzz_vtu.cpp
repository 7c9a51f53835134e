// libFuzzer target: the vtu reader (.vtu) on arbitrary bytes.
#include "mesh_fuzz.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // Decoded arrays within 64 MiB, as the sandbox bounds them by its memory budget.
  const auto read = [](const std::string& source, std::string_view text, softcut::Diagnostics& diag) {
    return softcut::mesh::io::read_vtu(source, text, diag, 64u << 20);
  };
  return softcut::fuzz::fuzz_mesh_reader(read, "fuzz.vtu", data, size);
}
