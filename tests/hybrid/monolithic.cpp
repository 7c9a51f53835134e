#include "hybrid/monolithic.hpp"

#include <doctest/doctest.h>

#include <random>

#include "fem/assembly.hpp"
#include "fem/dof_map.hpp"
#include "fixtures.hpp"

using namespace softcut;
using namespace softcut::hybrid;

TEST_SUITE("hybrid/monolithic") {
  TEST_CASE("the reference solves satisfy K u = f on free DOFs and Clapeyron's theorem") {
    std::mt19937 rng(21);
    for (int trial = 0; trial < 5; ++trial) {
      const test::HybridCase c = test::random_case(rng, 4);
      const Eigen::MatrixX3d f = test::load_field(c.mesh.num_nodes(), test::random_loads(c.partition, rng, 4));
      const Eigen::MatrixX3d u = solve_monolithic(c.mesh, c.material, c.fixed_mask, f);
      const Eigen::VectorXd r = fem::assemble_stiffness(c.mesh, c.material) * fem::flatten(u) - fem::flatten(f);
      double rmax = 0;
      for (int v = 0; v < c.mesh.num_nodes(); ++v)
        if (!c.fixed_mask[size_t(v)]) rmax = std::max(rmax, r.segment<3>(3 * v).cwiseAbs().maxCoeff());
      CHECK(rmax <= 1e-9 * f.cwiseAbs().maxCoeff());
      for (int v : c.fixed) CHECK(u.row(v).norm() == 0);
      // Work of the loads = twice the strain energy (computed element by element).
      const double work = (u.array() * f.array()).sum();
      CHECK(work == doctest::Approx(2 * fem::strain_energy(c.mesh, c.material, u)).epsilon(1e-9));
      solve::CgOptions o;
      o.tolerance = 1e-13;
      int it = 0;
      const Eigen::MatrixX3d ucg = solve_monolithic_cg(c.mesh, c.material, c.fixed_mask, f, o, &it);
      CHECK(it > 0);
      CHECK((ucg - u).cwiseAbs().maxCoeff() <= 1e-8 * u.cwiseAbs().maxCoeff());
    }
  }
}
