// The whole-mesh reference (fem/whole_mesh.hpp) against what must hold of
// any solution: K u = f + f0 on the free DOFs, zero on fixed and unused
// nodes, Clapeyron's theorem, the CG and the direct solve agreeing, and unit
// responses equal to solves of unit loads.
#include "fem/whole_mesh.hpp"

#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <cmath>
#include <functional>
#include <random>

#include "core/error.hpp"
#include "fem/assembly.hpp"
#include "fem/dof_map.hpp"
#include "fem/strain.hpp"
#include "fem_fixtures.hpp"
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
    if (fem::any_element_load(material)) r -= fem::flatten(fem::element_loads(mesh, material));
    double rmax = 0;
    for (int n = 0; n < unused(); ++n)
      if (!fixed[size_t(n)]) rmax = std::max(rmax, r.segment<3>(3 * n).cwiseAbs().maxCoeff());
    return rmax;
  }
};

std::vector<int> nodes_where(const mesh::TetMesh& m, const std::function<bool(const Eigen::Vector3d&)>& pred) {
  std::vector<int> ids;
  for (int i = 0; i < m.num_nodes(); ++i)
    if (pred(m.node(i))) ids.push_back(i);
  return ids;
}

// Consistent nodal weights of a uniform traction on the boundary faces whose
// three nodes satisfy `on_face`: each triangle gives area / 3 to its nodes.
// (nnode), m^2.
Eigen::VectorXd face_weights(const mesh::TetMesh& m, const std::function<bool(const Eigen::Vector3d&)>& on_face) {
  Eigen::VectorXd w = Eigen::VectorXd::Zero(m.num_nodes());
  for (int t = 0; t < m.num_tets(); ++t)
    for (const auto& f : mesh::kTetFaces) {
      const int a = m.tets(t, f[0]), b = m.tets(t, f[1]), c = m.tets(t, f[2]);
      if (!(on_face(m.node(a)) && on_face(m.node(b)) && on_face(m.node(c)))) continue;
      const double area = 0.5 * (m.node(b) - m.node(a)).cross(m.node(c) - m.node(a)).norm();
      for (int v : {a, b, c}) w(v) += area / 3;
    }
  return w;
}

Eigen::Matrix<double, 1, 6> voigt_strain(const Eigen::Matrix3d& A) {
  Eigen::Matrix<double, 1, 6> e;
  e << A(0, 0), A(1, 1), A(2, 2), A(1, 2) + A(2, 1), A(2, 0) + A(0, 2), A(0, 1) + A(1, 0);
  return e;
}

// Tip deflection of a cantilever [0, 10] x [0, 1] x [0, 1] m, clamped at x = 0,
// total load P along -y spread as a uniform traction over the end face x = 10,
// over the Euler-Bernoulli value P L^3 / (3 E I). Deflection = work-conjugate
// mean of u_y over the end face (face weights).
double cantilever_ratio(int n) {
  const double L = 10, h = 1, E = 1e4, nu = 0.3, P = 1e-2;
  const mesh::TetMesh m = test::jittered_box(10 * n, n, n, 0, 1, Eigen::Vector3d(L, h, h));
  auto on_end = [&](const Eigen::Vector3d& x) { return std::abs(x.x() - L) < 1e-9; };
  const Eigen::VectorXd w = face_weights(m, on_end);
  REQUIRE(w.sum() == doctest::Approx(h * h).epsilon(1e-12));
  fem::StaticProblem p;
  p.fixed_nodes = nodes_where(m, [](const Eigen::Vector3d& x) { return x.x() == 0; });
  p.forces = Eigen::MatrixX3d::Zero(m.num_nodes(), 3);
  p.forces.col(1) = -P / (h * h) * w;
  const fem::StaticSolution s = fem::solve_static(m, std::vector<fem::Material>(size_t(m.num_tets()), {E, nu}), p);
  const double tip = -w.dot(s.displacement.col(1)) / w.sum();
  const double I = h * h * h * h / 12;
  return tip / (P * L * L * L / (3 * E * I));
}

}  // namespace

