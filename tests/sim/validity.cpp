// sim/validity: what the linear law and the condensed region carried, read
// against a rigid rotation (whose infinitesimal rotation is sin(theta) and
// whose linear strain is 1 - cos(theta), exactly), and the warnings a run
// past the bounds gives.
#include "sim/validity.hpp"

#include <doctest/doctest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/warning.hpp"
#include "sim/step.hpp"
#include "test_support.hpp"
#include "fixtures.hpp"

using namespace softcut;

namespace {

// u = (R - I) x for a rotation by `theta` about (1, 2, 3) through the origin.
void rotate_rigidly(const sim::Model& m, sim::State& s, double theta) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(theta, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  for (int n = 0; n < m.mesh.num_nodes(); ++n)
    s.displacement.row(n) = ((R - Eigen::Matrix3d::Identity()) * m.mesh.node(n)).transpose();
}

bool has_code(const std::vector<std::string>& warnings, std::string_view code) {
  for (const auto& w : warnings)
    if (warning_code(w) == code) return true;
  return false;
}

}  // namespace

TEST_SUITE("sim/validity") {
  TEST_CASE("a rigid rotation reads its angle and 1 - cos in every linear tet, operational and condensed") {
    for (const auto backend : {backend::Backend::monolithic, backend::Backend::automatic}) {
      sim::ScenarioSpec spec = test::cantilever_spec(test::scratch_dir("validity_rigid"));
      spec.solver.backend = backend;
      const sim::Model m = sim::compile(spec);
      sim::State s = sim::make_state(m);
      for (const double theta : {0.02, 0.3, 1.0}) {
        CAPTURE(theta);
        rotate_rigidly(m, s, theta);
        const sim::Validity v = sim::measure_validity(m, s);
        CHECK(v.linear_rotation == doctest::Approx(theta).epsilon(1e-10));
        CHECK(v.linear_strain == doctest::Approx(1 - std::cos(theta)).epsilon(1e-9));
        CHECK(v.linear_tet >= 0);
        // The nonoperational region is the mixed model's linear part on every
        // backend: condensed by the hybrid, solved whole by the monolithic one.
        CHECK(v.condensed_rotation == doctest::Approx(theta).epsilon(1e-10));
        if (backend != backend::Backend::monolithic) {
          // Interior nodes the frame left unsolved (zero, or anything) are not read.
          REQUIRE_FALSE(m.solver->interior_valid());
          int interior = 0;
          for (int n = 0; n < m.mesh.num_nodes(); ++n)
            if (m.partition.node_set[size_t(n)] == hybrid::NodeSet::interior) s.displacement.row(n).setConstant(1.0), ++interior;
          REQUIRE(interior > 0);
          CHECK(sim::measure_validity(m, s).condensed_rotation == doctest::Approx(theta).epsilon(1e-10));
        }
      }
    }
  }

  TEST_CASE("tets with a nonlinear law are not the linear law's: a corotational body reads nothing") {
    sim::ScenarioSpec spec = test::cantilever_spec(test::scratch_dir("validity_corot"));
    spec.solver.backend = backend::Backend::monolithic;
    spec.solver.whole_body = true;  // else the nonoperational tets stay linear
    spec.materials[0].model = fem::MaterialModel::corotational;
    const sim::Model m = sim::compile(spec);
    sim::State s = sim::make_state(m);
    rotate_rigidly(m, s, 0.5);
    const sim::Validity v = sim::measure_validity(m, s);
    CHECK(v.linear_rotation == 0);
    CHECK(v.linear_strain == 0);
    CHECK(v.linear_tet == -1);
  }

  TEST_CASE("a bent cantilever past the bounds warns with codes and frames, the same bar bent gently does not") {
    // Tip force 0.006 N at t = 0.2 s on the 5 kPa bar: P L^2 / (2 E I) = 0.45 rad at the
    // tip by beam theory; the coarse bar (120 linear tets, stiff in bending) turns 0.11 rad
    // (6.4 deg) where most, and 0.0019 rad at a sixtieth of the load.
    for (const double tip : {0.03, 0.0005}) {
      CAPTURE(tip);
      sim::ScenarioSpec spec = test::cantilever_spec(test::scratch_dir("validity_bent"), 0.2, tip);
      spec.solver.backend = backend::Backend::monolithic;
      spec.solver.whole_body = true;  // every tet carries its own (linear) law
      const sim::Model m = sim::compile(spec);
      sim::State s = sim::make_state(m);
      for (int f = 0; f < m.num_frames; ++f) sim::step(m, s);
      const std::vector<std::string> w = sim::validity_warnings(m, s);
      const bool past = s.stats.linear_rotation_max > 5.0 * M_PI / 180;
      CHECK(past == (tip > 0.001));
      CHECK(has_code(w, "linear_large_rotation") == past);
      if (past) {
        CHECK(s.stats.linear_rotation_frame == m.num_frames - 1);  // the load grows to the last frame
        CHECK(w.front().find("at t = 0.200 s (the most") != std::string::npos);
        CHECK(w.front().find("model = \"corotational\"") != std::string::npos);
      }
      CHECK(!has_code(w, "condensed_rotation"));  // whole body: nothing condensed
    }
  }

  TEST_CASE("the condensed region's rotation warns, naming the remedies, on the 99th percentile") {
    sim::ScenarioSpec spec = test::cantilever_spec(test::scratch_dir("validity_condensed"));
    const sim::Model m = sim::compile(spec);
    sim::State s = sim::make_state(m);
    s.stats.condensed_rotation_max = 40.0 * M_PI / 180, s.stats.condensed_rotation_frame = 2;
    s.stats.condensed_rotation_p99_max = 12.0 * M_PI / 180, s.stats.condensed_rotation_p99_frame = 1;
    s.stats.linear_strain_max = 0.3, s.stats.linear_strain_frame = 2;
    s.stats.linear_strain_p99_max = 0.07, s.stats.linear_strain_p99_frame = 2;
    s.stats.linear_rotation_max = 1.0;  // one sliver: no warning
    const std::vector<std::string> w = sim::validity_warnings(m, s);
    REQUIRE(w.size() == 2);
    CHECK(has_code(w, "condensed_rotation"));
    CHECK(has_code(w, "linear_large_strain"));
    CAPTURE(w[0]);
    CAPTURE(w[1]);
    CHECK(w[0].find("more than 7.0 % at t = 0.200 s (the most 30.0 %)") != std::string::npos);
    CHECK(w[1].find("more than 12.0 deg at t = 0.100 s (the most 40.0 deg)") != std::string::npos);
    CHECK(w[1].find("whole_body") != std::string::npos);
    s.stats.condensed_rotation_p99_max = 9.9 * M_PI / 180, s.stats.linear_strain_p99_max = 0.049;
    CHECK(sim::validity_warnings(m, s).empty());
  }

  TEST_CASE("the 99th percentile: one sliver moves the largest, not it") {
    sim::ScenarioSpec spec = test::cantilever_spec(test::scratch_dir("validity_sliver"));
    spec.solver.backend = backend::Backend::monolithic;
    spec.solver.whole_body = true;  // every tet carries its own (linear) law
    const sim::Model m = sim::compile(spec);  // 120 tets
    sim::State s = sim::make_state(m);
    rotate_rigidly(m, s, 0.01);
    s.displacement.row(m.mesh.tets(7, 0)) += Eigen::RowVector3d(0, 0, 0.02);  // one node: its tets turn
    const sim::Validity v = sim::measure_validity(m, s);
    CHECK(v.linear_rotation > 0.1);
    CHECK(v.linear_rotation_p99 < v.linear_rotation);
    CHECK(v.linear_rotation_p99 >= 0.01 - 1e-12);
  }

  TEST_CASE("validity.csv: one row per frame with the solve's iterations") {
    sim::ScenarioSpec spec = test::cantilever_spec(test::scratch_dir("validity_log"));
    const sim::Model m = sim::compile(spec);
    sim::State s = sim::make_state(m);
    sim::step(m, s);
    sim::step(m, s);
    const std::string row = sim::validity_log_row(s);
    CHECK(row.rfind("1,1.000000000e-01,", 0) == 0);
    CHECK(std::count(row.begin(), row.end(), ',') ==
          std::count(sim::kValidityLogHeader, sim::kValidityLogHeader + std::strlen(sim::kValidityLogHeader), ','));
    CHECK(row.back() == '\n');
  }
}
