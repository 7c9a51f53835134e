// Legacy VTK reader (.vtk): DATASET UNSTRUCTURED_GRID, ASCII or BINARY
// (big-endian), cell layout of file versions < 5 (CELLS n size) and 5.x
// (OFFSETS / CONNECTIVITY). Cells of type 10 (VTK_TETRA) are kept; an integer
// CELL_DATA array named like a label (label, region, gmsh:physical,
// CellEntityIds, ...) gives the labels.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "mesh/io/formats.hpp"
#include "mesh/io/text_reader.hpp"

namespace softcut::mesh::io {

namespace {

std::string vtk_cell_name(int type) {
  switch (type) {
    case 1: return "vertex";
    case 3: return "line";
    case 5: return "triangle";
    case 7: return "polygon";
    case 9: return "quad";
    case 12: return "hexahedron";
    case 13: return "wedge";
    case 14: return "pyramid";
    case 24: return "quadratic tetrahedron";
    default: return cat("cell type ", type);
  }
}

// Bytes per value of a legacy VTK data type name; 0 if not supported.
int vtk_type_size(const std::string& t) {
  if (t == "float" || t == "int" || t == "unsigned_int" || t == "vtktypeint32" || t == "vtktypeuint32") return 4;
  if (t == "double" || t == "long" || t == "unsigned_long" || t == "vtktypeint64" || t == "vtktypeuint64") return 8;
  if (t == "short" || t == "unsigned_short") return 2;
  if (t == "char" || t == "unsigned_char") return 1;
  return 0;
}

double decode_be(const char* p, const std::string& t, int size) {
  unsigned char b[8];
  for (int i = 0; i < size; ++i) b[i] = static_cast<unsigned char>(p[size - 1 - i]);  // to little-endian
  if (t == "float") { float f; std::memcpy(&f, b, 4); return f; }
  if (t == "double") { double d; std::memcpy(&d, b, 8); return d; }
  const bool is_unsigned = t.rfind("unsigned", 0) == 0 || t == "vtktypeuint32" || t == "vtktypeuint64";
  std::uint64_t u = 0;
  std::memcpy(&u, b, size);
  if (is_unsigned) return double(u);
  const int shift = 64 - 8 * size;
  return double(std::int64_t(u << shift) >> shift);  // sign-extend
}

struct VtkFile {
  TextReader r;
  bool binary = false;
  int major = 0;
  std::vector<double> points, cells, offsets, types, labels;  // raw arrays as read
  int cells_line = 0, types_line = 0, labels_rank = 1 << 30;
  std::int64_t npoints = -1, ncells_header = -1;

  VtkFile(const std::string& source, std::string_view text) : r(source, text) {}

  // A count from the file; `limit` keeps products of counts far from overflow.
  std::int64_t count_token(std::string_view what, std::int64_t limit = std::int64_t(1) << 40) {
    const std::int64_t n = r.int_token(what);
    if (n < 0) r.fail_here("negative ", what, ": ", n);
    if (n > limit) r.fail_here(what, " ", n, " is implausibly large (limit ", limit, ")");
    return n;
  }
  static constexpr std::int64_t kMaxComponents = 1 << 20;

  // `count` values of `type` (ASCII tokens or big-endian binary right after this line).
  std::vector<double> values(std::int64_t count, const std::string& type, std::string_view what, bool finite = false) {
    const int size = vtk_type_size(type);
    if (size == 0) r.fail_here("unsupported data type '", type, "' for ", what);
    std::vector<double> out;
    if (binary) {
      if (std::uint64_t(count) > r.bytes_left() / std::uint64_t(size))
        r.fail_here("file ends inside ", what, " (", count, " values of ", size, " bytes announced, ", r.bytes_left(),
                    " bytes left)");
      const std::string_view bytes = r.take_bytes(std::size_t(count) * std::size_t(size), what);
      out.resize(std::size_t(count));
      for (std::size_t i = 0; i < out.size(); ++i) out[i] = decode_be(bytes.data() + i * std::size_t(size), type, size);
    } else {
      out.reserve(reserve_cap(count, r.bytes_left(), 2));
      for (std::int64_t i = 0; i < count; ++i) {
        const std::string_view tok = r.token(what);
        out.push_back(finite ? r.to_coord_lazy(tok, [&] { return cat("point ", i / 3, " ", "xyz"[i % 3]); })
                             : r.to_double(tok, what));
      }
    }
    return out;
  }

  void skip_values(std::int64_t count, const std::string& type, std::string_view what) { values(count, type, what); }

