// The implicit grasper springs (tools/springs.hpp) inside whole frames: against
// a dense whole-mesh reference on every backend, with cutting and caching.
#include "sim/step.hpp"

#include <doctest/doctest.h>

#include <algorithm>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "fem/assembly.hpp"
#include "fem/dof_map.hpp"
#include "fixtures.hpp"
#include "test_support.hpp"

using V = Eigen::Vector3d;
namespace backend = softcut::backend;
namespace sim = softcut::sim;
namespace tools = softcut::tools;
namespace fem = softcut::fem;

namespace {

// A 40 x 40 x 20 mm slab of n x n x n/2 cells held at its base, lifted 2 mm
// over 0.1 s by a stiff grasper of `radius` at `center` (the grip goes onto
// its target), solved whole (monolithic).
sim::ScenarioSpec lifted_slab(int n, double radius, const V& center, const char* dir) {
  sim::ScenarioSpec spec;
  spec.name = "slab";
  spec.mesh.generator = "box";
  spec.mesh.options = {{"max.x", 0.04}, {"max.y", 0.04}, {"max.z", 0.02}, {"nx", n}, {"ny", n}, {"nz", n / 2}};
  sim::MaterialAssignment mat;
  mat.name = "tissue";
  mat.young = 5e3;
  mat.poisson = 0.45;
  spec.materials.push_back(mat);
  spec.fixed = sim::NodeSelector::box(V(-1, -1, -1), V(1, 1, 0));
  spec.solver.backend = backend::parse_backend("monolithic");
  spec.timeline.duration = 0.1;
  spec.timeline.fps = 10.0;
  spec.outputs.dir = softcut::test::scratch_dir(dir);
  spec.tools.push_back(softcut::test::spring_grasper(1e5, radius, tools::Path::polyline({0.0, 0.1}, {center, center + V(0, 0, 2e-3)})));
  return spec;
}

// Independent reference: the whole mesh's stiffness with the fixed DOFs
// eliminated, inverted densely (no CHOLMOD, no hybrid model).
struct Monolithic {
  fem::DofMap map;
  Eigen::MatrixXd Kinv;  // (nfree x nfree) m/N
  int nnode = 0;

