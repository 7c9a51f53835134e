#include <doctest/doctest.h>

#include "io_sample.hpp"

using softcut::test::check_sample;
using softcut::test::expect_error;
using softcut::test::mesh_data;
using softcut::test::replaced;
using softcut::test::slurp;
using softcut::test::spit;

namespace {
// Writes a .node/.ele pair into a scratch folder and expects an error from
// reading it through `open` (".node" or ".ele").
void expect_pair_error(const std::string& node, const std::string& ele, std::initializer_list<std::string> parts) {
  const auto dir = softcut::test::scratch_dir("tetgen_errors");
  spit(dir / "bad.node", node);
  spit(dir / "bad.ele", ele);
  softcut::Diagnostics diag;
  std::string msg;
  try {
    softcut::mesh::read_mesh(dir / "bad.ele", diag);
  } catch (const softcut::Error& e) {
    msg = e.what();
  }
  INFO("message: ", msg);
  REQUIRE(!msg.empty());
  for (const auto& p : parts) CHECK(msg.find(p) != std::string::npos);
}
}  // namespace

TEST_SUITE("mesh/io/tetgen_reader") {
  TEST_CASE("1-based and 0-based pairs, opened by either name, read to the sample mesh") {
    check_sample(mesh_data("sample.node"), 0);
    check_sample(mesh_data("sample.ele"), 0);
    check_sample(mesh_data("sample0.node"), 0);
    check_sample(mesh_data("sample0.ele"), 0);
  }

  TEST_CASE("10-node tetrahedra keep their corners, with a warning") {
    const auto dir = softcut::test::scratch_dir("tetgen10");
    spit(dir / "q.node", slurp(mesh_data("sample0.node")));
    spit(dir / "q.ele", "2 10 1\n0 0 1 3 4 2 2 2 2 2 2 7\n1 1 4 3 5 2 2 2 2 2 2 9\n");
    softcut::Diagnostics diag;
    const auto m = softcut::mesh::read_mesh(dir / "q.ele", diag);
    CHECK(m.num_tets() == 2);
    CHECK(m.labels(1) == 9);
    CHECK(softcut::test::has_warning(diag, "10-node tetrahedra"));
  }

  TEST_CASE("malformed pairs name the file, the line and the problem") {
    const std::string node = slurp(mesh_data("sample.node")), ele = slurp(mesh_data("sample.ele"));
    expect_pair_error(node, replaced(ele, "2 2 5 4 6 9", "2 2 5 4 9"), {"bad.ele:4:", "expected 4 node indices and 1 attribute(s) for tetrahedron 2, found 4 values"});
    expect_pair_error(node, replaced(ele, "2 2 5 4 6 9", "2 2 5 4 7 9"), {"bad.ele:4:", "tetrahedron 2 refers to point 7, but the .node file has points 1..6"});
    expect_pair_error(replaced(node, "4 0 1 0 0.5 1", "5 0 1 0 0.5 1"), ele, {"bad.node:6:", "expected point 4, found 5"});
    expect_pair_error(replaced(node, "2 1 0 0 0.5 1", "2 1 0 0 1"), ele, {"bad.node:4:", "expected 6 values for a point"});
    expect_pair_error(replaced(node, "2 1 0 0 0.5 1", "2 inf 0 0 0.5 1"), ele, {"bad.node:4:", "point 2 x is not finite"});
    expect_pair_error(replaced(node, "6 3 1 1", "6 2 1 1"), ele, {"bad.node:2:", "dimension 2 is not supported"});
    expect_pair_error(replaced(node, "6 3 1 1", "7 3 1 1"), ele, {"bad.node:", "file ends after 6 of 7 points"});
    expect_pair_error(node, replaced(ele, "2 4 1", "3 4 1"), {"bad.ele:", "file ends after 2 of 3 tetrahedra"});
    expect_pair_error(node, replaced(ele, "2 4 1", "1 4 1"), {"bad.ele:4:", "unexpected data after the 1 announced tetrahedra"});
    expect_pair_error(node, replaced(ele, "1 1 2 4 5 7", "1 1 2 4 5 7.5"), {"bad.ele:3:", "region attribute 7.5 of tetrahedron 1 is not an integer"});
    expect_pair_error(node, replaced(ele, "2 4 1", "2 8 1"), {"bad.ele:2:", "nodes per tetrahedron must be 4 or 10"});
    expect_pair_error(replaced(node, "6 3 1 1", "6000000000 3 1 1"), ele, {"bad.node:", "file ends after 6 of 6000000000 points"});
  }

  TEST_CASE("a missing companion file is named") {
    const auto dir = softcut::test::scratch_dir("tetgen_alone");
    spit(dir / "alone.node", slurp(mesh_data("sample.node")));
    softcut::Diagnostics diag;
    CHECK_THROWS_WITH_AS(softcut::mesh::read_mesh(dir / "alone.node", diag),
                         doctest::Contains("alone.ele: no such file"), softcut::Error);
  }
}
