#include <doctest/doctest.h>

#include "io_sample.hpp"

using softcut::test::check_sample;
using softcut::test::expect_error;
using softcut::test::mesh_data;
using softcut::test::replaced;
using softcut::test::slurp;

TEST_SUITE("mesh/io/vtk_reader") {
  TEST_CASE("ASCII, BINARY and the version 5 cell layout read to the sample mesh") {
    check_sample(mesh_data("sample_ascii.vtk"), 2);
    check_sample(mesh_data("sample_binary.vtk"), 2);
    check_sample(mesh_data("sample_v51.vtk"), 2);
  }

  TEST_CASE("without a label array every tet gets label 0") {
    const std::string a = slurp(mesh_data("sample_ascii.vtk"));
    const auto dir = softcut::test::scratch_dir("vtk_nolabel");
    softcut::test::spit(dir / "a.vtk", replaced(a, "gmsh:physical", "something_else"));
    softcut::Diagnostics diag;
    const auto m = softcut::mesh::read_mesh(dir / "a.vtk", diag);
    CHECK(m.labels(0) == 0);
    CHECK(m.labels(1) == 0);
  }

  TEST_CASE("malformed ASCII files name the line and the problem") {
    const std::string a = slurp(mesh_data("sample_ascii.vtk"));
    expect_error("short_tet.vtk", replaced(replaced(a, "CELLS 4 17", "CELLS 4 16"), "4 1 4 3 5", "3 1 4 3"),
                 {"short_tet.vtk:8:", "cell 3: a tetrahedron (type 10) needs 4 points, found 3"});
    expect_error("range.vtk", replaced(a, "4 1 4 3 5", "4 1 4 3 6"), {"range.vtk:8:", "cell 3: refers to point 6, but the file has points 0..5"});
    expect_error("badnum.vtk", replaced(a, "5 5 5", "5 x 5"), {"badnum.vtk:6:", "expected a number for point 2 y, found 'x'"});
    expect_error("nan.vtk", replaced(a, "5 5 5", "5 5 nan"), {"nan.vtk:6:", "point 2 z is not finite"});
    expect_error("size.vtk", replaced(a, "CELLS 4 17", "CELLS 4 18"), {"size.vtk:13:", "expected a number for CELLS, found 'CELL_TYPES'"});
    expect_error("types.vtk", replaced(a, "CELL_TYPES 4\n3 5 10 10", "CELL_TYPES 3\n3 5 10"), {"types.vtk", "CELL_TYPES lists 3 cells but CELLS has 4"});
    // A non-integral cell type is malformed, not a tetrahedron (10.5 once truncated to 10).
    expect_error("celltype.vtk", replaced(a, "3 5 10 10", "3 5 10 10.5"), {"celltype.vtk:13:", "cell 3: type 10.5 is not an integer"});
    expect_error("celltype_big.vtk", replaced(a, "3 5 10 10", "3 5 10 1e300"), {"celltype_big.vtk:13:", "cell 3: type 1e+300 is not an integer"});
    expect_error("dataset.vtk", replaced(a, "UNSTRUCTURED_GRID", "POLYDATA"), {"dataset.vtk:4:", "dataset POLYDATA is not supported"});
    expect_error("header.vtk", replaced(a, "# vtk DataFile", "# vtx DataFile"), {"header.vtk:1:", "not a legacy VTK file"});
    expect_error("version.vtk", replaced(a, "Version 4.2", "Version 9.0"), {"version.vtk:1:", "unsupported legacy VTK version 9.0"});
    expect_error("mode.vtk", replaced(a, "ASCII", "TEXT"), {"mode.vtk:3:", "expected ASCII or BINARY"});
    expect_error("label.vtk", replaced(a, "1 2 7 9", "1 2 7.5 9"), {"label.vtk:19:", "label 7.5 of cell 2 in array gmsh:physical is not an integer"});
    expect_error("huge.vtk", replaced(a, "POINTS 6 double", "POINTS 600000000 double"), {"huge.vtk:8:", "found 'CELLS'"});
    expect_error("type.vtk", replaced(a, "POINTS 6 double", "POINTS 6 quad"), {"type.vtk:5:", "unsupported data type 'quad' for POINTS"});
  }

  TEST_CASE("malformed BINARY files: sizes beyond the file are refused before allocating") {
    const std::string b = slurp(mesh_data("sample_binary.vtk"));
    expect_error("huge_cells.vtk", replaced(b, "CELLS 4 17", "CELLS 4 1700000000"),
                 {"huge_cells.vtk:", "file ends inside CELLS (1700000000 values of 4 bytes announced"});
    expect_error("huge_points.vtk", replaced(b, "POINTS 6 double", "POINTS 2000000000 double"),
                 {"huge_points.vtk:5:", "file ends inside POINTS"});
    expect_error("trunc.vtk", b.substr(0, b.find("CELLS") + 30), {"trunc.vtk:", "file ends inside CELLS"});
    expect_error("nolut.vtk", replaced(b, "LOOKUP_TABLE default\n\x3f", "LOOKUPTABLE default\n\x3f"),
                 {"nolut.vtk:", "expected LOOKUP_TABLE after SCALARS quality"});
  }
}
