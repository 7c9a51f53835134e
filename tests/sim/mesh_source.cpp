#include "sim/mesh_source.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "core/warning.hpp"
#include "mesh/io/mesh_io.hpp"
#include "test_support.hpp"

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

  TEST_CASE("the organ generators mesh through CGAL with graded options and name what they made") {
    sim::MeshSource src;
    src.generator = "liver";
    src.options = {{"target_tets", 2500}, {"fine_center.x", 0.03}, {"fine_center.z", 0.045}, {"fine_radius", 0.02},
                   {"lesion_radius", 0.01}, {"seed", 3}};
    softcut::Diagnostics diag;
    const auto lm = sim::load_mesh_source(src, diag);
    CHECK(std::abs(lm.mesh.num_tets() - 2500) <= 500);
    CHECK(lm.mesh.labels.maxCoeff() == 2);
    CHECK(lm.description.find("generator liver (CGAL Mesh_3: " + std::to_string(lm.mesh.num_tets()) + " tets, min dihedral") == 0);
    // The lesion option is the liver's alone; option names are checked before meshing.
    src.generator = "kidney";
    CHECK_THROWS_WITH_AS(sim::load_mesh_source(src, diag), doctest::Contains("unknown option 'lesion_radius'"), softcut::Error);
    src.options = {{"target_tets", 1e6}};
    CHECK_THROWS_WITH_AS(sim::load_mesh_source(src, diag, 2e5), doctest::Contains("over this run's limit of 200000"),
                         softcut::Error);
    // A cell size alone sizes the mesh (target_tets then defaults to off); both together are refused.
    src.options = {{"cell_size", 0.012}};
    const auto sized = sim::load_mesh_source(src, diag);
    CHECK(sized.mesh.num_tets() > 100);
    src.options = {{"cell_size", 0.012}, {"target_tets", 2000}};
    CHECK_THROWS_WITH_AS(sim::load_mesh_source(src, diag), doctest::Contains("give target_tets or cell_size, not both"),
                         softcut::Error);
    CHECK(sim::generator_options("knee_ligament").size() == 10);
    CHECK(sim::generator_options("liver").size() == 14);  // and lesion_radius, lesion_center
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

  TEST_CASE("a mesh over max_tets is refused: a generator's before it allocates, a file's naming the file") {
    using softcut::Error;
    // Each generator at the limit loads (so the count the check uses is the
    // count the generator makes) and one tet below it is refused.
    const std::vector<std::pair<std::string, std::map<std::string, double>>> sources = {
        {"box", {{"nx", 3}, {"ny", 2}, {"nz", 2}}},
        {"cylinder", {{"rings", 2}, {"layers", 3}}},
        {"cylinder", {{"target_tets", 700}}},
        {"tube", {{"radial", 2}, {"around", 8}, {"layers", 2}}},
        {"band", {{"target_nodes", 300}}},
        {"ligament", {}},
        {"upper_leg", {}},
    };
    for (const auto& source : sources) {
      const std::string gen = source.first;  // a local, not a structured binding: clang 14 cannot capture those
      CAPTURE(gen);
      sim::MeshSource src;
      src.generator = gen;
      src.options = source.second;
      softcut::Diagnostics diag;
      const int n = sim::load_mesh_source(src, diag).mesh.num_tets();
      CHECK(sim::load_mesh_source(src, diag, n).mesh.num_tets() == n);
      const std::string refused = std::to_string(n) + " tetrahedra, over this run's limit of " + std::to_string(n - 1);
      CHECK_THROWS_WITH_AS(sim::load_mesh_source(src, diag, n - 1), doctest::Contains(refused.c_str()), Error);
    }
    // A billion-tet request ends at once: generating it would need ~100 GB.
    sim::MeshSource huge;
    huge.generator = "box";
    huge.options = {{"nx", 1000}, {"ny", 1000}, {"nz", 300}};
    softcut::Diagnostics diag;
    CHECK_THROWS_WITH_AS(sim::load_mesh_source(huge, diag, 2e6), doctest::Contains("1800000000 tetrahedra"), Error);

    sim::MeshSource file;
    file.file = softcut::test::scratch_dir("sim_mesh_source_limit") / "bar.msh";
    sim::MeshSource box;
    box.generator = "box";
    softcut::mesh::write_mesh(file.file, sim::load_mesh_source(box, diag).mesh);  // 4x4x4 cells: 384 tets
    CHECK(sim::load_mesh_source(file, diag, 384).mesh.num_tets() == 384);
    CHECK_THROWS_WITH_AS(sim::load_mesh_source(file, diag, 383), doctest::Contains("bar.msh has 384 tetrahedra"), Error);
  }

  TEST_CASE("the band's twist is `twist` (degrees) as on the command line, and twist_deg still reads") {
    auto band = [](std::map<std::string, double> opts) {
      sim::MeshSource src;
      src.generator = "band";
      src.options = std::move(opts);
      src.options["along"] = 6, src.options["across"] = 2, src.options["through"] = 1;
      softcut::Diagnostics diag;
      return sim::load_mesh_source(src, diag).mesh;
    };
    const auto twisted = band({{"twist", 45}}), old = band({{"twist_deg", 45}}), straight = band({{"twist", 0}});
    CHECK(twisted.nodes == old.nodes);
    CHECK(twisted.nodes != straight.nodes);
    const std::string both = softcut::test::error_of([&] { band({{"twist", 45}, {"twist_deg", 45}}); });
    CHECK(both.find("options 'twist_deg' and 'twist' are the same option; give 'twist' only") != std::string::npos);
    const auto names = sim::generator_options("band");
    CHECK(std::find(names.begin(), names.end(), "twist") != names.end());
    CHECK(std::find(names.begin(), names.end(), "twist_deg") == names.end());
  }
}