  void header() {
    if (!r.next_raw_line() || lower(r.line_text()).find("# vtk datafile version") != 0)
      r.fail_here("not a legacy VTK file: the first line must be '# vtk DataFile Version x.y'");
    const auto& t = r.tokens();
    if (t.size() < 5) r.fail_here("missing version number after '# vtk DataFile Version'");
    const std::string_view v = t[4];
    const double version = r.to_double(v, "the file version");
    if (!(version >= 1 && version < 6)) r.fail_here("unsupported legacy VTK version ", v, " (1.0 to 5.x are read)");
    major = int(version);  // in range: no overflow
    if (!r.next_raw_line()) r.fail_here("file ends before the title line");
    if (!r.next_line()) r.fail_here("file ends before the ASCII/BINARY line");
    const std::string mode = lower(r.tokens()[0]);
    if (mode == "binary") binary = true;
    else if (mode != "ascii") r.fail_here("expected ASCII or BINARY, found '", r.tokens()[0], "'");
    if (lower(r.token("DATASET")) != "dataset") r.fail_here("expected DATASET UNSTRUCTURED_GRID");
    const std::string_view ds = r.token("the dataset type");
    if (lower(ds) != "unstructured_grid")
      r.fail_here("dataset ", ds, " is not supported; softcut reads UNSTRUCTURED_GRID (tetrahedral meshes)");
  }

  // SCALARS / VECTORS / FIELD ... under CELL_DATA or POINT_DATA with `n` tuples.
  void attribute(const std::string& kw, std::int64_t n, bool cell_data) {
    const int line = r.line();
    if (kw == "scalars") {
      const std::string name(r.token("the SCALARS name"));
      const std::string type = lower(r.token("the SCALARS data type"));
      std::string_view tok;
      std::int64_t ncomp = 1;
      if (r.next_token(tok)) {
        std::int64_t c;
        if (parse_int(tok, c)) ncomp = c;
        else r.unget_token();
      }
      if (ncomp < 1 || ncomp > 4) r.fail_here("SCALARS ", name, " has ", ncomp, " components; expected 1..4");
      if (binary || (r.next_token(tok) && (r.unget_token(), lower(tok) == "lookup_table"))) {
        if (lower(r.token("LOOKUP_TABLE")) != "lookup_table") r.fail_here("expected LOOKUP_TABLE after SCALARS ", name);
        r.token("the lookup table name");
      }
      array(name, n, ncomp, type, cell_data, line);
    } else if (kw == "vectors" || kw == "normals" || kw == "tensors" || kw == "tensors6") {
      const std::string name(r.token("the array name"));
      const std::string type = lower(r.token("the data type"));
      const int width = kw == "tensors" ? 9 : kw == "tensors6" ? 6 : 3;
      skip_values(n * width, type, cat(kw, " ", name));
    } else if (kw == "field") {
      r.token("the FIELD name");
      const std::int64_t k = count_token("the number of FIELD arrays", kMaxComponents);
      for (std::int64_t i = 0; i < k; ++i) {
        const std::string name(r.token("a FIELD array name"));
        const std::int64_t ncomp = count_token(cat("the component count of FIELD array ", name), kMaxComponents);
        const std::int64_t ntup = count_token(cat("the tuple count of FIELD array ", name));
        const std::string type = lower(r.token("the data type"));
        array(name, ntup, ncomp, type, cell_data && ntup == n, r.line());
      }
    } else if (kw == "lookup_table") {
      r.token("the lookup table name");
      const std::int64_t size = count_token("the lookup table size");
      skip_values(4 * size, binary ? "unsigned_char" : "float", "LOOKUP_TABLE");
    } else if (kw == "color_scalars") {
      r.token("the COLOR_SCALARS name");
      const std::int64_t nv = count_token("the COLOR_SCALARS component count", kMaxComponents);
      skip_values(n * nv, binary ? "unsigned_char" : "float", "COLOR_SCALARS");
    } else if (kw == "texture_coordinates") {
      r.token("the TEXTURE_COORDINATES name");
      const std::int64_t dim = count_token("the TEXTURE_COORDINATES dimension", kMaxComponents);
      skip_values(n * dim, lower(r.token("the data type")), "TEXTURE_COORDINATES");
    }
  }

  // `line`: where the array is declared, for messages about its values.
  void array(const std::string& name, std::int64_t n, std::int64_t ncomp, const std::string& type, bool cell_data,
             int line) {
    std::vector<double> v = values(n * ncomp, type, cat("array ", name));
    const int rank = label_name_rank(name);
    if (!cell_data || rank < 0 || ncomp != 1 || rank >= labels_rank) return;
    for (std::size_t i = 0; i < v.size(); ++i)
      if (!label_value_ok(v[i])) fail(r.source(), ":", line, ": label ", v[i], " of cell ", i, " in array ", name, " is not an integer");
    labels = std::move(v);
    labels_rank = rank;
  }

  void skip_metadata() {
    while (r.next_raw_line())
      if (r.tokens().empty()) return;
  }

