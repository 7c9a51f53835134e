#include <doctest/doctest.h>

#include "io_sample.hpp"

using softcut::test::check_sample;
using softcut::test::expect_error;
using softcut::test::mesh_data;
using softcut::test::replaced;
using softcut::test::slurp;

TEST_SUITE("mesh/io/medit_reader") {
  TEST_CASE("the sample .mesh reads to the sample mesh, edges and triangles skipped") {
    check_sample(mesh_data("sample.mesh"), 2);
  }

  TEST_CASE("malformed files name the line and the problem") {
    const std::string m = slurp(mesh_data("sample.mesh"));
    expect_error("out_of_range.mesh", replaced(m, "2 5 4 6 9", "2 5 4 16 9"),
                 {"out_of_range.mesh:21:", "tetrahedron 2 refers to vertex 16, but the file has vertices 1..6"});
    expect_error("short.mesh", replaced(m, "2 5 4 6 9", "2 5 4 6"),
                 {"short.mesh:22:", "expected an integer for the reference of tetrahedron 2, found 'Corners'"});
    expect_error("nan.mesh", replaced(m, "1 1 1 0", "1 nan 1 0"), {"nan.mesh:11:", "vertex 6 y is not finite"});
    expect_error("dim.mesh", replaced(m, "Dimension 3", "Dimension 2"), {"dim.mesh:2:", "dimension 2 is not supported"});
    expect_error("tri_count.mesh", replaced(m, "Triangles\n1\n", "Triangles\n2\n"),
                 {"tri_count.mesh:15:", "section Triangles announces 2 items (8 values) but 4 values follow"});
    expect_error("junk.mesh", replaced(m, "Corners", "12 Corners"), {"junk.mesh:22:", "expected a section keyword", "'12'"});
    expect_error("count.mesh", replaced(m, "Tetrahedra\n2\n", "Tetrahedra\n3000000000\n"),
                 {"count.mesh:22:", "expected an integer for vertex 1 of tetrahedron 3, found 'Corners'"});
    expect_error("trunc.mesh", m.substr(0, m.find("2 5 4 6 9") + 8), {"trunc.mesh:21:", "unexpected end of file, expected the reference of tetrahedron 2"});
    expect_error("novert.mesh", "MeshVersionFormatted 2\nDimension 3\nEnd\n", {"novert.mesh", "no Vertices section"});
  }
}
