#include <doctest/doctest.h>

#include "io_round_trip.hpp"

TEST_SUITE("mesh/io/gmsh_writer") {
  TEST_CASE("read -> write .msh -> read is exact (sample files, boxes, awkward doubles and labels)") {
    softcut::test::check_round_trips(".msh");
  }

  TEST_CASE("the file is Gmsh 2.2 ASCII with labels as physical tags") {
    const auto dir = softcut::test::scratch_dir("gmsh_writer_content");
    softcut::mesh::BoxOptions o;
    o.nx = o.ny = o.nz = 1;
    o.label = 3;
    softcut::mesh::write_mesh(dir / "box.msh", softcut::mesh::generate_box(o));
    const std::string s = softcut::test::slurp(dir / "box.msh");
    CHECK(s.rfind("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n8\n1 0 0 0\n2 1 0 0\n", 0) == 0);
    CHECK(s.find("$Elements\n6\n1 4 2 3 3 ") != std::string::npos);
    CHECK(s.find("$EndElements\n") == s.size() - 13);
  }
}
