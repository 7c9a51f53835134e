#include "mesh/io/mesh_io.hpp"

#include <doctest/doctest.h>

#include <random>

#include "io_sample.hpp"
#include "mesh/generate/box.hpp"
#include "mesh/io/formats.hpp"

using softcut::test::expect_error;
using softcut::test::mesh_data;
using softcut::test::slurp;
using softcut::test::spit;

TEST_SUITE("mesh/io/mesh_io") {
  TEST_CASE("unknown extensions are refused with the list of supported ones") {
    expect_error("liver.stl", "solid x\n", {"liver.stl: unknown mesh file extension '.stl'", ".msh", ".node/.ele", ".mesh", ".vtk", ".vtu"});
    softcut::mesh::TetMesh m = softcut::mesh::generate_box({});
    const auto dir = softcut::test::scratch_dir("io_write_ext");
    CHECK_THROWS_WITH_AS(softcut::mesh::write_mesh(dir / "out.obj", m), doctest::Contains("supported: .vtu (VTK XML), .msh"),
                         softcut::Error);
    CHECK_THROWS_WITH_AS(softcut::mesh::write_mesh(dir / "missing" / "out.vtu", m), doctest::Contains("cannot create"),
                         softcut::Error);
  }

  TEST_CASE("extensions are matched case-insensitively, a missing file is named") {
    const auto dir = softcut::test::scratch_dir("io_case");
    spit(dir / "UPPER.MSH", slurp(mesh_data("sample_v22.msh")));
    softcut::Diagnostics diag;
    CHECK(softcut::mesh::read_mesh(dir / "UPPER.MSH", diag).num_tets() == 2);
    CHECK_THROWS_WITH_AS(softcut::mesh::read_mesh(dir / "nope.vtu", diag), doctest::Contains("nope.vtu: no such file"),
                         softcut::Error);
  }

  TEST_CASE("a file without tetrahedra and one with a degenerate tet are refused") {
    expect_error("surface.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$EndNodes\n"
                                "$Elements\n1\n1 2 0 1 2 3\n$EndElements\n",
                 {"surface.msh: the file holds no tetrahedra (3 nodes)"});
    expect_error("flat.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 1 1 0\n"
                             "$EndNodes\n$Elements\n1\n1 4 0 1 2 3 4\n$EndElements\n",
                 {"flat.msh: tetrahedron 0", "is degenerate"});
  }

  TEST_CASE("truncating any sample at any offset gives a clean mesh or a softcut::Error, never a crash") {
    // In memory through the per-format readers plus validate (what read_mesh
    // does after loading the file), so hundreds of variants stay fast.
    namespace io = softcut::mesh::io;
    std::mt19937 rng(2026);
    int meshes = 0, errors = 0;
    for (const char* name : {"sample_v1.msh", "sample_v22.msh", "sample_v41.msh", "sample.mesh", "sample_ascii.vtk",
                             "sample_binary.vtk", "sample_v51.vtk", "sample_ascii.vtu", "sample_base64_uint64.vtu",
                             "sample_zlib_uint32.vtu", "sample_appended_raw.vtu", "sample_appended_base64_zlib.vtu"}) {
      const std::string full = slurp(mesh_data(name));
      const std::string ext = std::filesystem::path(name).extension().string();
      for (int trial = 0; trial < 150; ++trial) {
        // Cut at a random offset, and every third time also change one byte before it.
        std::string s = full.substr(0, rng() % (full.size() + 1));
        if (trial % 3 == 0 && !s.empty()) s[rng() % s.size()] = char(rng() & 255);
        softcut::Diagnostics diag;
        try {
          softcut::mesh::TetMesh m = ext == ".msh"    ? io::read_gmsh("fuzzed", s, diag)
                                     : ext == ".mesh" ? io::read_medit("fuzzed", s, diag)
                                     : ext == ".vtk"  ? io::read_vtk("fuzzed", s, diag)
                                                      : io::read_vtu("fuzzed", s, diag);
          softcut::mesh::validate(m, "fuzzed", diag);
          // Whatever was read is clean: every tet positive, one label each.
          for (int t = 0; t < m.num_tets(); ++t) CHECK(softcut::mesh::signed_volume(m, t) > 0);
          CHECK(m.labels.size() == m.num_tets());
          ++meshes;
        } catch (const softcut::Error& e) {
          CAPTURE(e.what());
          CHECK(std::string(e.what()).rfind("fuzzed", 0) == 0);  // names the source
          ++errors;
        }
      }
    }
    CHECK(errors > 1000);
    CHECK(meshes > 0);
  }

  TEST_CASE("truncated TetGen pairs give a clean mesh or a softcut::Error") {
    const auto dir = softcut::test::scratch_dir("io_truncate_tetgen");
    const std::string node = slurp(mesh_data("sample.node")), ele = slurp(mesh_data("sample.ele"));
    for (std::size_t cut = 0; cut <= node.size() + ele.size(); cut += 7) {
      spit(dir / "t.node", node.substr(0, std::min(cut, node.size())));
      spit(dir / "t.ele", cut > node.size() ? ele.substr(0, cut - node.size()) : ele);
      softcut::Diagnostics diag;
      try {
        const int ntet = softcut::mesh::read_mesh(dir / "t.node", diag).num_tets();
        CHECK(ntet > 0);
      } catch (const softcut::Error& e) {
        CAPTURE(e.what());
        CHECK(std::string(e.what()).find((dir / "t.").string()) != std::string::npos);
      }
    }
  }

  TEST_CASE("a huge count on the last line (no newline after it) is an Error, not an allocation") {
    // Each reader reserves an announced count only up to what the bytes left
    // can hold; at the end of a file without a final newline nothing is left.
    expect_error("huge.mesh", "MeshVersionFormatted 1\nDimension 3\nVertices 1000000000000",
                 {"huge.mesh:3:", "unexpected end of file", "vertex 1 x"});
    expect_error("huge.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n1000000000000000000",
                 {"huge.msh:5:", "file ends after 0 of 1000000000000000000 nodes"});
    expect_error("huge.vtk", "# vtk DataFile Version 4.2\nx\nASCII\nDATASET UNSTRUCTURED_GRID\nCELLS 1 1000000000000",
                 {"huge.vtk:5:", "unexpected end of file", "CELLS"});
  }
}
