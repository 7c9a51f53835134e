#include <doctest/doctest.h>

#include "io_round_trip.hpp"

TEST_SUITE("mesh/io/vtu_writer") {
  TEST_CASE("read -> write .vtu -> read is exact (sample files, boxes, awkward doubles and labels)") {
    softcut::test::check_round_trips(".vtu");
  }

  TEST_CASE("the file declares what ParaView needs") {
    const auto dir = softcut::test::scratch_dir("vtu_writer_content");
    softcut::mesh::write_mesh(dir / "box.vtu", softcut::mesh::generate_box({}));
    const std::string s = softcut::test::slurp(dir / "box.vtu");
    CHECK(s.find("type=\"UnstructuredGrid\"") != std::string::npos);
    CHECK(s.find("header_type=\"UInt64\"") != std::string::npos);
    CHECK(s.find("NumberOfPoints=\"125\" NumberOfCells=\"384\"") != std::string::npos);
    CHECK(s.find("<CellData Scalars=\"label\">") != std::string::npos);
    CHECK(s.find("Name=\"label\" format=\"binary\"") != std::string::npos);
  }
}
