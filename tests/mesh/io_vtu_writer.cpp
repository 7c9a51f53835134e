#include <doctest/doctest.h>

#include "io_round_trip.hpp"
#include "mesh/generate/box.hpp"
#include "test_support.hpp"

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
    CHECK(s.find("Name=\"label\" format=\"appended\"") != std::string::npos);
    CHECK(s.find("<AppendedData encoding=\"raw\">_") != std::string::npos);
  }

  TEST_CASE("an independent reader (meshio) reads the points, tets and labels bit for bit") {
    const auto dir = softcut::test::scratch_dir("vtu_writer_meshio");
    softcut::mesh::BoxOptions o;
    o.jitter = 0.2;  // awkward doubles
    softcut::mesh::TetMesh m = softcut::mesh::generate_box(o);
    for (int t = 0; t < m.num_tets(); ++t) m.labels(t) = (t * 7) % 5 - 2;
    softcut::mesh::write_mesh(dir / "box.vtu", m);
    const softcut::test::ForeignArrays r = softcut::test::read_vtu_with_meshio(dir / "box.vtu");
    const auto& p = r.arrays.at("points");
    const auto& tets = r.arrays.at("tetra");
    const auto& labels = r.arrays.at("cell.label");
    REQUIRE(p.size() == std::size_t(3 * m.num_nodes()));
    REQUIRE(tets.size() == std::size_t(4 * m.num_tets()));
    REQUIRE(labels.size() == std::size_t(m.num_tets()));
    int bad = 0;
    for (int n = 0; n < m.num_nodes(); ++n)
      for (int c = 0; c < 3; ++c) bad += p[std::size_t(3 * n + c)] != m.nodes(n, c);
    for (int t = 0; t < m.num_tets(); ++t) {
      for (int k = 0; k < 4; ++k) bad += tets[std::size_t(4 * t + k)] != double(m.tets(t, k));
      bad += labels[std::size_t(t)] != double(m.labels(t));
    }
    CHECK(bad == 0);
  }
}