  void parse(Diagnostics& diag) {
    header();
    std::string_view tok;
    std::int64_t attr_n = -1;  // tuples of the current CELL_DATA / POINT_DATA block
    bool cell_data = false;
    while (r.next_token(tok)) {
      const std::string kw = lower(tok);
      if (kw == "points") {
        if (npoints >= 0) r.fail_here("second POINTS section");
        npoints = count_token("the number of points", INT32_MAX);
        points = values(3 * npoints, lower(r.token("the POINTS data type")), "POINTS", true);
      } else if (kw == "cells") {
        cells_line = r.line();
        const std::int64_t a = count_token("the number of cells"), b = count_token("the CELLS list size");
        if (major >= 5) {
          if (lower(r.token("OFFSETS")) != "offsets") r.fail_here("expected OFFSETS (VTK 5 cell layout)");
          offsets = values(a, lower(r.token("the OFFSETS data type")), "OFFSETS");
          if (lower(r.token("CONNECTIVITY")) != "connectivity") r.fail_here("expected CONNECTIVITY after OFFSETS");
          cells = values(b, lower(r.token("the CONNECTIVITY data type")), "CONNECTIVITY");
          ncells_header = a > 0 ? a - 1 : 0;
        } else {
          cells = values(b, "int", "CELLS");
          ncells_header = a;
        }
      } else if (kw == "cell_types") {
        types_line = r.line();
        const std::int64_t n = count_token("the number of cell types");
        types = values(n, "int", "CELL_TYPES");
      } else if (kw == "cell_data" || kw == "point_data") {
        attr_n = count_token(cat("the number of ", kw, " tuples"), INT32_MAX);
        cell_data = kw == "cell_data";
      } else if (kw == "metadata") {
        skip_metadata();
      } else if (attr_n >= 0 && (kw == "scalars" || kw == "vectors" || kw == "normals" || kw == "tensors" ||
                                  kw == "tensors6" || kw == "field" || kw == "lookup_table" ||
                                  kw == "color_scalars" || kw == "texture_coordinates")) {
        attribute(kw, attr_n, cell_data);
      } else if (npoints >= 0 && !types.empty()) {
        diag.warn(r.source(), ":", r.line(), ": stopped reading at unsupported keyword '", tok,
                  "'; any cell labels after it were not read");
        return;
      } else {
        r.fail_here("unexpected '", tok, "'; expected POINTS, CELLS, CELL_TYPES or CELL_DATA");
      }
    }
  }

  TetMesh finish(Diagnostics& diag) {
    if (npoints < 0) fail(r.source(), ": no POINTS section");
    if (ncells_header < 0) fail(r.source(), ": no CELLS section");
    if (std::int64_t(types.size()) != ncells_header)
      fail(r.source(), ": CELL_TYPES lists ", types.size(), " cells but CELLS has ", ncells_header);
    const bool use_labels = !labels.empty();
    if (use_labels && std::int64_t(labels.size()) != ncells_header)
      fail(r.source(), ": the label array has ", labels.size(), " values for ", ncells_header, " cells");
    MeshBuffers buf;
    buf.xyz = std::move(points);
    SkippedElements skipped;
    std::size_t pos = 0;
    auto where = [&](std::int64_t c) { return cat(r.source(), ":", cells_line, ": cell ", c); };
    for (std::int64_t c = 0; c < ncells_header; ++c) {
      std::size_t begin, end;
      if (major >= 5) {
        const double b = offsets[std::size_t(c)], e = offsets[std::size_t(c) + 1];
        if (!(b >= 0 && e >= b && e <= double(cells.size())))
          fail(where(c), ": offsets ", b, "..", e, " do not fit the connectivity of ", cells.size(), " entries");
        begin = std::size_t(b), end = std::size_t(e);
      } else {
        if (pos >= cells.size()) fail(where(c), ": the CELLS list ends early (is its size right?)");
        const double np = cells[pos];
        if (!(np >= 0 && np <= double(cells.size() - pos - 1)))
          fail(where(c), ": announces ", np, " points but the CELLS list has ", cells.size() - pos - 1, " entries left");
        begin = pos + 1, end = pos + 1 + std::size_t(np);
        pos = end;
      }
      if (!label_value_ok(types[std::size_t(c)]))
        fail(r.source(), ":", types_line, ": cell ", c, ": type ", types[std::size_t(c)], " is not an integer");
      const int type = int(types[std::size_t(c)]);
      if (type != 10) {
        skipped.add(vtk_cell_name(type));
        continue;
      }
      if (end - begin != 4) fail(where(c), ": a tetrahedron (type 10) needs 4 points, found ", end - begin);
      for (std::size_t k = begin; k < end; ++k) {
        const double v = cells[k];
        if (!(v >= 0 && v < double(npoints) && v == std::floor(v)))
          fail(where(c), ": refers to point ", v, ", but the file has points 0..", npoints - 1);
        buf.tet.push_back(int(v));
      }
      buf.label.push_back(use_labels ? int(labels[std::size_t(c)]) : 0);
    }
    if (major < 5 && pos != cells.size())
      fail(r.source(), ":", cells_line, ": the CELLS list has ", cells.size() - pos, " entries beyond its ",
           ncells_header, " cells (is its size right?)");
    skipped.report(r.source(), diag);
    return buf.finish();
  }
};

}  // namespace

TetMesh read_vtk(const std::string& source, std::string_view text, Diagnostics& diag) {
  VtkFile f(source, text);
  f.parse(diag);
  return f.finish(diag);
}

}  // namespace softcut::mesh::io