TEST_SUITE("fem/whole_mesh") {
  TEST_CASE("the solves satisfy K u = f on the free DOFs, Clapeyron's theorem, and CG agrees with CHOLMOD") {
    std::mt19937 rng(21);
    const Bar b;
    for (int trial = 0; trial < 5; ++trial) {
      const Eigen::MatrixX3d f = b.random_forces(rng);
      double rel = -1;
      const fem::WholeMeshSolver solver(b.mesh, b.material, b.fixed);
      solve::SolveWorkspace ws;
      const Eigen::MatrixX3d u = solver.solve(f, ws, {}, &rel);
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
    solve::SolveWorkspace ws;
    const Eigen::MatrixX3d u = solver.solve(Eigen::MatrixX3d::Zero(b.mesh.num_nodes(), 3), ws, {}, &rel);
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
    solve::SolveWorkspace ws;
    const Eigen::MatrixXd R = solver.unit_responses(nodes, ws);
    REQUIRE(R.rows() == 3 * b.mesh.num_nodes());
    REQUIRE(R.cols() == 6);
    for (size_t j = 0; j < nodes.size(); ++j)
      for (int a = 0; a < 3; ++a) {
        Eigen::MatrixX3d f = Eigen::MatrixX3d::Zero(b.mesh.num_nodes(), 3);
        f(nodes[j], a) = 1.0;
        const Eigen::VectorXd u = fem::flatten(solver.solve(f, ws));
        CHECK((R.col(Eigen::Index(3 * j + a)) - u).norm() <= 1e-12 * u.norm());
      }
    CHECK(test::contains(test::error_of([&] { solver.unit_responses({0}, ws); }), "node 0 is fixed or in no tetrahedron"));
    CHECK(test::contains(test::error_of([&] { solver.unit_responses({b.unused()}, ws); }), "is fixed or in no tetrahedron"));
    CHECK(test::contains(test::error_of([&] { solver.unit_responses({-1}, ws); }), "node -1"));
  }

  TEST_CASE("everything fixed: nothing to solve, zero displacement") {
    Bar b;
    b.fixed.assign(b.fixed.size(), 1);
    const fem::WholeMeshSolver solver(b.mesh, b.material, b.fixed);
    CHECK(solver.system().dofs().size() == 0);
    double rel = -1;
    solve::SolveWorkspace ws;
    CHECK(solver.solve(Eigen::MatrixX3d::Ones(b.mesh.num_nodes(), 3), ws, {}, &rel).isZero(0));
    CHECK(rel == 0);
  }

  // The general static problem (solve_static: prescribed displacements, reactions) on the same system.
  TEST_CASE("patch test: a linear field on the boundary is reproduced inside, strains exact") {
    std::mt19937 rng(21);
    std::normal_distribution<double> g(0, 1);
    for (unsigned seed = 1; seed <= 3; ++seed) {
      const mesh::TetMesh m = test::jittered_box(4, 4, 4, 0.24, seed);  // distorted interior nodes
      const fem::Material mat{5e3, 0.1 + 0.1 * seed};
      const std::vector<fem::Material> mats(size_t(m.num_tets()), mat);
      Eigen::Matrix3d A;
      for (int i = 0; i < 9; ++i) A(i) = 1e-3 * g(rng);
      const Eigen::RowVector3d a(g(rng), g(rng), g(rng));
      auto exact = [&](int i) -> Eigen::RowVector3d { return 1e-3 * a + m.nodes.row(i) * A.transpose(); };
      fem::StaticProblem p;
      p.fixed_nodes = nodes_where(m, [](const Eigen::Vector3d& x) {
        return (x.array() == 0).any() || (x.array() == 1).any();
      });
      REQUIRE(p.fixed_nodes.size() == 125 - 27);
      p.fixed_displacement.resize(Eigen::Index(p.fixed_nodes.size()), 3);
      for (size_t k = 0; k < p.fixed_nodes.size(); ++k) p.fixed_displacement.row(Eigen::Index(k)) = exact(p.fixed_nodes[k]);
      fem::StaticOptions opt;
      for (auto backend : {fem::StaticBackend::cholmod, fem::StaticBackend::cg}) {
        opt.backend = backend;
        opt.cg.tolerance = 1e-14;
        const fem::StaticSolution s = fem::solve_static(m, mats, p, opt);
        CHECK(s.free_dofs == 3 * 27);
        double err = 0;
        for (int i = 0; i < m.num_nodes(); ++i) err = std::max(err, (s.displacement.row(i) - exact(i)).norm());
        CAPTURE(seed);
        CHECK(err <= 1e-14);  // |u| ~ 1e-3 m: 1e-11 relative
        const fem::StrainField eps = fem::element_strains(m, s.displacement);
        const fem::StrainField sig = fem::element_stresses(m, mats, s.displacement);
        const Eigen::Matrix<double, 1, 6> e0 = voigt_strain(A);
        const Eigen::Matrix<double, 1, 6> s0 = (fem::elasticity_matrix(mat) * e0.transpose()).transpose();
        double eerr = 0, serr = 0;
        for (int t = 0; t < m.num_tets(); ++t) {
          eerr = std::max(eerr, (eps.row(t) - e0).norm());
          serr = std::max(serr, (sig.row(t) - s0).norm());
        }
        CHECK(eerr <= 1e-10 * e0.norm());
        CHECK(serr <= 1e-10 * s0.norm());
      }
    }
  }

  // Initial strain, closed form: a body pinned only against rigid motion
  // takes on exactly the strain eps0 it is given (no stress anywhere, no
  // support force), whatever the mesh's distortion.
  TEST_CASE("initial strain patch test: a pinned body takes on a uniform eps0 exactly and stays stress-free") {
    std::mt19937 rng(23);
    std::normal_distribution<double> g(0, 1);
    for (unsigned seed = 1; seed <= 3; ++seed) {
      const mesh::TetMesh m = test::jittered_box(4, 3, 3, 0.24, seed);
      Eigen::Matrix3d A;  // symmetric eps0 with shears
      for (int i = 0; i < 9; ++i) A(i) = 1e-2 * g(rng);
      A = (0.5 * (A + A.transpose())).eval();
      fem::Material mat{4e3, 0.1 + 0.1 * seed};
      const Eigen::Matrix<double, 1, 6> e0 = voigt_strain(A);
      for (int k = 0; k < 6; ++k) mat.initial_strain[size_t(k)] = e0(k);
      const std::vector<fem::Material> mats(size_t(m.num_tets()), mat);
      // Supports that remove the rigid motions without restraining the
      // strain: u = eps0 x prescribed at three corners not on one line.
      const int o = 0;
      int cx = -1, cy = -1;
      for (int i = 0; i < m.num_nodes(); ++i) {
        const Eigen::Vector3d x = m.node(i);
        if (x.y() == 0 && x.z() == 0 && x.x() > 0.99) cx = i;
        if (x.x() == 0 && x.z() == 0 && x.y() > 0.99) cy = i;
      }
      REQUIRE(cx >= 0);
      REQUIRE(cy >= 0);
      REQUIRE(m.node(o).norm() == 0);
      fem::StaticProblem p;
      p.fixed_nodes = {o, cx, cy};
      p.fixed_displacement.resize(3, 3);
      for (int k = 0; k < 3; ++k) p.fixed_displacement.row(k) = (A * m.node(p.fixed_nodes[size_t(k)])).transpose();
      const fem::StaticSolution s = fem::solve_static(m, mats, p);
      double err = 0;
      for (int i = 0; i < m.num_nodes(); ++i)
        err = std::max(err, (s.displacement.row(i) - (A * m.node(i)).transpose()).norm());
      CAPTURE(seed);
      CHECK(err <= 1e-12 * A.norm());
      const fem::StrainField eps = fem::element_strains(m, s.displacement);
      const fem::StrainField sig = fem::element_stresses(m, mats, s.displacement);
      const double s0 = (fem::elasticity_matrix(mat) * e0.transpose()).norm();
      double eerr = 0, smax = 0;
      for (int t = 0; t < m.num_tets(); ++t) {
        eerr = std::max(eerr, (eps.row(t) - e0).norm());
        smax = std::max(smax, sig.row(t).norm());
      }
      CHECK(eerr <= 1e-10 * e0.norm());
      CHECK(smax <= 1e-9 * s0);  // against the stress eps0 would cause if held
      CHECK(s.reaction.norm() <= 1e-9 * s0);
      // Without the initial strain the same supports do not give that field:
      // eps0 is what shapes it.
      const fem::StaticSolution none =
          fem::solve_static(m, std::vector<fem::Material>(size_t(m.num_tets()), {mat.young, mat.poisson}), p);
      double off = 0, scale = 0;
      for (int i = 0; i < m.num_nodes(); ++i) {
        off = std::max(off, (none.displacement.row(i) - (A * m.node(i)).transpose()).norm());
        scale = std::max(scale, (A * m.node(i)).norm());
      }
      CHECK(off > 0.1 * scale);
    }
  }

  // Held all round, a uniform eps0 moves nothing: the equivalent forces of a
  // constant stress cancel at every inner node, the stress is -D eps0, and the
  // support forces are the traction of that stress on the boundary.
  TEST_CASE("initial strain held on the whole boundary: no motion inside, stress -D eps0, balanced supports") {
    const mesh::TetMesh m = test::jittered_box(4, 4, 4, 0.24, 7);
    fem::Material mat{6e3, 0.4};
    mat.initial_strain = {-0.03, -0.03, 0.01, 0.0, 0.004, 0.0};
    const std::vector<fem::Material> mats(size_t(m.num_tets()), mat);
    fem::StaticProblem p;
    p.fixed_nodes = nodes_where(m, [](const Eigen::Vector3d& x) { return (x.array() == 0).any() || (x.array() == 1).any(); });
    const fem::StaticSolution s = fem::solve_static(m, mats, p);
    const Eigen::Matrix<double, 6, 1> e0 = Eigen::Map<const Eigen::Matrix<double, 6, 1>>(mat.initial_strain.data());
    const Eigen::Matrix<double, 6, 1> expected = -fem::elasticity_matrix(mat) * e0;
    CHECK(fem::flatten(s.displacement).norm() <= 1e-14);
    const fem::StrainField sig = fem::element_stresses(m, mats, s.displacement);
    for (int t = 0; t < m.num_tets(); ++t) CHECK((sig.row(t).transpose() - expected).norm() <= 1e-10 * expected.norm());
    // Reactions: zero resultant and moment (a self-equilibrated stress).
    const Eigen::MatrixXd R = test::rigid_motions(m.nodes);
    CHECK((R.transpose() * fem::flatten(s.reaction)).norm() <= 1e-10 * fem::flatten(s.reaction).norm());
    // At a node inside the face x = 1 (not on its edges, which other faces
    // share) the support force is the held stress's traction sigma n over the
    // node's share of the face (n = +x): f0 = integral of B^T D eps0 is the
    // boundary integral of -sigma n, and the support balances it.
    const Eigen::VectorXd w = face_weights(m, [](const Eigen::Vector3d& x) { return x.x() == 1.0; });
    Eigen::Matrix3d sigma;  // -D eps0 as a tensor
    sigma << expected(0), expected(5), expected(4), expected(5), expected(1), expected(3), expected(4), expected(3), expected(2);
    Eigen::Vector3d on_face = Eigen::Vector3d::Zero(), traction = Eigen::Vector3d::Zero();
    for (int i = 0; i < m.num_nodes(); ++i)
      if (m.nodes(i, 0) == 1.0 && m.nodes(i, 1) > 0 && m.nodes(i, 1) < 1 && m.nodes(i, 2) > 0 && m.nodes(i, 2) < 1) {
        on_face += s.reaction.row(i).transpose();
        traction += w(i) * (sigma * Eigen::Vector3d::UnitX());
      }
    CHECK((on_face - traction).norm() <= 1e-10 * traction.norm());
    CHECK(on_face.x() > 0);  // eps0_xx < 0: held in tension, the support pulls the body outward
  }

  // Expected ratios (the lead's independent prototype): 0.22, 0.51, 0.79,
  // 0.94 for 10x1x1 .. 80x8x8 cells. Linear tets lock in bending, so the
  // ratio climbs toward 1 (Timoshenko shear adds < 1% at L/h = 10). The
  // values carry two digits (rounding error 0.005) and the prototype's tip
  // measure may differ from the work-conjugate face mean used here by a few
  // 1e-3 (measured here: 0.2211 0.5076 0.7933 0.9368); 0.01 covers both and
  // is 15x smaller than the gap between refinements (>= 0.14), so a wrong
  // element, load or clamp fails it.
  TEST_CASE("cantilever tip deflection converges to Euler-Bernoulli from below: 10x1x1 .. 40x4x4") {
    const double expected[3] = {0.22, 0.51, 0.79};
    double prev = 0;
    for (int k = 0; k < 3; ++k) {
      const double r = cantilever_ratio(1 << k);
      CAPTURE(k);
      CAPTURE(r);
      CHECK(std::abs(r - expected[k]) <= 0.01);
      CHECK(r > prev);
      prev = r;
    }
  }

  TEST_CASE("cantilever 80x8x8 (about 20k DOFs, CHOLMOD): closer still, below 1") {
    const double r = cantilever_ratio(8);
    CAPTURE(r);
    CHECK(std::abs(r - 0.94) <= 0.01);
    CHECK(r > cantilever_ratio(4));
    CHECK(r < 1.0);
  }

  TEST_CASE("CHOLMOD and CG agree to the CG tolerance, and reactions balance the loads") {
    for (unsigned seed = 1; seed <= 4; ++seed) {
      const mesh::TetMesh m = test::jittered_box(3 + int(seed), 3, 2 + int(seed) % 2, 0.2, seed);
      const auto mats = test::random_materials(m.num_tets(), seed);
      fem::StaticProblem p;
      p.fixed_nodes = nodes_where(m, [](const Eigen::Vector3d& x) { return x.x() == 0; });
      p.forces = Eigen::MatrixX3d::Random(m.num_nodes(), 3);
      fem::StaticOptions opt;
      const fem::StaticSolution a = fem::solve_static(m, mats, p, opt);
      opt.backend = fem::StaticBackend::cg;
      opt.cg.tolerance = 1e-10;
      const fem::StaticSolution b = fem::solve_static(m, mats, p, opt);
      CAPTURE(seed);
      CHECK(b.cg_iterations > 0);
      CHECK(b.cg_relative_residual <= 1e-10);
      // The tolerance bounds the residual ||K_ff (u_cg - u) || / ||f_free||;
      // 2x leaves room for the drift of CG's recursive residual.
      const fem::SparseMatrix K = fem::assemble_stiffness(m, mats);
      const Eigen::VectorXd du = fem::flatten(b.displacement - a.displacement);
      Eigen::VectorXd r = K * du, f = fem::flatten(p.forces);
      for (int i : p.fixed_nodes) r.segment<3>(3 * i).setZero(), f.segment<3>(3 * i).setZero();
      CHECK(r.norm() <= 2e-10 * f.norm());
      CHECK(du.norm() <= 1e-5 * fem::flatten(a.displacement).norm());  // cond(K_ff) < 1e5 here
      // Equilibrium: K annihilates rigid motions, so forces plus reactions
      // have zero resultant and zero moment.
      const Eigen::VectorXd total = fem::flatten(p.forces + a.reaction);
      const Eigen::MatrixXd R = test::rigid_motions(m.nodes);
      CHECK((R.transpose() * total).norm() <= 1e-12 * fem::flatten(p.forces).norm());
      double off = 0;
      for (int i = 0; i < m.num_nodes(); ++i)
        if (m.nodes(i, 0) != 0) off = std::max(off, a.reaction.row(i).norm());
      CHECK(off == 0.0);
    }
  }

  TEST_CASE("nodes outside every tet stay out of the system") {
    mesh::TetMesh m = test::jittered_box(2, 2, 2, 0, 1);
    const int nn = m.num_nodes();
    m.nodes.conservativeResize(nn + 2, 3);
    m.nodes.row(nn) << 5, 5, 5;
    m.nodes.row(nn + 1) << 6, 6, 6;
    const std::vector<fem::Material> mats(size_t(m.num_tets()), {1e4, 0.3});
    fem::StaticProblem p;
    p.fixed_nodes = nodes_where(m, [](const Eigen::Vector3d& x) { return x.x() == 0; });
    p.fixed_nodes.push_back(nn + 1);
    p.fixed_displacement = Eigen::MatrixX3d::Zero(Eigen::Index(p.fixed_nodes.size()), 3);
    p.fixed_displacement.bottomRows(1) << 1, 2, 3;
    p.forces = Eigen::MatrixX3d::Zero(nn + 2, 3);
    p.forces(nn - 1, 2) = 1;
    const fem::StaticSolution s = fem::solve_static(m, mats, p);
    CHECK(s.free_dofs == 3 * (nn - 9));
    CHECK(s.displacement.row(nn).isZero(0));
    CHECK(s.displacement.row(nn + 1) == Eigen::RowVector3d(1, 2, 3));  // prescribed stays prescribed
    CHECK(s.displacement(nn - 1, 2) > 0);
    p.forces(nn, 0) = 1;
    CHECK_THROWS_WITH_AS(fem::solve_static(m, mats, p), doctest::Contains("node 27 carries a force"), Error);
  }

  TEST_CASE("errors: floating part, bad loads, bad fixed lists, CG out of iterations") {
    const mesh::TetMesh a = test::jittered_box(2, 2, 2, 0, 1);
    mesh::TetMesh m = a;  // second copy at x + 2, sharing no node
    m.nodes.resize(2 * a.num_nodes(), 3);
    m.nodes << a.nodes, (a.nodes.rowwise() + Eigen::RowVector3d(2, 0, 0));
    m.tets.resize(2 * a.num_tets(), 4);
    m.tets << a.tets, (a.tets.array() + a.num_nodes()).matrix();
    m.labels = Eigen::VectorXi::Zero(m.num_tets());
    const std::vector<fem::Material> mats(size_t(m.num_tets()), {1e4, 0.3});
    fem::StaticProblem p;
    p.fixed_nodes = nodes_where(m, [](const Eigen::Vector3d& x) { return x.x() == 0; });
    CHECK_THROWS_WITH_AS(fem::solve_static(m, mats, p),
                         doctest::Contains("static solve: the part of the body containing node 27 (48 tets"), Error);
    p.fixed_nodes = nodes_where(m, [](const Eigen::Vector3d& x) { return x.x() == 0 || x.x() == 2; });
    CHECK_NOTHROW(fem::solve_static(m, mats, p));

    fem::StaticProblem q = p;
    q.forces = Eigen::MatrixX3d::Zero(m.num_nodes(), 3);
    q.forces(30, 1) = std::nan("");
    CHECK_THROWS_WITH_AS(fem::solve_static(m, mats, q), doctest::Contains("force of node 30 is not finite"), Error);
    q.forces = Eigen::MatrixX3d::Zero(5, 3);
    CHECK_THROWS_WITH_AS(fem::solve_static(m, mats, q), doctest::Contains("5 rows"), Error);
    q = p;
    q.fixed_displacement = Eigen::MatrixX3d::Zero(Eigen::Index(p.fixed_nodes.size()), 3);
    q.fixed_displacement(2, 0) = INFINITY;
    const std::string msg = cat("prescribed displacement of node ", p.fixed_nodes[2]);
    CHECK_THROWS_WITH_AS(fem::solve_static(m, mats, q), doctest::Contains(msg.c_str()), Error);
    q.fixed_displacement = Eigen::MatrixX3d::Zero(3, 3);
    CHECK_THROWS_WITH_AS(fem::solve_static(m, mats, q), doctest::Contains("one row per fixed node"), Error);
    q = p;
    q.fixed_nodes.push_back(q.fixed_nodes.front());
    CHECK_THROWS_WITH_AS(fem::solve_static(m, mats, q), doctest::Contains("listed twice"), Error);
    q.fixed_nodes.back() = 1000;
    CHECK_THROWS_WITH_AS(fem::solve_static(m, mats, q), doctest::Contains("fixed node 1000 is out of range"), Error);

    q = p;
    q.forces = Eigen::MatrixX3d::Ones(m.num_nodes(), 3);
    fem::StaticOptions opt;
    opt.backend = fem::StaticBackend::cg;
    opt.cg.max_iterations = 2;
    CHECK_THROWS_WITH_AS(fem::solve_static(m, mats, q, opt), doctest::Contains("stopped after 2 iterations"), Error);
  }
}
