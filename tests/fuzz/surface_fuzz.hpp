#pragma once
// One libFuzzer input through a surface reader (CGAL's, behind softcut's
// structure scan: mesh/io/surface_io.hpp) and then the checks a surface gets
// before meshing (mesh/mesher/surface_domain.hpp: closed, oriented, not
// self-intersecting, nesting), as `softcut mesh generate surface` runs them.
#include "fuzz_support.hpp"
#include "mesh/io/surface_io.hpp"
#include "mesh/mesher/surface_domain.hpp"

namespace softcut::fuzz {

inline int fuzz_surface_reader(const char* ext, const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes = as_text(data, size);
  expect_clean([&] {
    Diagnostics diag;
    const mesh::SurfaceSoup s = mesh::read_surface_bytes(std::string("fuzz") + ext, ext, bytes, diag);
    if (s.triangles.rows() <= 4000) mesh::surface_domain({s}, 1.0, diag);
  });
  return 0;
}

}  // namespace softcut::fuzz
