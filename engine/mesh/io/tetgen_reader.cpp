// TetGen .node/.ele reader. Either file may be named; the other is found
// beside it. Numbering is 0- or 1-based as the first point of the .node file
// says; the first .ele attribute (the region attribute) becomes the label.
// 10-node tetrahedra keep their 4 corner nodes (TetGen lists them first).
#include <cstdint>

#include "mesh/io/formats.hpp"
#include "mesh/io/text_reader.hpp"

namespace softcut::mesh::io {

namespace {

// Reads up to `n` header values with defaults for the missing ones.
void read_header(TextReader& r, std::string_view what, std::int64_t* v, std::size_t n) {
  if (!r.next_line()) fail(r.source(), ": the file is empty; a TetGen ", what, " file starts with a header line");
  const auto& t = r.tokens();
  if (t.size() > n) r.fail_here("expected at most ", n, " values on the ", what, " header line, found ", t.size());
  for (std::size_t i = 0; i < t.size(); ++i) v[i] = r.to_int(t[i], cat(what, " header value ", i + 1));
}

}  // namespace

TetMesh read_tetgen(const std::filesystem::path& node_file, const std::filesystem::path& ele_file, Diagnostics& diag,
                    const ReadOptions& opt) {
  MeshBuffers buf;
  int base = 0;
  std::int64_t npoint = 0;
  {
    const std::string text = read_file(node_file, opt);
    TextReader r(node_file.string(), text);
    r.set_comment('#');
    std::int64_t h[4] = {0, 3, 0, 0};  // points, dimension, attributes, boundary markers
    read_header(r, ".node", h, 4);
    npoint = h[0];
    if (h[0] <= 0) r.fail_here("the .node file announces ", h[0], " points; expected at least 4");
    if (h[1] != 3) r.fail_here("dimension ", h[1], " is not supported; expected 3");
    if (h[2] < 0 || h[2] > 1000) r.fail_here("bad number of point attributes: ", h[2]);
    if (h[3] != 0 && h[3] != 1) r.fail_here("the boundary marker flag must be 0 or 1, found ", h[3]);
    const std::size_t width = 4 + std::size_t(h[2]) + std::size_t(h[3]);
    buf.xyz.reserve(3 * reserve_cap(npoint, r.bytes_left(), 8));
    for (std::int64_t i = 0; i < npoint; ++i) {
      if (!r.next_line()) r.fail_here("file ends after ", i, " of ", npoint, " points");
      const auto& t = r.tokens();
      if (t.size() != width)
        r.fail_here("expected ", width, " values for a point (index x y z", h[2] ? " attributes" : "",
                    h[3] ? " marker" : "", "), found ", t.size());
      const std::int64_t index = r.to_int(t[0], "point index");
      if (i == 0) {
        if (index != 0 && index != 1) r.fail_here("the first point must be numbered 0 or 1, found ", index);
        base = int(index);
      } else if (index != base + i) {
        r.fail_here("expected point ", base + i, ", found ", index, " (points must be numbered consecutively)");
      }
      static const char* axis[] = {"x", "y", "z"};
      for (int c = 0; c < 3; ++c)
        buf.xyz.push_back(r.to_coord_lazy(t[1 + c], [&] { return cat("point ", index, " ", axis[c]); }));
      for (std::size_t k = 4; k < width; ++k)
        r.to_double_lazy(t[k], [&] { return cat("attribute or marker of point ", index); });
    }
    if (r.next_line()) r.fail_here("unexpected data after the ", npoint, " announced points");
  }
  {
    const std::string text = read_file(ele_file, opt);
    TextReader r(ele_file.string(), text);
    r.set_comment('#');
    std::int64_t h[3] = {0, 4, 0};  // tetrahedra, nodes per tetrahedron, attributes
    read_header(r, ".ele", h, 3);
    if (h[0] < 0) r.fail_here("negative number of tetrahedra: ", h[0]);
    if (h[1] != 4 && h[1] != 10) r.fail_here("nodes per tetrahedron must be 4 or 10, found ", h[1]);
    if (h[2] < 0 || h[2] > 1000) r.fail_here("bad number of tetrahedron attributes: ", h[2]);
    const std::size_t width = 1 + std::size_t(h[1]) + std::size_t(h[2]);
    buf.tet.reserve(4 * reserve_cap(h[0], r.bytes_left(), 10));
    for (std::int64_t i = 0; i < h[0]; ++i) {
      if (!r.next_line()) r.fail_here("file ends after ", i, " of ", h[0], " tetrahedra");
      const auto& t = r.tokens();
      const std::int64_t index = r.to_int(t[0], "tetrahedron index");
      if (t.size() != width)
        r.fail_here("expected ", h[1], " node indices", h[2] ? cat(" and ", h[2], " attribute(s)") : std::string(),
                    " for tetrahedron ", index, ", found ", t.size() - 1, " values");
      for (int k = 0; k < 4; ++k) {
        const std::int64_t v = r.to_int_lazy(t[1 + k], [&] { return cat("node of tetrahedron ", index); });
        if (v < base || v >= base + npoint)
          r.fail_here("tetrahedron ", index, " refers to point ", v, ", but the .node file has points ", base, "..",
                      base + npoint - 1);
        buf.tet.push_back(int(v - base));
      }
      for (std::size_t k = 5; k < 1 + std::size_t(h[1]); ++k)
        r.to_int_lazy(t[k], [&] { return cat("node of tetrahedron ", index); });
      int label = 0;
      if (h[2] > 0) {
        const std::size_t at = 1 + std::size_t(h[1]);
        const double a = r.to_double_lazy(t[at], [&] { return cat("region attribute of tetrahedron ", index); });
        if (!label_value_ok(a)) r.fail_here("region attribute ", t[at], " of tetrahedron ", index, " is not an integer");
        label = int(a);
        for (std::size_t k = at + 1; k < width; ++k)
          r.to_double_lazy(t[k], [&] { return cat("attribute of tetrahedron ", index); });
      }
      buf.label.push_back(label);
    }
    if (r.next_line()) r.fail_here("unexpected data after the ", h[0], " announced tetrahedra");
    if (h[1] == 10 && h[0] > 0)
      diag.warn(ele_file.string(), ": read ", h[0], " 10-node tetrahedra as linear 4-node tetrahedra",
                " (their mid-edge nodes stay unreferenced)");
  }
  return buf.finish();
}

}  // namespace softcut::mesh::io
