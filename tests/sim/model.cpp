#include "sim/model.hpp"

#include <doctest/doctest.h>

#include <thread>

#include "core/error.hpp"
#include "fem/assembly.hpp"
#include "fem/dof_map.hpp"
#include "fixtures.hpp"
#include "sim/step.hpp"
#include "solve/cholesky.hpp"
#include "test_support.hpp"

using V = Eigen::Vector3d;
namespace sim = softcut::sim;
namespace fem = softcut::fem;

TEST_SUITE("sim/model") {
  TEST_CASE("compile + step of a cantilever equals an independent whole-mesh solve, every backend") {
    auto spec = softcut::test::cantilever_spec(softcut::test::scratch_dir("sim_model_cantilever"));
    for (const char* backend : {"cpu", "direct", "monolithic"}) {
    CAPTURE(backend);
    spec.solver.backend = softcut::backend::parse_backend(backend);
    const sim::Model m = sim::compile(spec);
    CHECK(m.mesh.num_nodes() == 6 * 3 * 3);
    CHECK(m.partition.fixed.size() == 9);
    CHECK(m.partition.counts.operational_tets == 2 * 2 * 6);
    const auto& c = m.partition.counts;
    CHECK(c.fixed + c.operational + c.interface + c.surface + c.interior + c.unused == m.mesh.num_nodes());
    CHECK(m.num_frames == 3);
    CHECK(m.log_nodes == m.surface.nodes);

    // Reference: K from all tets, x = 0 nodes eliminated, tip nodes loaded.
    std::vector<fem::Material> mats(m.mesh.num_tets(), fem::Material{5e3, 0.45});
    const fem::SparseMatrix K = fem::assemble_stiffness(m.mesh, mats);
    std::vector<char> free(m.mesh.num_nodes());
    std::vector<int> tip;
    for (int n = 0; n < m.mesh.num_nodes(); ++n) {
      free[n] = m.mesh.nodes(n, 0) > 1e-12;
      if (m.mesh.nodes(n, 0) > 0.1 - 1e-12) tip.push_back(n);
    }
    REQUIRE(tip.size() == 9);
    const fem::DofMap map = fem::make_dof_map(free);
    softcut::solve::Cholesky chol(fem::restrict_matrix(K, map));

    sim::State s = sim::make_state(m);
    for (int frame = 0; frame < m.num_frames; ++frame) {
      sim::step(m, s);
      CHECK(s.frame == frame);
      const double t = 0.1 * frame;
      CHECK(s.time == doctest::Approx(t));
      Eigen::MatrixX3d f = Eigen::MatrixX3d::Zero(m.mesh.num_nodes(), 3);
      for (int n : tip) f(n, 2) = -0.01 * t / 9.0;
      CHECK((s.forces - f).norm() <= 1e-15);
      softcut::solve::SolveWorkspace ws;
      const Eigen::VectorXd x = chol.solve(fem::restrict_vector(fem::flatten(f), map), ws);
      const Eigen::MatrixX3d u = fem::unflatten(fem::expand_vector(x, map, m.mesh.num_nodes()));
      // Interior nonoperational nodes are condensed away (not computed per frame).
      Eigen::MatrixX3d diff = s.displacement - u;
      for (int n : m.partition.interior) diff.row(n).setZero();
      CHECK(diff.norm() <= 1e-8 * std::max(u.norm(), 1e-30));
      for (int n : m.partition.fixed) CHECK(s.displacement.row(n).norm() == 0);
    }
    CHECK(s.displacement.col(2).minCoeff() < 0);  // bends down
    CHECK(s.stats.frames == 3);
    if (std::string(backend) == "cpu") CHECK(s.stats.cg_iterations_max > 0);
    }
  }

  TEST_CASE("hybrid equals monolithic on every node when interior nodes are logged, also without operational tets") {
    for (bool operational : {true, false}) {
      CAPTURE(operational);
      auto spec = softcut::test::cantilever_spec(softcut::test::scratch_dir("sim_model_interior"), 0.3);
      if (!operational) spec.operational = sim::TetSelector::of(sim::TetSelector::Kind::none);
      spec.outputs.log_all_surface = false;  // log_nodes kind all: every node, interior included
      spec.loads[0].magnitude = softcut::tools::Ramp::sine_wave(0.0, 0.02, 2.0);
      const sim::Model hyb = sim::compile(spec);
      spec.solver.backend = softcut::backend::Backend::monolithic;
      const sim::Model mono = sim::compile(spec);
      CHECK(hyb.solver->interior_valid());
      CHECK(!hyb.partition.interior.empty());
      sim::State a = sim::make_state(hyb), b = sim::make_state(mono);
      for (int i = 0; i < hyb.num_frames; ++i) {
        sim::step(hyb, a);
        sim::step(mono, b);
        CHECK((a.displacement - b.displacement).norm() <= 1e-8 * b.displacement.norm());
      }
    }
  }

  TEST_CASE("reading an interior node the hybrid model does not solve is an error, not a stale zero") {
    auto spec = softcut::test::cantilever_spec(softcut::test::scratch_dir("sim_model_unsolved"), 0.1);
    const sim::Model m = sim::compile(spec);  // logs the surface only
    REQUIRE(!m.solver->interior_valid());
    REQUIRE(!m.partition.interior.empty());
    sim::State s = sim::make_state(m);
    sim::step(m, s);
    const int inner = m.partition.interior[0], surface = m.partition.surface[0];
    CHECK_NOTHROW(sim::check_solved(m, s, surface, "probe"));
    const std::string expected = "probe: node " + std::to_string(inner) + " lies inside the nonoperational region";
    CHECK_THROWS_WITH_AS(sim::check_solved(m, s, inner, "probe"), doctest::Contains(expected.c_str()), softcut::Error);
    // An expectation's bounds on it make the model solve it every frame.
    sim::ExpectationSpec e;
    e.name = "inner";
    e.bounds = true;
    e.nodes = sim::NodeSelector::list({inner});
    e.max = 1.0;
    spec.expectations.push_back(e);
    const sim::Model solved = sim::compile(spec);
    CHECK(solved.solver->interior_valid());
    sim::State t = sim::make_state(solved);
    sim::step(solved, t);
    CHECK_NOTHROW(sim::check_solved(solved, t, inner, "probe"));
  }

  TEST_CASE("materials: presets, overrides, later entries win") {
    auto spec = softcut::test::cantilever_spec(softcut::test::scratch_dir("sim_model_materials"));
    sim::MaterialAssignment liver;
    liver.name = "right";
    liver.preset = "liver";
    liver.tets = sim::TetSelector::of(sim::TetSelector::Kind::halfspace);
    liver.tets.point = V(0.06, 0, 0);  // the last two of five cells
    liver.tets.normal = V(1, 0, 0);
    spec.materials.push_back(liver);
    const sim::Model m = sim::compile(spec);
    int n_liver = 0;
    for (const auto& mat : m.tet_material) n_liver += mat.young == 5.4e3;
    CHECK(n_liver == 2 * 2 * 2 * 6);
    CHECK(m.tet_material[0].young == 5e3);
  }

  TEST_CASE("bad scenarios fail naming the item") {
    using softcut::Error;
    const auto dir = softcut::test::scratch_dir("sim_model_errors");
    {
      auto spec = softcut::test::cantilever_spec(dir);
      spec.fixed = sim::NodeSelector::box(V(5, 5, 5), V(6, 6, 6));
      spec.fixed.where = "bar.lua:3";
      CHECK_THROWS_WITH_AS(sim::compile(spec), doctest::Contains("bar.lua:3: fixed: selects no node"), Error);
    }
    {
      auto spec = softcut::test::cantilever_spec(dir);
      spec.loads[0].nodes = sim::NodeSelector::box(V(-1, -1, -1), V(0, 1, 1));
      spec.loads[0].where = "bar.lua:9";
      CHECK_THROWS_WITH_AS(sim::compile(spec), doctest::Contains("bar.lua:9: load 'tip': node 0 is fixed"), Error);
    }
    {
      auto spec = softcut::test::cantilever_spec(dir);
      spec.loads[0].magnitude = softcut::tools::Ramp::linear_ramp(0, 1, 1, 0);
      CHECK_THROWS_WITH_AS(sim::compile(spec), doctest::Contains("load 'tip' magnitude"), Error);
    }
    {
      auto spec = softcut::test::cantilever_spec(dir);
      spec.materials[0].poisson = 0.5;
      CHECK_THROWS_WITH_AS(sim::compile(spec), doctest::Contains("material 'tissue'"), Error);
    }
    {
      auto spec = softcut::test::cantilever_spec(dir);
      spec.materials[0].preset = "spleen";
      CHECK_THROWS_WITH_AS(sim::compile(spec), doctest::Contains("liver"), Error);
    }
    {
      auto spec = softcut::test::cantilever_spec(dir);
      spec.loads[0].nodes = sim::NodeSelector::list({25});  // (0.02, 0.01, 0.01): interior, nonoperational
      CHECK_THROWS_WITH_AS(sim::compile(spec), doctest::Contains("node 25 is an interior nonoperational node"), Error);
      spec.loads[0].nodes = sim::NodeSelector::list({27});  // (0.06, 0.01, 0.01): interface, inside the body
      spec.loads[0].direction_kind = sim::LoadSpec::Direction::normal;
      CHECK_THROWS_WITH_AS(sim::compile(spec), doctest::Contains("node 27 is not on the surface"), Error);
    }
  }

  // The Model is fixed data: two runs may step it at once on two threads
  // (its K22 factor, its operational system, its whole-mesh factor shared;
  // every workspace, factor of a cut system and cache in each run's State)
  // and each gets exactly the frames it gets alone.
  TEST_CASE("one Model, two runs stepping it at once on two threads: each equals the run made alone") {
    auto spec = softcut::test::cantilever_spec(softcut::test::scratch_dir("sim_model_two_runs"), 1.0);
    spec.tools.push_back(softcut::test::spring_grasper(
        50.0, 0.006, softcut::tools::Path::polyline({0.0, 1.0}, {V(0.05, 0.01, 0.02), V(0.05, 0.01, 0.03)})));
    for (const char* backend : {"direct", "cpu", "monolithic"}) {
      CAPTURE(backend);
      spec.solver.backend = softcut::backend::parse_backend(backend);
      spec.solver.mode = softcut::hybrid::Storage::factor;  // stage 5 through the shared K22 factor
      const sim::Model m = sim::compile(spec);
      auto run = [&m](std::vector<Eigen::MatrixX3d>& frames) {
        sim::State s = sim::make_state(m);
        for (int f = 0; f < m.num_frames; ++f) {
          sim::step(m, s);
          frames.push_back(s.displacement);
        }
      };
      std::vector<Eigen::MatrixX3d> alone, a, b;
      run(alone);
      std::thread ta([&] { run(a); }), tb([&] { run(b); });
      ta.join();
      tb.join();
      REQUIRE(alone.size() == size_t(m.num_frames));
      CHECK(alone.back().col(2).maxCoeff() > 0);  // the grasper lifted the bar
      CHECK(a == alone);
      CHECK(b == alone);
    }
  }
}
