#pragma once
// The one VTU writer (VTK XML UnstructuredGrid, .vtu): mesh files
// (write_mesh) and the per-frame exports of a run (sim/vtu_export) both go
// through it. Binary, appended raw (what ParaView reads fastest: no base64,
// no XML parsing of numbers), header_type UInt64, little-endian, so doubles
// round-trip bit for bit. The XML part is written by pugixml.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "mesh/tet_mesh.hpp"

namespace softcut::mesh::io {

// One point or cell data array: (items x components) values, row-major.
struct VtuArray {
  enum class Type { float64, int32 };
  std::string name;
  Type type = Type::float64;
  int components = 1;
  std::vector<double> f64;        // type float64
  std::vector<std::int32_t> i32;  // type int32
};

struct VtuFields {
  std::vector<VtuArray> point_data;  // nnode rows each
  std::vector<VtuArray> cell_data;   // ntet rows each, after "label" (the mesh's labels, always written)
  std::string point_vectors;         // PointData Vectors= (the array ParaView warps by); may be empty
};

// Writes `m` (rest points, tets, CellData "label") and `fields` to `path`
// atomically; returns the bytes written. Throws softcut::Error naming the
// array when its size does not match the mesh.
std::uintmax_t write_vtu(const std::filesystem::path& path, const TetMesh& m, const VtuFields& fields = {});

}  // namespace softcut::mesh::io
