// Large deformation against CalculiX (DESIGN.md §1b, docs/fidelity.md): the
// same mesh, loads and supports solved by softcut's whole pipeline (a
// scenario compiled and stepped, the hybrid model's Newton frames) and by
// ccx's *STATIC, NLGEOM with C3D4 elements. Corotational elasticity against
// ccx's *ELASTIC (St Venant-Kirchhoff under NLGEOM: the two agree where
// strains are moderate, whatever the rotation), neo-Hooke against ccx's NEO
// HOOKE (the same law: they agree to the solvers' tolerances). The linear
// model is checked to be far off, so the cases have teeth.
#include <doctest/doctest.h>

#include <cmath>

#include "ccx.hpp"
#include "sim/model.hpp"
#include "sim/step.hpp"
#include "test_support.hpp"

using namespace softcut;
using V = Eigen::Vector3d;

namespace {

constexpr double kE = 1e4, kNu = 0.3;

// A box scenario of one material, every tet operational (the ccx cases have
// no condensed region: the whole body rotates).
sim::ScenarioSpec box_spec(const std::string& name, const V& size, int nx, int ny, int nz, const char* model) {
  sim::ScenarioSpec s;
  s.name = name;
  s.mesh.generator = "box";
  s.mesh.options = {{"max.x", size.x()}, {"max.y", size.y()}, {"max.z", size.z()}, {"nx", nx}, {"ny", ny}, {"nz", nz}};
  sim::MaterialAssignment mat;
  mat.name = "tissue";
  mat.young = kE;
  mat.poisson = kNu;
  mat.model = fem::parse_material_model(model);
  s.materials.push_back(mat);
  s.operational.kind = sim::TetSelector::Kind::all;
  s.fixed = sim::NodeSelector::box(V(-1, -1, -1), V(0, 1, 1));
  s.timeline.duration = 1.0;
  s.timeline.fps = 20.0;  // the load ramps over 20 Newton frames, as ccx's increments do
  s.outputs.dir = test::scratch_dir("fidelity_" + name);
  s.outputs.csv = false;
  return s;
}

struct Solved {
  sim::Model model;
  Eigen::MatrixX3d u;  // at the last frame
};

Solved run(const sim::ScenarioSpec& spec) {
  Solved r{sim::compile(spec), {}};
  sim::State s = sim::make_state(r.model);
  for (int f = 0; f < r.model.num_frames; ++f) sim::step(r.model, s);
  r.u = s.displacement;
  return r;
}

std::vector<int> nodes_at_x(const mesh::TetMesh& m, double x) {
  std::vector<int> ids;
  for (int n = 0; n < m.num_nodes(); ++n)
    if (std::abs(m.nodes(n, 0) - x) < 1e-12) ids.push_back(n);
  return ids;
}

V mean_rows(const Eigen::MatrixX3d& u, const std::vector<int>& ids) {
  V s = V::Zero();
  for (int n : ids) s += u.row(n).transpose();
  return s / double(ids.size());
}

// A cantilever 0.1 x 0.01 x 0.01 m, clamped at x = 0, a tip load P along -z
// with P L^2 / (E I) = k, spread evenly over the tip face's nodes.
sim::ScenarioSpec cantilever(double k, const char* model) {
  const double L = 0.1, h = 0.01, I = h * h * h * h / 12;
  sim::ScenarioSpec s = box_spec(std::string("cantilever_") + model, V(L, h, h), 20, 2, 2, model);
  sim::LoadSpec tip;
  tip.name = "tip";
  tip.nodes = sim::NodeSelector::box(V(L, -1, -1), V(1, 1, 1));
  tip.direction = V(0, 0, -1);
  tip.magnitude = tools::Ramp::linear_ramp(0.0, k * kE * I / (L * L), 0.0, 1.0);
  s.loads.push_back(tip);
  return s;
}

test::CcxProblem ccx_problem(const Solved& r, test::CcxProblem::Law law) {
  test::CcxProblem p;
  p.mesh = r.model.mesh;
  p.young = kE;
  p.poisson = kNu;
  p.law = law;
  p.fixed = r.model.partition.fixed;
  return p;
}

// A flap 0.04 x 0.02 x 0.004 m clamped at x = 0, its free edge (x = 0.04)
// grasped and lifted by `lift` m along +z (a prescribed displacement).
sim::ScenarioSpec flap(double lift, const char* model) {
  sim::ScenarioSpec s = box_spec(std::string("flap_") + model, V(0.04, 0.02, 0.004), 16, 8, 2, model);
  sim::MotionSpec grasp;
  grasp.name = "grasp";
  grasp.nodes = sim::NodeSelector::box(V(0.04, -1, -1), V(1, 1, 1));
  grasp.path = tools::Path::polyline({0.0, 1.0}, {V::Zero(), V(0, 0, lift)});
  s.motions.push_back(grasp);
  return s;
}

}  // namespace

