// The whole-mesh reference (fem/whole_mesh.hpp) against what must hold of
// any solution: K u = f + f0 on the free DOFs, zero on fixed and unused
// nodes, Clapeyron's theorem, the CG and the direct solve agreeing, and unit
// responses equal to solves of unit loads.
#include "fem/whole_mesh.hpp"

#include <doctest/doctest.h>

#include <random>

#include "core/error.hpp"
#include "mesh/generate/box.hpp"
#include "test_support.hpp"

using namespace softcut;

namespace {

// A 0.1 x 0.04 x 0.04 m box (5 x 2 x 2 cells) fixed at x = 0, one material,
// plus one node in no tet (the unused node, last).
struct Bar {
  mesh::TetMesh mesh;
  std::vector<fem::Material> material;
  std::vector<char> fixed;
  Bar() {
    mesh::BoxOptions o;
    o.max_corner = Eigen::Vector3d(0.1, 0.04, 0.04);
    o.nx = 5, o.ny = 2, o.nz = 2;
    mesh = mesh::generate_box(o);
    mesh.nodes.conservativeResize(mesh.nodes.rows() + 1, 3);
    mesh.nodes.row(mesh.nodes.rows() - 1) << 0.5, 0.5, 0.5;
    material.assign(size_t(mesh.num_tets()), fem::Material{});
    fixed.assign(size_t(mesh.num_nodes()), 0);
    for (int n = 0; n < mesh.num_nodes() - 1; ++n) fixed[size_t(n)] = mesh.nodes(n, 0) == 0;
  }
  int unused() const { return mesh.num_nodes() - 1; }
  Eigen::MatrixX3d random_forces(std::mt19937& rng) const {
    std::uniform_real_distribution<double> d(-0.01, 0.01);
    Eigen::MatrixX3d f = Eigen::MatrixX3d::Zero(mesh.num_nodes(), 3);
    for (int n = 0; n < unused(); ++n)
      if (!fixed[size_t(n)]) f.row(n) << d(rng), d(rng), d(rng);
    return f;
  }
  // max |K u - f - f0| over the free nodes' DOFs, N.
  double residual(const Eigen::MatrixX3d& u, const Eigen::MatrixX3d& f) const {
    Eigen::VectorXd r = fem::assemble_stiffness(mesh, material) * fem::flatten(u) - fem::flatten(f);
    if (fem::any_initial_strain(material)) r -= fem::flatten(fem::initial_strain_forces(mesh, material));
    double rmax = 0;
    for (int n = 0; n < unused(); ++n)
      if (!fixed[size_t(n)]) rmax = std::max(rmax, r.segment<3>(3 * n).cwiseAbs().maxCoeff());
    return rmax;
  }
};

}  // namespace

TEST_SUITE("fem/whole_mesh") {
  TEST_CASE("the solves satisfy K u = f on the free DOFs, Clapeyron's theorem, and CG agrees with CHOLMOD") {
    std::mt19937 rng(21);
    const Bar b;
    for (int trial = 0; trial < 5; ++trial) {
      const Eigen::MatrixX3d f = b.random_forces(rng);
      double rel = -1;
      const fem::WholeMeshSolver solver(b.mesh, b.material, b.fixed);
      const Eigen::MatrixX3d u = solver.solve(f, &rel);
      CHECK(b.residual(u, f) <= 1e-9 * f.cwiseAbs().maxCoeff());
      CHECK(rel >= 0);
      CHECK(rel <= 1e-12);
      for (int n = 0; n < b.mesh.num_nodes(); ++n)
        if (b.fixed[size_t(n)]) CHECK(u.row(n).norm() == 0);
      CHECK(u.row(b.unused()).norm() == 0);
      // Work of the loads = twice the strain energy (computed element by element).
      const double work = (u.array() * f.array()).sum();
      CHECK(work == doctest::Approx(2 * fem::strain_energy(b.mesh, b.material, u)).epsilon(1e-9));
      CHECK(fem::solve_whole_mesh(b.mesh, b.material, b.fixed, f) == u);  // one solve, same bits
      solve::CgOptions o;
      o.tolerance = 1e-13;
      int it = 0;
      const Eigen::MatrixX3d ucg = fem::solve_whole_mesh_cg(b.mesh, b.material, b.fixed, f, o, &it);
      CHECK(it > 0);
      CHECK((ucg - u).cwiseAbs().maxCoeff() <= 1e-8 * u.cwiseAbs().maxCoeff());
    }
  }

  TEST_CASE("initial strains load the system without any force: K u = f0") {
    Bar b;
    for (auto& m : b.material) m.initial_strain = {1e-3, 0, 0, 0, 0, 0};  // the bar wants to be 0.1 % longer
    const fem::WholeMeshSolver solver(b.mesh, b.material, b.fixed);
    double rel = -1;
    const Eigen::MatrixX3d u = solver.solve(Eigen::MatrixX3d::Zero(b.mesh.num_nodes(), 3), &rel);
    CHECK(rel <= 1e-12);
    CHECK(b.residual(u, Eigen::MatrixX3d::Zero(b.mesh.num_nodes(), 3)) <= 1e-12);
    // Free to grow along x from its fixed end: the far end moves by 0.1 % of 0.1 m.
    for (int n = 0; n < b.unused(); ++n)
      if (b.mesh.nodes(n, 0) == 0.1) CHECK(u(n, 0) == doctest::Approx(1e-4).epsilon(1e-6));
  }

  TEST_CASE("unit responses are the solves of unit loads - a fixed or unused node is refused") {
    const Bar b;
    const fem::WholeMeshSolver solver(b.mesh, b.material, b.fixed);
    const std::vector<int> nodes = {b.unused() - 1, 40};
    REQUIRE(!b.fixed[size_t(nodes[0])]);
    REQUIRE(!b.fixed[size_t(nodes[1])]);
    const Eigen::MatrixXd R = solver.unit_responses(nodes);
    REQUIRE(R.rows() == 3 * b.mesh.num_nodes());
    REQUIRE(R.cols() == 6);
    for (size_t j = 0; j < nodes.size(); ++j)
      for (int a = 0; a < 3; ++a) {
        Eigen::MatrixX3d f = Eigen::MatrixX3d::Zero(b.mesh.num_nodes(), 3);
        f(nodes[j], a) = 1.0;
        const Eigen::VectorXd u = fem::flatten(solver.solve(f));
        CHECK((R.col(Eigen::Index(3 * j + a)) - u).norm() <= 1e-12 * u.norm());
      }
    CHECK(test::contains(test::error_of([&] { solver.unit_responses({0}); }), "node 0 is fixed or in no tetrahedron"));
    CHECK(test::contains(test::error_of([&] { solver.unit_responses({b.unused()}); }), "is fixed or in no tetrahedron"));
    CHECK(test::contains(test::error_of([&] { solver.unit_responses({-1}); }), "node -1"));
  }

  TEST_CASE("everything fixed: nothing to solve, zero displacement") {
    Bar b;
    b.fixed.assign(b.fixed.size(), 1);
    const fem::WholeMeshSolver solver(b.mesh, b.material, b.fixed);
    CHECK(solver.system().dofs().size() == 0);
    double rel = -1;
    CHECK(solver.solve(Eigen::MatrixX3d::Ones(b.mesh.num_nodes(), 3), &rel).isZero(0));
    CHECK(rel == 0);
  }
}
