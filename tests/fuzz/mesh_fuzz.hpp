#pragma once
// One libFuzzer input through a text/binary mesh reader and then the same
// checks read_mesh applies (non-empty, validate), from the in-memory entry
// points of mesh/io/formats.hpp (no file per exec).
#include "fuzz_support.hpp"
#include "mesh/io/formats.hpp"
#include "mesh/tet_mesh.hpp"

namespace softcut::fuzz {

template <class Reader>
int fuzz_mesh_reader(Reader reader, const char* source, const std::uint8_t* data, std::size_t size) {
  const std::string_view text = as_text(data, size);
  expect_clean([&] {
    Diagnostics diag;
    mesh::TetMesh m = reader(source, text, diag);
    if (m.num_tets() == 0) return;
    mesh::validate(m, source, diag);
  });
  return 0;
}

}  // namespace softcut::fuzz
