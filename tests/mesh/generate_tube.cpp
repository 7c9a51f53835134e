#include "mesh/generate/tube.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include "core/error.hpp"
#include "mesh/io/mesh_io.hpp"
#include "test_support.hpp"
#include "generate_checks.hpp"

using namespace softcut;
using namespace softcut::mesh;

TEST_SUITE("mesh/generate/tube") {
  TEST_CASE("closed torus-like surface, positive tets, counts and polygonal volume") {
    for (int radial : {1, 3})
      for (int around : {3, 8, 17})
        for (double jitter : {0.0, 0.2}) {
          if (around < 8 && jitter > 0) continue;  // 120-degree cells: jitter is no small perturbation
          TubeOptions o;
          o.radial = radial, o.around = around, o.layers = 2, o.jitter = jitter, o.seed = unsigned(around);
          o.base_center = Eigen::Vector3d(-0.05, 0.02, 0.01);
          const TetMesh m = generate_tube(o);
          CAPTURE(radial);
          CAPTURE(around);
          CHECK(m.num_nodes() == (radial + 1) * around * 3);
          CHECK(m.num_tets() == 6 * radial * around * 2);
          test::check_solid(m, 0);
          const double s = 0.5 * around * std::sin(2 * std::numbers::pi / around);
          const double area = s * (o.outer_radius * o.outer_radius - o.inner_radius * o.inner_radius);
          CHECK(total_volume(m) == doctest::Approx(area * o.length).epsilon(1e-12));
        }
  }

  TEST_CASE("hole nodes: exactly the grid's inner ring, on the inner radius, on the surface") {
    TubeOptions o;
    o.radial = 2, o.around = 12, o.layers = 3, o.jitter = 0.2;
    const TetMesh m = generate_tube(o);
    const auto hole = tube_hole_nodes(m, o);
    REQUIRE(hole.size() == size_t(o.around * (o.layers + 1)));
    const auto on_surface = surface_node_mask(m, extract_surface(m));
    for (size_t n = 0; n < hole.size(); ++n) {
      const int id = hole[n];
      CHECK(id % (o.radial + 1) == 0);  // ir == 0 in the documented numbering
      CHECK(on_surface[size_t(id)]);
      const Eigen::Vector3d d = m.node(id) - o.base_center;
      CHECK(std::hypot(d.x(), d.y()) == doctest::Approx(o.inner_radius).epsilon(1e-12));
    }
    // No other surface node is nearer the axis than the middle of the wall.
    int inner_surface = 0;
    for (int i = 0; i < m.num_nodes(); ++i)
      inner_surface += on_surface[size_t(i)] && m.node(i).head<2>().norm() < 0.5 * (o.inner_radius + o.outer_radius) &&
                       m.node(i).z() > 1e-9 && m.node(i).z() < o.length - 1e-9;
    CHECK(inner_surface == o.around * (o.layers - 1));
  }

  TEST_CASE("hole nodes survive writing and reading the mesh back") {
    TubeOptions o;
    o.target_tets = 3000;
    const TetMesh m = generate_tube(o);
    const auto want = tube_hole_nodes(m, o);
    const auto r = resolve_tube(o);
    CHECK(want.size() == size_t(r.around * (r.layers + 1)));
    const auto dir = test::scratch_dir("tube_hole");
    for (const char* name : {"t.vtu", "t.msh"}) {
      write_mesh(dir / name, m);
      Diagnostics d;
      CHECK(tube_hole_nodes(read_mesh(dir / name, d), o) == want);
    }
  }

  TEST_CASE("a target tet count picks a resolution within 10 %, jitter moves interior nodes only") {
    for (int target : {1000, 8000}) {
      TubeOptions o;
      o.target_tets = target;
      o.jitter = 0.15;
      const TetMesh m = generate_tube(o);
      CHECK(std::abs(double(m.num_tets()) / target - 1) <= 0.1);
      test::check_solid(m, 0);
      o.jitter = 0;
      const TetMesh plain = generate_tube(o);
      const auto surface = surface_node_mask(plain, extract_surface(plain));
      int moved = 0;
      for (int i = 0; i < m.num_nodes(); ++i) {
        const bool differs = m.node(i) != plain.node(i);
        if (surface[size_t(i)]) CHECK(!differs);
        moved += differs;
      }
      CHECK(moved == m.num_nodes() - int(extract_surface(plain).nodes.size()));
    }
  }

  TEST_CASE("bad options are errors") {
    TubeOptions o;
    o.inner_radius = 0.03;
    CHECK_THROWS_AS(generate_tube(o), Error);
    o = {};
    o.radial = 1, o.around = 2, o.layers = 1;
    CHECK_THROWS_AS(generate_tube(o), Error);
  }

  TEST_CASE("resolutions whose node or tet count overflows an int are errors, not crashes") {
    TubeOptions o;
    o.radial = 100000, o.around = 100000, o.layers = 1;
    CHECK_THROWS_WITH_AS(generate_tube(o), doctest::Contains("too many"), Error);
    o = {};
    o.outer_radius = o.inner_radius + 1e-12;  // default cells of the wall's size: 1.5e11 around
    CHECK_THROWS_WITH_AS(generate_tube(o), doctest::Contains("too many"), Error);
  }
}