  explicit Monolithic(const sim::Model& m) {
    nnode = m.mesh.num_nodes();
    std::vector<char> free(size_t(nnode), 0);
    for (int n = 0; n < nnode; ++n) free[size_t(n)] = m.partition.node_set[size_t(n)] != softcut::hybrid::NodeSet::fixed;
    map = fem::make_dof_map(free);
    const Eigen::MatrixXd K = Eigen::MatrixXd(fem::restrict_matrix(fem::assemble_stiffness(m.mesh, m.tet_material), map));
    Kinv = K.llt().solve(Eigen::MatrixXd::Identity(K.rows(), K.cols()));
  }
  // u (nnode x 3) for forces (nnode x 3)
  Eigen::MatrixX3d solve(const Eigen::MatrixX3d& f) const {
    return fem::unflatten(fem::expand_vector(Kinv * fem::restrict_vector(fem::flatten(f), map), map, nnode));
  }
  // (3m x 3m) compliance of the nodes' DOFs
  Eigen::MatrixXd compliance(const std::vector<int>& nodes) const {
    const Eigen::Index ng = Eigen::Index(3 * nodes.size());
    Eigen::MatrixXd C(ng, ng);
    for (Eigen::Index i = 0; i < ng; ++i)
      for (Eigen::Index j = 0; j < ng; ++j)
        C(i, j) = Kinv(map.reduced[size_t(3 * nodes[size_t(i / 3)] + i % 3)],
                       map.reduced[size_t(3 * nodes[size_t(j / 3)] + j % 3)]);
    return C;
  }
};

// Cantilever (fixtures.hpp) with a constant 0.01 N tip load and a grasper
// closing at t = 0 on the two top nodes (0.06, 0.01, 0.02) (interface) and
// (0.08, 0.01, 0.02) (nonoperational surface), its tip lifted 3 mm by t = 0.1.
sim::ScenarioSpec grasp_spec(const std::string& scratch, const std::string& backend) {
  auto spec = softcut::test::cantilever_spec(softcut::test::scratch_dir(scratch), 0.3);
  spec.loads[0].magnitude = tools::Ramp::constant_value(0.01);
  spec.solver.backend = backend::parse_backend(backend);
  const V p(0.07, 0.01, 0.02);
  spec.tools.push_back(softcut::test::spring_grasper(1.0, 0.011, tools::Path::polyline({0.0, 0.1}, {p, p + V(0, 0, 3e-3)})));  // stiffness set per test
  return spec;
}

// Closed form of the springs of tool 0 in the state's frame: with W the
// grip's weights and C the compliance of its nodes, the point forces solve
// (I/kp + W C W^T) f = T - X_p - W u0 (u0 the response to the loads); the
// nodes take W^T f (3 per entry of ts.nodes).
Eigen::VectorXd closed_form(const sim::Model& m, const sim::State& s, const Monolithic& ref, double k) {
  const tools::ToolState& ts = s.tools[0];
  const double kp = k / double(ts.grip.size());
  const Eigen::MatrixX3d u0 = ref.solve(sim::load_forces(m, s, s.time));
  const Eigen::MatrixXd W = softcut::test::grip_weights(ts);
  const Eigen::MatrixXd A = W * ref.compliance(ts.nodes) * W.transpose();
  const Eigen::VectorXd d = softcut::test::grip_gaps(ts, m.mesh.nodes, u0);
  return W.transpose() * (Eigen::MatrixXd::Identity(A.rows(), A.cols()) / kp + A).llt().solve(d);
}

// The grip covers the jaw's area on the top face (z = 0.02), not one node;
// a jaw wider than the bar also holds its sides, within half a radius of
// the top.
void check_patch(const sim::Model& m, const tools::ToolState& ts, const V& center, double radius) {
  REQUIRE(ts.grip.size() >= 7);
  for (const auto& p : ts.grip) {
    const V x = p.at(m.mesh.nodes);
    CHECK((x - center).norm() <= 1.5 * radius);
    CHECK(x.z() >= 0.02 - 0.5 * radius);
  }
}

Eigen::VectorXd tool_forces(const sim::State& s) {
  Eigen::VectorXd f(Eigen::Index(3 * s.tools[0].forces.size()));
  for (size_t j = 0; j < s.tools[0].forces.size(); ++j) f.segment<3>(Eigen::Index(3 * j)) = s.tools[0].forces[j];
  return f;
}

// Max relative difference of u and the reference over the non-interior rows.
double displacement_error(const sim::Model& m, const sim::State& s, const Monolithic& ref) {
  const Eigen::MatrixX3d u = ref.solve(s.forces);
  double err = 0;
  for (int n = 0; n < m.mesh.num_nodes(); ++n)
    if (m.partition.node_set[size_t(n)] != softcut::hybrid::NodeSet::interior)
      err = std::max(err, (s.displacement.row(n) - u.row(n)).norm());
  return err / u.rowwise().norm().maxCoeff();
}

// Delegates to a real solver but reports a system generation the test sets,
// standing in for cutting (which rebuilds the operational system).
class GenerationProbe final : public backend::Solver {
 public:
  explicit GenerationProbe(std::unique_ptr<const backend::Solver> inner) : inner_(std::move(inner)) {}
  long generation = 0;
  std::string name() const override { return inner_->name(); }
  void solve(const Eigen::MatrixX3d& f, Eigen::MatrixX3d& u, backend::SolverRun& w, backend::SolveStats& st,
             const backend::FrameInput& in) const override {
    inner_->solve(f, u, w, st, in);
  }
  bool nonlinear() const override { return inner_->nonlinear(); }
  bool interior_valid() const override { return inner_->interior_valid(); }
  std::vector<std::pair<std::string, double>> precompute_ms() const override { return inner_->precompute_ms(); }
  const backend::BackendChoice& backend() const override { return inner_->backend(); }
  void unit_responses(const std::vector<int>& nodes, backend::SolverRun& w, Eigen::MatrixXd& out) const override {
    inner_->unit_responses(nodes, w, out);
  }
  void start_run(backend::SolverRun& w, const backend::CutBody* cut) const override {
    inner_->start_run(w, cut);
  }
  long system_generation(const backend::SolverRun&) const override { return generation; }
  void apply_cut(const backend::CutBody& cut, backend::SolverRun& w) const override {
    inner_->apply_cut(cut, w);
  }

 private:
  std::unique_ptr<const backend::Solver> inner_;
};

}  // namespace

