#include <doctest/doctest.h>

#include "io_sample.hpp"

using softcut::test::check_sample;
using softcut::test::expect_error;
using softcut::test::mesh_data;
using softcut::test::replaced;
using softcut::test::slurp;

TEST_SUITE("mesh/io/gmsh_reader") {
  TEST_CASE("versions 1, 2.2 and 4.1 read to the sample mesh") {
    check_sample(mesh_data("sample_v1.msh"), 2);
    check_sample(mesh_data("sample_v22.msh"), 2);
    check_sample(mesh_data("sample_v41.msh"), 2);
  }

  TEST_CASE("4.1: a volume without physical tag is labelled by its entity tag") {
    // Volume 9 has no physical group in sample_v41.msh; give it one (5) and
    // the label follows the physical tag instead.
    const std::string text = replaced(slurp(mesh_data("sample_v41.msh")), "9 0 0 0 1 1 1 0 0", "9 0 0 0 1 1 1 1 5 0");
    const auto dir = softcut::test::scratch_dir("gmsh41_phys");
    softcut::test::spit(dir / "a.msh", text);
    softcut::Diagnostics diag;
    const auto m = softcut::mesh::read_mesh(dir / "a.msh", diag);
    CHECK(m.labels(0) == 7);
    CHECK(m.labels(1) == 5);
  }

  TEST_CASE("2.2: an element without tags gets label 0") {
    const std::string text = replaced(slurp(mesh_data("sample_v22.msh")), "3 4 2 7 1 10 20 30 3", "3 4 0 10 20 30 3");
    const auto dir = softcut::test::scratch_dir("gmsh22_notag");
    softcut::test::spit(dir / "a.msh", text);
    softcut::Diagnostics diag;
    CHECK(softcut::mesh::read_mesh(dir / "a.msh", diag).labels(0) == 0);
  }

  TEST_CASE("malformed files name the line and the problem") {
    const std::string v2 = slurp(mesh_data("sample_v22.msh"));
    const std::string v4 = slurp(mesh_data("sample_v41.msh"));
    const std::string v1 = slurp(mesh_data("sample_v1.msh"));
    // Element line 22 of sample_v22.msh is "3 4 2 7 1 10 20 30 3".
    expect_error("short_tet.msh", replaced(v2, "3 4 2 7 1 10 20 30 3", "3 4 2 7 1 10 20 30"),
                 {"short_tet.msh:22:", "expected 4 node tags for tetrahedron 3, found 3"});
    expect_error("short_tet41.msh", replaced(v4, "1 10 20 30 3", "1 10 20 30"),
                 {"short_tet41.msh:40:", "expected 4 node tags for tetrahedron 1, found 3"});
    expect_error("short_tet1.msh", replaced(v1, "3 4 7 1 4 10 20 30 3", "3 4 7 1 4 10 20 30"),
                 {"short_tet1.msh:14:", "announces 4 nodes but lists 3"});
    expect_error("short_tri.msh", replaced(v2, "2 2 2 0 1 10 20 30", "2 2 2 0 1 10 20"),
                 {"short_tri.msh:21:", "expected 3 node tags for triangle 2, found 2"});
    expect_error("version.msh", replaced(v2, "2.2 0 8", "3.0 0 8"), {"version.msh:2:", "unsupported Gmsh format version 3.0"});
    expect_error("binary.msh", replaced(v2, "2.2 0 8", "2.2 1 8"), {"binary.msh:2:", "binary Gmsh files are not supported"});
    expect_error("badnum.msh", replaced(v2, "20 1.0 0 0", "20 1.0x 0 0"), {"badnum.msh:12:", "'1.0x'", "node 20 x"});
    expect_error("nan.msh", replaced(v2, "20 1.0 0 0", "20 nan 0 0"), {"nan.msh:12:", "node 20 x is not finite"});
    expect_error("inf.msh", replaced(v4, "1 1 1\n$EndNodes", "1 -inf 1\n$EndNodes"), {"inf.msh:31:", "not finite"});
    expect_error("count_low.msh", replaced(v2, "$Nodes\n6\n", "$Nodes\n5\n"),
                 {"count_low.msh:16:", "expected $EndNodes after 5 nodes, found '100'"});
    expect_error("count_high.msh", replaced(v2, "$Elements\n4\n", "$Elements\n5\n"),
                 {"count_high.msh:24:", "expected element 5 of 5, found '$EndElements'"});
    expect_error("missing_node.msh", replaced(v2, "1 10 20 30 3", "1 10 20 30 4"),
                 {"missing_node.msh:22:", "tetrahedron 3 refers to node 4, which is not in the node section"});
    expect_error("dup_node.msh", replaced(v2, "7 5 5 5", "10 5 5 5"), {"dup_node.msh:13:", "node tag 10 appears twice"});
    expect_error("block41.msh", replaced(v4, "4 4 1 5", "5 4 1 5"), {"block41.msh:", "expected element block 5 of 5, found '$EndElements'"});
    expect_error("total41.msh", replaced(v4, "3 6 3 100", "3 7 3 100"),
                 {"total41.msh:", "announces 7 nodes but the blocks hold 6"});
    expect_error("nosection.msh", "hello\n", {"nosection.msh:1:", "expected a section"});
    expect_error("unterminated.msh", replaced(v2, "$EndPhysicalNames\n", ""),
                 {"unterminated.msh:4:", "section $PhysicalNames has no $EndPhysicalNames"});
    expect_error("noelements.msh", v2.substr(0, v2.find("$Elements")), {"noelements.msh", "no element section"});
    expect_error("label.msh", replaced(v2, "3 4 2 7 1", "3 4 2 99999999999 1"), {"label.msh:22:", "does not fit"});
  }

  TEST_CASE("a header announcing billions of nodes fails at the end of the file, without allocating them") {
    const std::string v2 = slurp(mesh_data("sample_v22.msh"));
    expect_error("huge.msh", replaced(v2, "$Nodes\n6\n", "$Nodes\n4000000000\n"),
                 {"huge.msh:17:", "expected node 7 of 4000000000, found '$EndNodes'"});
    const std::string v4 = slurp(mesh_data("sample_v41.msh"));
    expect_error("huge41.msh", replaced(v4, "3 6 3 100", "3 6000000000000 3 100"), {"huge41.msh:", "announces 6000000000000 nodes"});
  }
}
