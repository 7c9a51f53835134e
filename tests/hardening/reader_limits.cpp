// Mesh and label-volume files whose headers announce billions of items while
// holding almost none: every reader must refuse them with a softcut::Error
// naming the file, without first reserving what the header announces (peak
// RSS of the process may grow by a few MB at most).
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "hardening_support.hpp"
#include "mesh/io/mesh_io.hpp"
#include "mesh/volume/nrrd.hpp"

namespace fs = std::filesystem;
using softcut::hardening::contains;
using softcut::hardening::error_of;
using softcut::hardening::peak_rss_bytes;
using softcut::hardening::put_file;

namespace {

struct Bomb {
  const char* name;   // file name; its extension picks the reader
  std::string text;   // the file
};

// Headers announcing ~2e9..4e9 nodes or elements (or voxels), a few items of data.
std::vector<Bomb> mesh_bombs() {
  const std::string vtk_head = "# vtk DataFile Version 3.0\nbomb\nASCII\nDATASET UNSTRUCTURED_GRID\n";
  const std::string vtkb_head = "# vtk DataFile Version 3.0\nbomb\nBINARY\nDATASET UNSTRUCTURED_GRID\n";
  const std::string vtu_head = "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\"";
  return {
      {"gmsh22_nodes.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3000000000\n1 0 0 0\n$EndNodes\n"},
      {"gmsh22_nodes_int.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n2000000000\n1 0 0 0\n$EndNodes\n"},
      {"gmsh22_elements.msh",
       "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n"
       "$Elements\n2000000000\n1 4 2 1 1 1 2 3 4\n$EndElements\n"},
      {"gmsh41_nodes.msh",
       "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 2000000000 1 2000000000\n3 1 0 2000000000\n1\n0 0 0\n$EndNodes\n"},
      {"gmsh41_maxtag.msh",
       "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 4 1 4000000000\n3 1 0 4\n1\n2\n3\n4000000000\n"
       "0 0 0\n1 0 0\n0 1 0\n0 0 1\n$EndNodes\n"},
      {"gmsh41_elements.msh",
       "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 4 1 4\n3 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n$EndNodes\n"
       "$Elements\n1 2000000000 1 2000000000\n3 1 4 2000000000\n1 1 2 3 4\n$EndElements\n"},
      {"gmsh1_nodes.msh", "$NOD\n2000000000\n1 0 0 0\n$ENDNOD\n"},
      {"medit_vertices.mesh", "MeshVersionFormatted 2\nDimension 3\nVertices\n2000000000\n0 0 0 1\nEnd\n"},
      {"medit_tets.mesh",
       "MeshVersionFormatted 2\nDimension 3\nVertices\n4\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n"
       "Tetrahedra\n2000000000\n1 2 3 4 1\nEnd\n"},
      {"points.vtk", vtk_head + "POINTS 2000000000 double\n0 0 0\n"},
      {"cells.vtk", vtk_head + "POINTS 4 double\n0 0 0 1 0 0 0 1 0 0 0 1\nCELLS 2000000000 10000000000\n4 0 1 2 3\n"},
      {"points_binary.vtk", vtkb_head + "POINTS 2000000000 float\n" + std::string(12, '\0') + "\n"},
      {"points.vtu", vtu_head + ">\n<UnstructuredGrid><Piece NumberOfPoints=\"2000000000\" NumberOfCells=\"2000000000\">\n"
                                "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">0 0 0</DataArray></Points>\n"
                                "</Piece></UnstructuredGrid></VTKFile>\n"},
      // base64 block whose UInt32 size header announces ~4 GB
      {"base64_size.vtu", vtu_head + ">\n<UnstructuredGrid><Piece NumberOfPoints=\"4\" NumberOfCells=\"1\">\n"
                                     "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"binary\">"
                                     "8P///wAAAAAAAAAAAAAAAA==</DataArray></Points>\n</Piece></UnstructuredGrid></VTKFile>\n"},
      // zlib block header announcing a ~4 GB uncompressed block
      {"zlib_size.vtu", vtu_head + " compressor=\"vtkZLibDataCompressor\">\n<UnstructuredGrid><Piece NumberOfPoints=\"4\" NumberOfCells=\"1\">\n"
                                   "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"binary\">"
                                   "AQAAAPD////w////DAAAAA==eHh4eHh4eHh4eHh4</DataArray></Points>\n</Piece></UnstructuredGrid></VTKFile>\n"},
      {"tetgen_nodes.node", "2000000000 3 0 0\n1 0 0 0\n"},
      // The announcing header is the file's last line, without '\n' (found by fuzz_tetgen).
      {"gmsh22_last_line.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n100000000000"},
      {"medit_last_line.mesh", "MeshVersionFormatted 2\nDimension 3\nVertices\n100000000000"},
      {"tetgen_last_line.node", "100000000000 3 0 0"},
  };
}

void check_refused(const fs::path& file) {
  const long long before = peak_rss_bytes();
  softcut::Diagnostics diag;
  const std::string msg = error_of([&] { softcut::mesh::read_mesh(file, diag); });
  const long long grown = peak_rss_bytes() - before;
  INFO(file.filename().string(), ": ", msg);
  CHECK(!msg.empty());
  CHECK(contains(msg, file.filename().string()));
  CHECK(grown < (64ll << 20));
}

}  // namespace