TEST_SUITE("sim/mesh_source") {
  TEST_CASE("a mesh file's unit and scale - a body of implausible size is a coded warning suggesting the unit") {
    using softcut::test::contains;
    const auto dir = softcut::test::scratch_dir("sim_mesh_source_unit");
    sim::MeshSource box;
    box.generator = "box";
    box.options = {{"max.x", 190}, {"max.y", 130}, {"max.z", 80}};  // a liver's box in mm, as metres
    softcut::Diagnostics diag;
    const auto mm = sim::load_mesh_source(box, diag).mesh;
    REQUIRE(diag.warnings.size() == 1);
    CHECK(softcut::warning_code(diag.warnings[0]) == "implausible_size");
    CHECK(contains(diag.warnings[0], "mesh (generator box (4 x 4 x 4 cells)): the body is 190 m across"));
    softcut::mesh::write_mesh(dir / "liver_mm.vtu", mm);
    sim::MeshSource file;
    file.file = dir / "liver_mm.vtu";
    diag.warnings.clear();
    sim::load_mesh_source(file, diag);
    CHECK(contains(diag.warnings.at(0), "unit = \"mm\""));
    for (const auto& [unit, scale] : std::vector<std::pair<std::string, double>>{{"mm", 1}, {"", 1e-3}, {"cm", 0.1}}) {
      file.unit = unit;
      file.scale = scale;
      diag.warnings.clear();
      const auto m = sim::load_mesh_source(file, diag).mesh;
      CHECK(m.nodes.col(0).maxCoeff() == doctest::Approx(0.19));
      CHECK(diag.warnings.empty());
    }
    file.unit = "inch";
    CHECK_THROWS_WITH_AS(sim::load_mesh_source(file, diag), doctest::Contains("unknown unit 'inch'"), softcut::Error);
    file.unit = "";
    file.scale = -1;
    CHECK_THROWS_WITH_AS(sim::load_mesh_source(file, diag), doctest::Contains("must be a positive number"), softcut::Error);
    box.unit = "mm";
    CHECK_THROWS_WITH_AS(sim::load_mesh_source(box, diag), doctest::Contains("unit and scale apply to a mesh file"),
                         softcut::Error);
  }

  TEST_CASE("the surface generator meshes closed surfaces, guessing their unit with a coded warning") {
    using softcut::test::contains;
    sim::MeshSource src;
    src.generator = "surface";
    src.surfaces = {softcut::test::data_dir() / "surface" / "outer_mm.off", softcut::test::data_dir() / "surface" / "inner_mm.obj"};
    src.options = {{"target_tets", 2000}};
    softcut::Diagnostics diag;
    const auto lm = sim::load_mesh_source(src, diag);
    CHECK(lm.mesh.labels.maxCoeff() == 2);
    CHECK(lm.mesh.nodes.col(0).maxCoeff() == doctest::Approx(0.04).epsilon(0.02));  // a 40 mm sphere, in metres
    REQUIRE(diag.warnings.size() == 1);
    CHECK(softcut::warning_code(diag.warnings[0]) == "unit_guessed");
    CHECK(contains(diag.warnings[0], "taken as mm"));
    CHECK(contains(lm.description, "generator surface (2 files, CGAL Mesh_3"));
    src.unit = "cm";  // 0.4 m across
    diag.warnings.clear();
    CHECK(sim::load_mesh_source(src, diag).mesh.nodes.col(0).maxCoeff() == doctest::Approx(0.4).epsilon(0.02));
    CHECK(diag.warnings.empty());
    src.surfaces.clear();
    CHECK_THROWS_WITH_AS(sim::load_mesh_source(src, diag), doctest::Contains("give the surface file(s)"), softcut::Error);
    src.surfaces = {softcut::test::data_dir() / "surface" / "sphere_mm.stl"};
    src.options = {{"target_tets", 1e8}};
    CHECK_THROWS_WITH_AS(sim::load_mesh_source(src, diag, 1e5), doctest::Contains("over this run's limit of 100000"),
                         softcut::Error);
    CHECK(sim::generator_options("surface").size() == 10);
  }
}
