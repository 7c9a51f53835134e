// medit .mesh (ASCII) reader: Vertices and Tetrahedra with their references;
// the tetrahedron reference becomes the label. Other sections are skipped
// (element sections are counted in the warning). Indices are 1-based.
#include <algorithm>
#include <cctype>
#include <cstdint>

#include "mesh/io/formats.hpp"
#include "mesh/io/text_reader.hpp"

namespace softcut::mesh::io {

namespace {

bool is_keyword(std::string_view tok) { return !tok.empty() && std::isalpha(static_cast<unsigned char>(tok[0])); }

// Values per item of sections skipped here; 0 where not known. Element
// sections also name the kind for the "skipped" warning.
struct SectionShape {
  const char* keyword;
  int width;
  const char* element;
};
constexpr SectionShape kShapes[] = {
    {"edges", 3, "edge"},          {"triangles", 4, "triangle"}, {"quadrilaterals", 5, "quadrilateral"},
    {"hexahedra", 9, "hexahedron"}, {"prisms", 7, "prism"},       {"pyramids", 6, "pyramid"},
    {"corners", 1, nullptr},       {"ridges", 1, nullptr},       {"requiredvertices", 1, nullptr},
    {"requirededges", 1, nullptr}, {"requiredtriangles", 1, nullptr}, {"normals", 3, nullptr},
    {"tangents", 3, nullptr},      {"normalatvertices", 2, nullptr},  {"tangentatvertices", 2, nullptr},
};

}  // namespace

TetMesh read_medit(const std::string& source, std::string_view text, Diagnostics& diag) {
  TextReader r(source, text);
  r.set_comment('#');
  MeshBuffers buf;
  SkippedElements skipped;
  bool have_vertices = false, have_tets = false;
  std::string_view tok;
  while (r.next_token(tok)) {
    if (!is_keyword(tok)) r.fail_here("expected a section keyword such as Vertices or Tetrahedra, found '", tok, "'");
    const std::string kw = lower(tok);
    if (kw == "end") break;
    if (kw == "meshversionformatted") {
      const std::int64_t v = r.int_token("the MeshVersionFormatted value");
      if (v < 1 || v > 4) r.fail_here("unsupported MeshVersionFormatted ", v);
    } else if (kw == "dimension") {
      const std::int64_t d = r.int_token("the dimension");
      if (d != 3) r.fail_here("dimension ", d, " is not supported; expected 3");
    } else if (kw == "vertices") {
      if (have_vertices) r.fail_here("second Vertices section");
      have_vertices = true;
      const std::int64_t n = r.int_token("the number of vertices");
      if (n < 0) r.fail_here("negative number of vertices");
      buf.xyz.reserve(3 * reserve_cap(n, r.bytes_left(), 8));
      static const char* axis[] = {"x", "y", "z"};
      for (std::int64_t i = 1; i <= n; ++i) {
        if (std::int64_t(buf.xyz.size() / 3) >= INT32_MAX) r.fail_here("too many vertices");
        for (int c = 0; c < 3; ++c) {
          auto what = [&] { return cat("vertex ", i, " ", axis[c]); };
          buf.xyz.push_back(r.to_coord_lazy(r.token_lazy(what), what));
        }
        auto what = [&] { return cat("the reference of vertex ", i); };
        r.to_int_lazy(r.token_lazy(what), what);
      }
    } else if (kw == "tetrahedra") {
      if (!have_vertices) r.fail_here("Tetrahedra before Vertices; the vertex section must come first");
      have_tets = true;
      const std::int64_t n = r.int_token("the number of tetrahedra");
      if (n < 0) r.fail_here("negative number of tetrahedra");
      const std::int64_t nv = std::int64_t(buf.xyz.size() / 3);
      for (std::int64_t i = 1; i <= n; ++i) {
        for (int k = 0; k < 4; ++k) {
          auto what = [&] { return cat("vertex ", k + 1, " of tetrahedron ", i); };
          const std::int64_t v = r.to_int_lazy(r.token_lazy(what), what);
          if (v < 1 || v > nv) r.fail_here("tetrahedron ", i, " refers to vertex ", v, ", but the file has vertices 1..", nv);
          buf.tet.push_back(int(v - 1));
        }
        auto what = [&] { return cat("the reference of tetrahedron ", i); };
        const std::int64_t ref = r.to_int_lazy(r.token_lazy(what), what);
        if (!label_value_ok(double(ref))) r.fail_here("reference ", ref, " of tetrahedron ", i, " does not fit a 32-bit label");
        buf.label.push_back(int(ref));
      }
    } else {
      // Any other section: a count, then numbers up to the next keyword.
      const int line = r.line();
      const std::string name(tok);
      const std::int64_t n = r.int_token(cat("the item count of section ", name));
      if (n < 0 || n > (std::int64_t(1) << 40)) r.fail_here("bad item count ", n, " in section ", name);
      std::int64_t values = 0;
      while (r.next_token(tok)) {
        if (is_keyword(tok)) {
          r.unget_token();
          break;
        }
        r.to_double_lazy(tok, [&] { return cat("a value of section ", name); });
        ++values;
      }
      for (const auto& s : kShapes)
        if (kw == s.keyword) {
          if (values != n * s.width)
            fail(source, ":", line, ": section ", name, " announces ", n, " items (", n * s.width, " values) but ",
                 values, " values follow");
          if (s.element) skipped.add(s.element, n);
        }
    }
  }
  if (!have_vertices) fail(source, ": no Vertices section found");
  if (!have_tets) fail(source, ": no Tetrahedra section found");
  skipped.report(source, diag);
  return buf.finish();
}

}  // namespace softcut::mesh::io
