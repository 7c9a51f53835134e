#include "mesh/units.hpp"

#include <doctest/doctest.h>

#include "core/warning.hpp"
#include "mesh/generate/box.hpp"
#include "test_support.hpp"

using namespace softcut;
using namespace softcut::mesh;
using test::contains;
using test::error_of;

TEST_SUITE("mesh/units") {
  TEST_CASE("units in metres, and an unknown one named") {
    CHECK(unit_metres("m", "x") == 1);
    CHECK(unit_metres("cm", "x") == doctest::Approx(0.01));
    CHECK(unit_metres("mm", "x") == doctest::Approx(0.001));
    CHECK(unit_metres("um", "x") == doctest::Approx(1e-6));
    CHECK(contains(error_of([] { unit_metres("inch", "option --unit"); }), "option --unit: unknown unit 'inch' (use m, cm, mm or um)"));
  }

  TEST_CASE("the unit guessed from a size: m up to 1, mm up to 1000, um up to 1e6") {
    CHECK(guess_unit(0.19, "s") == "m");
    CHECK(guess_unit(1.0, "s") == "m");
    CHECK(guess_unit(190, "s") == "mm");
    CHECK(guess_unit(1000, "s") == "mm");
    CHECK(guess_unit(5e4, "s") == "um");
    CHECK(contains(error_of([] { guess_unit(1e7, "surface a.stl"); }), "surface a.stl: the body is 10000000 units across"));
    CHECK(contains(error_of([] { guess_unit(1e-4, "s"); }), "too small"));
    CHECK(contains(error_of([] { guess_unit(0, "s"); }), "cannot guess"));
  }

  TEST_CASE("an organ larger than 1 m or smaller than 1 mm is a coded warning suggesting the unit") {
    Diagnostics d;
    // A liver written in millimetres and read as metres: 190 x 130 x 80 m.
    CHECK(check_plausible_size(Eigen::AlignedBox3d(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(190, 130, 80)), "liver.msh", d));
    REQUIRE(d.warnings.size() == 1);
    CHECK(warning_code(d.warnings[0]) == "implausible_size");
    CHECK(contains(d.warnings[0], "liver.msh: the body is 190 m across"));
    CHECK(contains(d.warnings[0], "unit = \"mm\""));
    CHECK(contains(d.warnings[0], "0.19 m across then"));
    // A metre file read as millimetres: 0.19 mm.
    d.warnings.clear();
    CHECK(check_plausible_size(Eigen::AlignedBox3d(Eigen::Vector3d::Zero(), Eigen::Vector3d(1.9e-4, 1e-4, 1e-4)), "m", d));
    CHECK(contains(d.warnings.at(0), "0.19 mm across"));
    CHECK(contains(d.warnings.at(0), "0.19 m across then"));
    // Organs, a 1 mm vessel, a 1 m body: no warning.
    d.warnings.clear();
    for (const double side : {0.19, 1e-3, 1.0, 0.035})
      CHECK_FALSE(check_plausible_size(Eigen::AlignedBox3d(Eigen::Vector3d::Zero(), Eigen::Vector3d(side, side / 2, side / 3)), "m", d));
    CHECK(d.warnings.empty());
  }

  TEST_CASE("scale_nodes scales, and refuses a factor that is not a positive number") {
    BoxOptions b;
    TetMesh m = generate_box(b);
    const Eigen::MatrixX3d before = m.nodes;
    scale_nodes(m, 1e-3, "s");
    CHECK((m.nodes - 1e-3 * before).cwiseAbs().maxCoeff() == 0);
    CHECK(bounding_box(m).sizes().maxCoeff() == doctest::Approx(1e-3));
    CHECK(contains(error_of([&] { scale_nodes(m, 0, "option --scale"); }), "option --scale: the scale must be a positive number"));
    CHECK(contains(error_of([&] { scale_nodes(m, -2, "s"); }), "positive"));
    b.max_corner = Eigen::Vector3d(10, 1, 1);
    TetMesh big = generate_box(b);
    CHECK(contains(error_of([&] { scale_nodes(big, 1e308, "s"); }), "not finite"));
  }
}
