#include "sim/vtu_export.hpp"

#include <doctest/doctest.h>

#include <cstring>

#include "fixtures.hpp"
#include "sim/cutting.hpp"
#include "sim/step.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
namespace sim = softcut::sim;

namespace {

// Bit-for-bit equality of doubles (NaN-free data: == on the bits).
bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace

TEST_SUITE("sim/vtu_export") {
  TEST_CASE("an independent reader (meshio) gets every array back exactly") {
    const fs::path dir = softcut::test::scratch_dir("sim_vtu_export");
    const sim::Model m = sim::compile(softcut::test::cantilever_spec(dir, 0.3, 0.02));
    sim::State s = sim::make_state(m);
    for (int f = 0; f < 3; ++f) sim::step(m, s);
    const fs::path vtu = dir / "frame.vtu";
    const std::uintmax_t bytes = sim::write_vtu(vtu, m, s);
    CHECK(bytes == fs::file_size(vtu));
    const std::string text = softcut::test::slurp(vtu);
    CHECK(text.find("<AppendedData encoding=\"raw\">") != std::string::npos);
    CHECK(text.find("format=\"ascii\"") == std::string::npos);

    const softcut::test::ForeignArrays r = softcut::test::read_vtu_with_meshio(vtu);
    const int nn = m.mesh.num_nodes(), nt = m.mesh.num_tets();
    CHECK(r.cell_blocks == 1);
    CHECK(r.tetra_blocks == 1);
    const auto& points = r.arrays.at("points");
    const auto& u = r.arrays.at("point.displacement");
    const auto& sets = r.arrays.at("point.node_set");
    REQUIRE(points.size() == std::size_t(3 * nn));
    REQUIRE(u.size() == std::size_t(3 * nn));
    REQUIRE(sets.size() == std::size_t(nn));
    int bad = 0;
    for (int n = 0; n < nn; ++n) {
      for (int c = 0; c < 3; ++c) {
        bad += !same_bits(points[std::size_t(3 * n + c)], m.mesh.nodes(n, c));
        bad += !same_bits(u[std::size_t(3 * n + c)], s.displacement(n, c));
      }
      bad += sets[std::size_t(n)] != double(int(sim::node_set(m, s, n)));
    }
    CHECK(bad == 0);
    REQUIRE(s.displacement.cwiseAbs().maxCoeff() > 0);  // the numbers compared are not all zero
    const auto& tets = r.arrays.at("tetra");
    const auto& labels = r.arrays.at("cell.label");
    const auto& op = r.arrays.at("cell.operational");
    REQUIRE(tets.size() == std::size_t(4 * nt));
    REQUIRE(labels.size() == std::size_t(nt));
    REQUIRE(op.size() == std::size_t(nt));
    int ops = 0;
    for (int t = 0; t < nt; ++t) {
      for (int k = 0; k < 4; ++k) bad += tets[std::size_t(4 * t + k)] != double(m.mesh.tets(t, k));
      bad += labels[std::size_t(t)] != double(m.mesh.labels(t));
      bad += op[std::size_t(t)] != double(m.partition.operational_tet[std::size_t(t)]);
      ops += m.partition.operational_tet[std::size_t(t)] != 0;
    }
    CHECK(bad == 0);
    CHECK(ops > 0);
    CHECK(ops < nt);
  }
}
