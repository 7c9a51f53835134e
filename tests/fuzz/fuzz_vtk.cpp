// libFuzzer target: the legacy VTK reader (.vtk) on arbitrary bytes.
#include "mesh_fuzz.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return softcut::fuzz::fuzz_mesh_reader(softcut::mesh::io::read_vtk, "fuzz.vtk", data, size);
}