TEST_SUITE("fidelity/calculix") {
  TEST_CASE("cantilever at P L^2 / EI = 1, 2, 3: corotational within 2 % of CalculiX NLGEOM, volume within 1 %") {
    for (double k : {1.0, 2.0, 3.0}) {
      CAPTURE(k);
      const Solved co = run(cantilever(k, "corotational"));
      const Solved lin = run(cantilever(k, "linear"));
      test::CcxProblem p = ccx_problem(co, test::CcxProblem::Law::elastic);
      p.forces = Eigen::MatrixX3d::Zero(co.model.mesh.num_nodes(), 3);
      const std::vector<int> tip = nodes_at_x(co.model.mesh, 0.1);
      const double I = 1e-8 / 12;
      for (int n : tip) p.forces(n, 2) = -k * kE * I / 0.01 / double(tip.size());
      const Eigen::MatrixX3d uc = test::run_ccx(p, test::scratch_dir("fidelity_ccx_cantilever"));
      const V tc = mean_rows(uc, tip), ts = mean_rows(co.u, tip), tl = mean_rows(lin.u, tip);
      const double v0 = test::deformed_volume(co.model.mesh, Eigen::MatrixX3d::Zero(co.model.mesh.num_nodes(), 3));
      const double vc = test::deformed_volume(co.model.mesh, uc), vs = test::deformed_volume(co.model.mesh, co.u);
      const double vl = test::deformed_volume(co.model.mesh, lin.u);
      MESSAGE("k = ", k, ": tip ccx (", tc.transpose(), "), corotational (", ts.transpose(), ") ",
              (ts - tc).norm() / tc.norm() * 100, " %, linear ", (tl - tc).norm() / tc.norm() * 100,
              " %; volume change ccx ", (vc / v0 - 1) * 100, " %, corotational ", (vs / v0 - 1) * 100, " %, linear ",
              (vl / v0 - 1) * 100, " %");
      CHECK((ts - tc).norm() <= 0.02 * tc.norm());
      CHECK(std::abs(vs - vc) <= 0.01 * vc);
      if (k == 3.0) {
        CHECK((tl - tc).norm() > 0.3 * tc.norm());  // the paper's linear model, far off
        CHECK(std::abs(vl - vc) > 0.05 * vc);
      }
    }
  }

  TEST_CASE("a grasped flap lifted 10 and 20 mm: corotational within 2 % of CalculiX NLGEOM, volume within 1 %") {
    for (double lift : {0.01, 0.02}) {
      CAPTURE(lift);
      const Solved co = run(flap(lift, "corotational"));
      const Solved lin = run(flap(lift, "linear"));
      test::CcxProblem p = ccx_problem(co, test::CcxProblem::Law::elastic);
      p.prescribed = Eigen::MatrixX3d::Zero(co.model.mesh.num_nodes(), 3);
      for (int n : nodes_at_x(co.model.mesh, 0.04)) p.prescribed(n, 2) = lift;
      const Eigen::MatrixX3d uc = test::run_ccx(p, test::scratch_dir("fidelity_ccx_flap"));
      const double scale = uc.rowwise().norm().maxCoeff();
      const double err = (co.u - uc).rowwise().norm().maxCoeff() / scale;
      const double err_lin = (lin.u - uc).rowwise().norm().maxCoeff() / scale;
      const double vc = test::deformed_volume(co.model.mesh, uc), vs = test::deformed_volume(co.model.mesh, co.u);
      const double vl = test::deformed_volume(co.model.mesh, lin.u);
      MESSAGE("lift ", lift * 1000, " mm: max |u - u_ccx| / max |u_ccx|: corotational ", err * 100, " %, linear ",
              err_lin * 100, " %; volume vs ccx: corotational ", (vs / vc - 1) * 100, " %, linear ", (vl / vc - 1) * 100,
              " %");
      CHECK(err <= 0.02);
      CHECK(std::abs(vs - vc) <= 0.01 * vc);
      CHECK(err_lin > 2 * err);
    }
  }

  TEST_CASE("neo-Hooke against CalculiX's NEO HOOKE: the same law, the same answer") {
    const Solved nh = run(flap(0.02, "neohookean"));
    test::CcxProblem p = ccx_problem(nh, test::CcxProblem::Law::neo_hooke);
    p.prescribed = Eigen::MatrixX3d::Zero(nh.model.mesh.num_nodes(), 3);
    for (int n : nodes_at_x(nh.model.mesh, 0.04)) p.prescribed(n, 2) = 0.02;
    const Eigen::MatrixX3d uc = test::run_ccx(p, test::scratch_dir("fidelity_ccx_neohooke"));
    const double err = (nh.u - uc).rowwise().norm().maxCoeff() / uc.rowwise().norm().maxCoeff();
    MESSAGE("neo-Hooke flap lifted 20 mm: max |u - u_ccx| / max |u_ccx| = ", err);
    CHECK(err <= 1e-4);
  }
}