TEST_SUITE("sim/step") {
  TEST_CASE("a stiff implicit grasper matches the closed form (I + kC)^-1 k d in the first frames") {
    for (const std::string backend : {"cpu", "direct", "monolithic"}) {
      CAPTURE(backend);
      auto spec = grasp_spec("sim_springs_stiff", backend);
      sim::Model m = sim::compile(spec);
      const Monolithic ref(m);
      const std::vector<int> grasped = {45, 46};  // top nodes under the jaw: the stiffness scale
      REQUIRE((m.mesh.node(45) - V(0.06, 0.01, 0.02)).norm() < 1e-12);
      REQUIRE((m.mesh.node(46) - V(0.08, 0.01, 0.02)).norm() < 1e-12);
      REQUIRE(m.partition.node_set[45] == softcut::hybrid::NodeSet::interface);
      REQUIRE(m.partition.node_set[46] == softcut::hybrid::NodeSet::surface);
      // Per-node stiffness kn with kn ||C_gg|| = 100: far beyond what an
      // explicit spring survives (it needs kn ||C|| < ~1).
      const double normC = ref.compliance(grasped).selfadjointView<Eigen::Lower>().eigenvalues().maxCoeff();
      const double k = 2 * 100.0 / normC;
      m = sim::compile([&] { spec.tools[0].stiffness = k; return spec; }());
      sim::State s = sim::make_state(m);
      for (int frame = 0; frame < 3; ++frame) {
        CAPTURE(frame);
        sim::step(m, s);
        check_patch(m, s.tools[0], V(0.07, 0.01, 0.02), 0.011);
        const Eigen::VectorXd expected = closed_form(m, s, ref, k);
        CHECK(expected.norm() > 1e-4);  // the spring does work in every frame
        CHECK((tool_forces(s) - expected).norm() <= 1e-8 * expected.norm());
        // The displacement is the response to all forces, the springs' included.
        CHECK(displacement_error(m, s, ref) <= 1e-8);
      }
      CHECK(s.springs.builds == 1);
      CHECK(s.stats.springs_frames == 3);
    }
  }

  TEST_CASE("explicit springs are still available: force from last frame's positions") {
    auto spec = grasp_spec("sim_springs_explicit", "direct");
    spec.tools[0].implicit = false;
    spec.tools[0].stiffness = 0.5;
    const sim::Model m = sim::compile(spec);
    sim::State s = sim::make_state(m);
    sim::step(m, s);  // grasp on the rest positions: no stretch yet
    CHECK(tool_forces(s).norm() <= 1e-12 * 0.5 * 3e-3);  // rounding of the barycentric points only
    const Eigen::MatrixX3d u_prev = s.displacement;
    sim::step(m, s);
    const tools::ToolState& ts = s.tools[0];
    // Each point's spring (0.5 N/m over the points) on last frame's positions, onto its nodes.
    const Eigen::VectorXd expected = softcut::test::grip_weights(ts).transpose() *
                                     (0.5 / double(ts.grip.size()) * softcut::test::grip_gaps(ts, m.mesh.nodes, u_prev));
    REQUIRE(expected.norm() > 0);
    CHECK((tool_forces(s) - expected).norm() <= 1e-14 * expected.norm());
    CHECK(s.springs.builds == 0);
  }

  TEST_CASE("the compliance cache is rebuilt when the grasped set changes and only then") {
    auto spec = grasp_spec("sim_springs_cache", "cpu");
    spec.tools[0].stiffness = 50.0;
    const sim::Model m = sim::compile(spec);
    const Monolithic ref(m);
    sim::State s = sim::make_state(m), nocache = sim::make_state(m);
    nocache.springs.enabled = false;
    for (int frame = 0; frame < 3; ++frame) sim::step(m, s), sim::step(m, nocache);
    CHECK(s.springs.builds == 1);
    CHECK(nocache.springs.builds == 3);
    CHECK((s.displacement - nocache.displacement).norm() <= 1e-9 * s.displacement.norm());
    const std::vector<int> first = s.tools[0].nodes;
    CHECK(s.springs.nodes == first);

    // Let go for a frame, then grasp a small patch around (0.08, 0.01, 0.02).
    s.tool_specs[0].enabled = false;
    sim::step(m, s);
    CHECK(s.tools[0].nodes.empty());
    CHECK(s.springs.builds == 1);  // nothing grasped: nothing to build
    s.tool_specs[0].enabled = true;
    s.tool_specs[0].radius = 0.005;
    s.tools[0].override_tip = true;
    s.tools[0].tip = m.mesh.node(46) + s.displacement.row(46).transpose();
    sim::step(m, s);
    const std::vector<int> second = s.tools[0].nodes;
    REQUIRE(std::count(second.begin(), second.end(), 46) == 1);
    REQUIRE(second != first);
    CHECK(s.springs.builds == 2);
    CHECK(s.springs.nodes == second);
    CHECK((s.springs.compliance - ref.compliance(second)).norm() <= 1e-8 * ref.compliance(second).norm());
    s.tools[0].tip += V(0, 0, 2e-3);  // pull: the same set, the cached columns serve
    sim::step(m, s);
    CHECK(s.springs.builds == 2);
    const Eigen::VectorXd expected = closed_form(m, s, ref, 50.0);
    CHECK(expected.norm() > 1e-3);
    CHECK((tool_forces(s) - expected).norm() <= 1e-8 * expected.norm());
  }

  // #17: a grasp must not pull one node into a spike. A slab fixed at its
  // base is lifted 2 mm by a stiff grasper of radius r = 4 mm at the middle of
  // its top face; "peak" is the grip's lift over the mean lift of the top
  // nodes in the ring r < d <= 2r around it. A jaw that holds one node (the
  // old grasp) peaks in proportion to the refinement (a point load: 5.3,
  // 11.7, 22.4 at 8, 16, 32 cells). The patch grip is a rigid punch of radius
  // r, whose continuum value on a half-space is 1 / ((2/pi) mean of
  // asin(r/d) over the ring) = 2.09 (a slab on a fixed base 5 r below
  // decays faster, so somewhat more); the meshes rise by shrinking factors
  // per halving of the cells (1.09, 1.44, 1.86: 1.32x, 1.29x; 2.27 at 64
  // cells, 1.22x, measured once: 90 s, 10 GB) while one node's peak doubles.
  // Whether it settles at the slab's punch value is not shown here (finer
  // meshes do not fit a test); the bound below is a regression bound.
  TEST_CASE("a patch grasp lifts a patch: its peak over the ring around it stays bounded as the mesh is refined") {
    const double radius_ring = 4e-3;  // the patch jaw's radius
    auto peak = [&](int n, double radius, const V& center) {
      const sim::Model m = sim::compile(lifted_slab(n, radius, center, "sim_springs_patch"));
      sim::State s = sim::make_state(m);
      for (int i = 0; i < m.num_frames; ++i) sim::step(m, s);
      const tools::ToolState& ts = s.tools[0];
      REQUIRE(!ts.grip.empty());
      double lift = 0;
      for (const auto& p : ts.grip) lift += p.at(s.displacement).z() / double(ts.grip.size());
      CHECK(lift == doctest::Approx(2e-3).epsilon(0.02));
      double ring = 0;
      int count = 0;
      for (int v = 0; v < m.mesh.num_nodes(); ++v) {
        const V x = m.mesh.node(v);
        const double d = (x - V(center.x(), center.y(), 0.02)).norm();
        if (x.z() == 0.02 && d > radius_ring && d <= 2 * radius_ring) ring += s.displacement(v, 2), ++count;
      }
      REQUIRE(count >= 4);
      return lift / (ring / count);
    };
    const V off_node(0.0207, 0.0211, 0.02), on_node(0.02, 0.02, 0.02);
    double patch[3], single[3];
    const int cells[3] = {8, 16, 32};
    for (int i = 0; i < 3; ++i) {
      patch[i] = peak(cells[i], radius_ring, off_node);
      single[i] = peak(cells[i], 1e-7, on_node);  // a jaw on one node
      MESSAGE("cells ", cells[i], ": patch peak ", patch[i], ", one-node peak ", single[i]);
    }
    for (int i = 0; i + 1 < 3; ++i) {
      CHECK(single[i + 1] >= 1.8 * single[i]);  // the control: the measure sees a spike grow
      CHECK(patch[i + 1] <= 1.4 * patch[i]);    // the patch's: 1.32x, 1.29x
    }
    CHECK(patch[2] <= 2.5);               // the scale of a rigid punch (2.09), far below one node's 22
    CHECK(patch[2] <= 0.15 * single[2]);
  }

  // Issue #43's realism check: the grasp's effect on the tissue around it
  // must not depend on where the mesh's nodes happen to lie. The same slab
  // and 2 mm lift by a 4 mm patch jaw (off every node) as above, at 16, 24
  // and 32 cells across: the mean lift of the top nodes 4-8 mm from the jaw
  // varies by at most 1.3x (a one-node jaw: 1.64x when the issue measured).
  // Measured 2026-11-29: 1.388, 1.202, 1.074 mm (1.29x): inside the bound,
  // but still falling with refinement, not settled.
  TEST_CASE("the ring 4-8 mm around a grasp lifts alike on meshes of 16, 24 and 32 cells") {
    const V center(0.0207, 0.0211, 0.02);
    std::vector<double> rings;
    for (const int n : {16, 24, 32}) {
      const sim::Model m = sim::compile(lifted_slab(n, 4e-3, center, "sim_springs_ring"));
      sim::State s = sim::make_state(m);
      for (int i = 0; i < m.num_frames; ++i) sim::step(m, s);
      double ring = 0;
      int count = 0;
      for (int v = 0; v < m.mesh.num_nodes(); ++v) {
        const V x = m.mesh.node(v);
        const double d = (x - center).norm();
        if (x.z() == 0.02 && d > 4e-3 && d <= 8e-3) ring += s.displacement(v, 2), ++count;
      }
      REQUIRE(count >= 8);
      rings.push_back(ring / count);
      MESSAGE("cells ", n, ": ring mean lift ", 1e3 * rings.back(), " mm over ", count, " nodes");
    }
    const double lo = *std::min_element(rings.begin(), rings.end()), hi = *std::max_element(rings.begin(), rings.end());
    REQUIRE(lo > 0);
    CHECK(hi / lo <= 1.3);
  }

  TEST_CASE("a jaw that would hold too many nodes is a clear error, not hours of solves") {
    sim::ScenarioSpec spec;
    spec.name = "slab";
    spec.mesh.generator = "box";
    spec.mesh.options = {{"max.x", 0.04}, {"max.y", 0.04}, {"max.z", 0.01}, {"nx", 24}, {"ny", 24}, {"nz", 2}};
    spec.fixed = sim::NodeSelector::box(V(-1, -1, -1), V(1, 1, 0));
    spec.solver.backend = backend::parse_backend("monolithic");
    spec.outputs.dir = softcut::test::scratch_dir("sim_springs_huge");
    // Its jaw radius covers the whole top face: 625 nodes.
    spec.tools.push_back(softcut::test::spring_grasper(10.0, 0.05, tools::Path::fixed_at(V(0.02, 0.02, 0.01))));
    const sim::Model m = sim::compile(spec);
    sim::State s = sim::make_state(m);
    CHECK_THROWS_WITH_AS(sim::step(m, s), doctest::Contains("more than the 400 their exact solve allows"), softcut::Error);
  }

  TEST_CASE("a fixed grasped node takes no spring force") {
    auto spec = grasp_spec("sim_springs_fixed", "direct");
    spec.tools[0].path = tools::Path::fixed_at(V(0.002, 0.01, 0.02));  // on the top face by the clamped end
    spec.tools[0].radius = 0.021;
    spec.tools[0].stiffness = 10.0;
    const sim::Model m = sim::compile(spec);
    sim::State s = sim::make_state(m);
    sim::step(m, s);
    sim::step(m, s);
    const tools::ToolState& ts = s.tools[0];
    REQUIRE(!ts.nodes.empty());
    bool any_fixed = false, any_free = false;
    for (size_t j = 0; j < ts.nodes.size(); ++j) {
      const bool fixed = m.partition.node_set[size_t(ts.nodes[j])] == softcut::hybrid::NodeSet::fixed;
      any_fixed |= fixed, any_free |= !fixed;
      if (fixed) CHECK(ts.forces[j].norm() == 0.0);
    }
    CHECK(any_fixed);
    CHECK(any_free);
    const Monolithic ref(m);
    CHECK(displacement_error(m, s, ref) <= 1e-8);
  }

  TEST_CASE("the compliance cache is rebuilt when the solver's system changes (cutting)") {
    auto spec = grasp_spec("sim_springs_generation", "cpu");
    spec.tools[0].stiffness = 50.0;
    sim::Model m = sim::compile(spec);
    auto probe = std::make_unique<GenerationProbe>(std::move(m.solver));
    GenerationProbe& gen = *probe;
    m.solver = std::move(probe);
    sim::State s = sim::make_state(m);
    sim::step(m, s);
    sim::step(m, s);
    CHECK(s.springs.builds == 1);
    gen.generation = 7;
    sim::step(m, s);
    CHECK(s.springs.builds == 2);
    CHECK(s.springs.generation == 7);
    sim::step(m, s);
    CHECK(s.springs.builds == 2);
  }
}