TEST_SUITE("hardening/reader_limits") {
  TEST_CASE("mesh headers announcing billions of items: clear error, bounded memory") {
    const fs::path dir = softcut::test::scratch_dir("hardening_mesh_bombs");
    for (const Bomb& b : mesh_bombs()) {
      CAPTURE(b.name);
      check_refused(put_file(dir / b.name, b.text));
    }
  }

  TEST_CASE("sparse node tags up to 2e9 read with bounded memory (tags are not indices)") {
    const fs::path dir = softcut::test::scratch_dir("hardening_sparse_tags");
    const fs::path file = put_file(dir / "bigtag.msh",
                                   "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n"
                                   "2000000000 0 0 1\n$EndNodes\n$Elements\n1\n1 4 2 1 1 1 2 3 2000000000\n$EndElements\n");
    const long long before = peak_rss_bytes();
    softcut::Diagnostics diag;
    CHECK(softcut::mesh::read_mesh(file, diag).num_tets() == 1);
    CHECK(peak_rss_bytes() - before < (64ll << 20));
  }

  TEST_CASE("TetGen .ele announcing billions of tets: clear error, bounded memory") {
    const fs::path dir = softcut::test::scratch_dir("hardening_tetgen_bomb");
    put_file(dir / "m.node", "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n");
    put_file(dir / "m.ele", "2000000000 4 0\n1 1 2 3 4\n");
    check_refused(dir / "m.ele");
  }

  TEST_CASE("NRRD sizes announcing 1e15 voxels or overflowing int: clear error, bounded memory") {
    const fs::path dir = softcut::test::scratch_dir("hardening_nrrd_bombs");
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"huge_raw.nrrd", "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 100000 100000 100000\nencoding: raw\n\n" + std::string(12, '\1')},
        {"huge_int32.nrrd", "NRRD0004\ntype: int32\ndimension: 3\nsizes: 65536 65536 65536\nencoding: raw\nendian: little\n\n" + std::string(48, '\0')},
        {"huge_ascii.nrrd", "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2000000000 2000000000 2\nencoding: ascii\n\n1 2 3\n"},
        {"huge_gzip.nrrd", "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 4000 4000 4000\nencoding: gzip\n\n" + std::string("\x1f\x8b\x08\x00\x00\x00\x00\x00", 8)},
        {"negative.nrrd", "NRRD0004\ntype: uint8\ndimension: 3\nsizes: -2 2 2\nencoding: raw\n\n" + std::string(8, '\1')},
    };
    for (const auto& name_text : cases) {
      const std::string name = name_text.first;  // not a structured binding: CAPTURE makes a lambda (clang 14)
      const std::string& text = name_text.second;
      CAPTURE(name);
      const fs::path file = put_file(dir / name, text);
      const long long before = peak_rss_bytes();
      softcut::Diagnostics diag;
      const std::string msg = error_of([&] { softcut::mesh::read_nrrd_labels(file, diag); });
      INFO(msg);
      CHECK(contains(msg, name));
      CHECK(peak_rss_bytes() - before < (64ll << 20));
    }
  }
}
