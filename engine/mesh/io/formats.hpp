#pragma once
// Per-format readers and writers behind read_mesh / write_mesh, and what they
// share. Readers return the mesh as stored in the file (not yet validated) and
// fail with `file:line: what is wrong` on anything they cannot make sense of.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.hpp"
#include "mesh/io/mesh_io.hpp"
#include "mesh/tet_mesh.hpp"

namespace softcut::mesh::io {

TetMesh read_gmsh(const std::string& source, std::string_view text, Diagnostics& diag);
TetMesh read_tetgen(const std::filesystem::path& node_file, const std::filesystem::path& ele_file,
                    Diagnostics& diag, const ReadOptions& opt = {});
TetMesh read_medit(const std::string& source, std::string_view text, Diagnostics& diag);
TetMesh read_vtk(const std::string& source, std::string_view text, Diagnostics& diag);
// `max_bytes`: the most any one decoded (base64, zlib) array may take.
TetMesh read_vtu(const std::string& source, std::string_view text, Diagnostics& diag,
                 std::size_t max_bytes = std::numeric_limits<std::size_t>::max());

void write_gmsh(const std::filesystem::path& path, const TetMesh& m);

// Whole file as bytes, read as `opt` allows; fails naming the path when it
// cannot be read.
std::string read_file(const std::filesystem::path& path, const ReadOptions& opt = {});

// Growing storage while a file is parsed (sizes in headers are not trusted).
struct MeshBuffers {
  std::vector<double> xyz;  // (3 nnode) coordinates, m
  std::vector<int> tet;     // (4 ntet) node ids
  std::vector<int> label;   // (ntet)
  TetMesh finish() const;
};

// Elements that are not linear tets, counted by kind and reported in one warning.
struct SkippedElements {
  std::map<std::string, std::int64_t> count;
  void add(const std::string& kind, std::int64_t n = 1) { count[kind] += n; }
  void report(const std::string& source, Diagnostics& diag) const;
};

// Cell data array names taken as region labels (VTK, VTU), case-insensitive;
// lower rank is preferred when several are present, -1 for other names.
int label_name_rank(std::string_view name);

// Value check shared by readers for labels and cell types: integral and within int range.
bool label_value_ok(double v);

}  // namespace softcut::mesh::io
