#include "mesh/generate/presets.hpp"

#include <doctest/doctest.h>

#include "generate_checks.hpp"

using namespace softcut;
using namespace softcut::mesh;

namespace {
double miss(int got, int want) { return std::abs(double(got) / want - 1); }
}  // namespace

TEST_SUITE("mesh/generate/presets") {
  TEST_CASE("ligament: the paper's 615 nodes and 1900 tets within 10 %") {
    const TetMesh m = generate_band(ligament_preset());
    CHECK(miss(m.num_nodes(), kLigamentNodes) <= 0.1);
    CHECK(miss(m.num_tets(), kLigamentTets) <= 0.1);
    test::check_solid(m, 2);
  }

  TEST_CASE("upper leg: the paper's 785 nodes and 2550 tets within 10 %, with a fixed hole") {
    const TubeOptions o = upper_leg_preset();
    const TetMesh m = generate_tube(o);
    CHECK(miss(m.num_nodes(), kUpperLegNodes) <= 0.1);
    CHECK(miss(m.num_tets(), kUpperLegTets) <= 0.1);
    test::check_solid(m, 0);
    const auto r = resolve_tube(o);
    CHECK(tube_hole_nodes(m, o).size() == size_t(r.around * (r.layers + 1)));
  }

  TEST_CASE("presets are deterministic") {
    CHECK(generate_band(ligament_preset()).nodes == generate_band(ligament_preset()).nodes);
    CHECK(generate_tube(upper_leg_preset()).tets == generate_tube(upper_leg_preset()).tets);
  }
}
