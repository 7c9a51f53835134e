#include "sim/mesh_source.hpp"

#include <doctest/doctest.h>

#include "core/error.hpp"

namespace sim = softcut::sim;

TEST_SUITE("sim/mesh_source") {
  TEST_CASE("box generator with options") {
    sim::MeshSource src;
    src.generator = "box";
    src.options = {{"nx", 3}, {"ny", 1}, {"nz", 2}, {"max.x", 0.3}};
    softcut::Diagnostics diag;
    const auto lm = sim::load_mesh_source(src, diag);
    CHECK(lm.mesh.num_nodes() == 4 * 2 * 3);
    CHECK(lm.mesh.num_tets() == 6 * 3 * 1 * 2);
    CHECK(lm.mesh.nodes.col(0).maxCoeff() == doctest::Approx(0.3));
  }

  TEST_CASE("tube provides the hole surface as a named node set") {
    sim::MeshSource src;
    src.generator = "tube";
    src.options = {{"radial", 2}, {"around", 8}, {"layers", 2}};
    softcut::Diagnostics diag;
    const auto lm = sim::load_mesh_source(src, diag);
    REQUIRE(lm.named_sets.count("hole"));
    const auto& hole = lm.named_sets.at("hole");
    CHECK(hole.size() == 8 * 3);
    for (int n : hole) CHECK(lm.mesh.nodes.row(n).head<2>().norm() == doctest::Approx(0.012));
  }

  TEST_CASE("bad sources are refused naming the option") {
    using softcut::Error;
    softcut::Diagnostics diag;
    sim::MeshSource src;
    src.generator = "box";
    src.options = {{"nw", 3}};
    CHECK_THROWS_WITH_AS(sim::load_mesh_source(src, diag), doctest::Contains("unknown option 'nw'"), Error);
    src.options = {{"nx", 2.5}};
    CHECK_THROWS_WITH_AS(sim::load_mesh_source(src, diag), doctest::Contains("'nx'"), Error);
    src.options.clear();
    src.generator = "sphere";
    CHECK_THROWS_WITH_AS(sim::load_mesh_source(src, diag), doctest::Contains("unknown generator 'sphere'"), Error);
    src.generator = "box";
    src.file = "x.msh";
    CHECK_THROWS_WITH_AS(sim::load_mesh_source(src, diag), doctest::Contains("exactly one"), Error);
    CHECK(!sim::generator_options("upper_leg").empty());
  }
}
