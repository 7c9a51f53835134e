#include "hybrid/update.hpp"

#include <doctest/doctest.h>

#include <array>
#include <optional>
#include <random>

#include "core/error.hpp"
#include "core/threads.hpp"
#include "fixtures.hpp"
#include "fem/whole_mesh.hpp"
#include "mesh/generate/presets.hpp"
#include "mesh/generate/tube.hpp"

using namespace softcut;
using namespace softcut::hybrid;
using softcut::test::HybridCase;

namespace {

std::vector<int> visible_nodes(const Partition& p) {
  std::vector<int> v = p.operational;
  v.insert(v.end(), p.interface.begin(), p.interface.end());
  v.insert(v.end(), p.surface.begin(), p.surface.end());
  return v;
}

UpdateOptions with_interior(bool recover) {
  UpdateOptions o;
  o.recover_interior = recover;
  return o;
}

std::unique_ptr<OperationalSolver> tight_cg() {
  solve::CgOptions o;
  o.tolerance = 1e-14;
  return std::make_unique<CgSolver>(o);
}

// A crack: one set-1 node (drawn from rng) gets a twin, appended last, used
// by every other one of its operational tets. Nullopt when that moves none
// or all of them (no crack). c must have operational nodes.
std::optional<mesh::TetMesh> crack_one_node(const HybridCase& c, std::mt19937& rng) {
  const int v = c.partition.operational[rng() % c.partition.operational.size()];
  mesh::TetMesh cut = c.mesh;
  cut.nodes.conservativeResize(c.mesh.num_nodes() + 1, 3);
  cut.nodes.row(c.mesh.num_nodes()) = c.mesh.nodes.row(v);
  int moved = 0, uses = 0;
  for (int t : c.partition.operational_tets)
    for (int k = 0; k < 4; ++k)
      if (cut.tets(t, k) == v && (uses++ % 2)) {
        cut.tets(t, k) = c.mesh.num_nodes();
        ++moved;
      }
  if (moved == 0 || moved == uses) return std::nullopt;
  return cut;
}

}  // namespace

TEST_SUITE("hybrid/update") {
  TEST_CASE("hybrid == monolithic over many random meshes, partitions, fixed sets and loads") {
    std::mt19937 rng(20050707);
    int checked = 0, with_interface = 0, fixed_both = 0, kinds[6] = {};
    for (int trial = 0; trial < 100; ++trial) {
      const HybridCase c = test::random_case(rng);
      PrecomputeOptions po;
      po.storage = trial % 3 == 0 ? Storage::factor : Storage::automatic;
      const Model model = precompute(c.mesh, c.material, c.partition, po);
      State state = make_state(model, tight_cg());
      for (int frame = 0; frame < 3; ++frame) {
        const auto loads = test::random_loads(c.partition, rng, 1 + int(rng() % 6));
        update(model, state, loads, with_interior(frame == 2));
        const Eigen::MatrixX3d ref =
            fem::solve_whole_mesh(c.mesh, c.material, c.fixed_mask, test::load_field(c.mesh.num_nodes(), loads));
        INFO("trial ", trial, " frame ", frame, " kind ", c.partition_kind, " ", describe(c.partition.counts));
        CHECK(test::relative_error(state.u, ref, visible_nodes(c.partition)) <= 1e-8);
        if (frame == 2) CHECK(test::relative_error(state.u, ref, c.partition.interior) <= 1e-8);
        for (int v : c.partition.fixed) CHECK(state.u.row(v).norm() == 0);
        ++checked;
      }
      with_interface += !c.partition.interface.empty();
      bool fixed_op = false, fixed_non = false;  // fixed nodes touched by each region
      for (int t = 0; t < c.mesh.num_tets(); ++t)
        for (int k = 0; k < 4; ++k)
          if (c.fixed_mask[size_t(c.mesh.tets(t, k))]) (c.partition.operational_tet[size_t(t)] ? fixed_op : fixed_non) = true;
      fixed_both += fixed_op && fixed_non;
      ++kinds[c.partition_kind];
    }
    CHECK(checked == 300);
    CHECK(with_interface >= 40);  // the generator really exercises K' and P*
    CHECK(fixed_both >= 30);      // ... and fixed nodes in both regions
    for (int k : kinds) CHECK(k > 0);
  }

  TEST_CASE("the CHOLMOD backend and initial loads give the monolithic answer") {
    std::mt19937 rng(11);
    for (int trial = 0; trial < 10; ++trial) {
      const HybridCase c = test::random_case(rng, trial % 4);
      const auto initial = test::random_loads(c.partition, rng, 4);
      PrecomputeOptions po;
      po.initial_loads = test::load_field(c.mesh.num_nodes(), initial);
      po.storage = trial % 2 ? Storage::dense : Storage::factor;
      const Model model = precompute(c.mesh, c.material, c.partition, po);
      State state = make_state(model);
      CholmodSolver direct;
      const auto loads = test::random_loads(c.partition, rng, 3);
      update(model, state, loads, direct);
      const Eigen::MatrixX3d ref = fem::solve_whole_mesh(c.mesh, c.material, c.fixed_mask,
                                                    po.initial_loads + test::load_field(c.mesh.num_nodes(), loads));
      CHECK(test::relative_error(state.u, ref, visible_nodes(c.partition)) <= 1e-8);
    }
  }

  TEST_CASE("a frame with the run's helper thread holds OpenBLAS at one thread, and gives it back") {
    // The operational solver sees the BLAS thread count the frame runs with.
    struct Probe : OperationalSolver {
      CgSolver cg;
      std::vector<int> seen;
      std::string name() const override { return "probe"; }
      SolveReport solve(const OperationalSystem& sys, const Eigen::VectorXd& b, Eigen::VectorXd& x) override {
        seen.push_back(blas_threads());
        return cg.solve(sys, b, x);
      }
    };
    REQUIRE(blas_threads() > 0);
    const int before = blas_threads();
    apply_blas_threads(2);
    std::mt19937 rng(5);
    const HybridCase c = test::random_case(rng, 0);
    const Model model = precompute(c.mesh, c.material, c.partition);
    const auto loads = test::random_loads(c.partition, rng, 2);
    for (const int threads : {1, 2}) {
      StateOptions so;
      so.product_threads = threads;
      State state = make_state(model, std::make_unique<Probe>(), so);
      REQUIRE(bool(state.helper) == (threads == 2));
      update(model, state, loads);
      update(model, state, loads);
      CHECK(blas_threads() == 2);  // given back after each frame
      const auto& seen = static_cast<Probe&>(*state.solver).seen;
      REQUIRE(seen.size() == 2);
      for (int t : seen) CHECK(t == (threads == 2 ? 1 : 2));
    }
    apply_blas_threads(before);
  }

  TEST_CASE("dense, product and factor storage give the same displacements frame after frame") {
    std::mt19937 rng(5);
    for (int trial = 0; trial < 6; ++trial) {
      const HybridCase c = test::random_case(rng, trial % 4);
      PrecomputeOptions pd, pp, pf;
      pd.storage = Storage::dense;
      pp.storage = Storage::product;
      pf.storage = Storage::factor;
      const Model md = precompute(c.mesh, c.material, c.partition, pd);
      const Model mp = precompute(c.mesh, c.material, c.partition, pp);
      const Model mf = precompute(c.mesh, c.material, c.partition, pf);
      CHECK(md.storage == Storage::dense);
      CHECK(mp.storage == Storage::product);
      CHECK(mf.storage == Storage::factor);
      CHECK(mp.Kstar_inv.size() == 0);
      CHECK(mp.Kstar_inv_Pstar.rows() == 3 * mp.ns());
      CHECK(mf.Kstar_inv.size() == 0);
      CHECK(mf.Kstar_inv_Pstar.size() == 0);
      State sd = make_state(md, tight_cg()), sp = make_state(mp, tight_cg()), sf = make_state(mf, tight_cg());
      CHECK(!sd.columns);
      CHECK(bool(sp.columns) == (mp.ns() > 0));
      for (int frame = 0; frame < 5; ++frame) {
        const auto loads = test::random_loads(c.partition, rng, 3);
        update(md, sd, loads, with_interior(true));
        update(mp, sp, loads, with_interior(true));
        update(mf, sf, loads, with_interior(true));
        CHECK(test::relative_error(sp.u, sd.u, visible_nodes(c.partition)) <= 1e-9);
        CHECK(test::relative_error(sf.u, sd.u, visible_nodes(c.partition)) <= 1e-9);
        CHECK(test::relative_error(sp.u, sd.u, c.partition.interior) <= 1e-9);
        CHECK(test::relative_error(sf.u, sd.u, c.partition.interior) <= 1e-9);
      }
    }
  }

  TEST_CASE("a physics frame writes the loaded and asked-for surface nodes exactly, and only those") {
    std::mt19937 rng(55);
    int asked_total = 0;
    for (int trial = 0; trial < 12; ++trial) {
      const HybridCase c = test::random_case(rng, trial % 4);
      if (c.partition.surface.size() < 3) continue;
      PrecomputeOptions po;
      po.storage = std::array{Storage::dense, Storage::product, Storage::factor}[size_t(trial % 3)];
      const Model model = precompute(c.mesh, c.material, c.partition, po);
      State full = make_state(model, tight_cg()), phys = make_state(model, tight_cg());
      for (int frame = 0; frame < 4; ++frame) {
        const auto loads = test::random_loads(c.partition, rng, 3);
        const std::vector<int> asked = {c.partition.surface[rng() % c.partition.surface.size()],
                                        c.partition.surface[rng() % c.partition.surface.size()], -5,
                                        c.mesh.num_nodes() + 3};
        const Eigen::MatrixX3d before = phys.u;
        update(model, full, loads);
        UpdateOptions o;
        o.full_surface = false;
        o.surface_nodes = asked;
        const FrameReport& r = update(model, phys, loads, o);
        CHECK(!r.surface_complete);
        std::vector<char> written(size_t(c.mesh.num_nodes()), 0);
        for (int pos : phys.loaded_surface) written[size_t(c.partition.surface[size_t(pos)])] = 1;
        for (int v : asked)
          if (v >= 0 && v < c.mesh.num_nodes()) written[size_t(v)] = 1;
        for (int v : c.partition.surface) {
          INFO("trial ", trial, " frame ", frame, " node ", v, " storage ", to_string(model.storage));
          if (written[size_t(v)]) {
            CHECK((phys.u.row(v) - full.u.row(v)).norm() <= 1e-9 * full.u.norm());
            asked_total += 1;
          } else {
            CHECK(phys.u.row(v) == before.row(v));  // untouched
          }
        }
        // Operational and interface nodes are always this frame's.
        for (int v : c.partition.operational) CHECK((phys.u.row(v) - full.u.row(v)).norm() <= 1e-9 * full.u.norm());
        for (int v : c.partition.interface) CHECK((phys.u.row(v) - full.u.row(v)).norm() <= 1e-9 * full.u.norm());
      }
    }
    CHECK(asked_total > 50);
  }

  TEST_CASE("automatic storage follows the memory budget and the cost of a full-surface update") {
    std::mt19937 rng(8);
    int product = 0;
    for (int trial = 0; trial < 20; ++trial) {
      const HybridCase c = test::random_case(rng, trial % 4);
      PrecomputeOptions po;
      po.memory_budget_bytes = 1;
      CHECK(precompute(c.mesh, c.material, c.partition, po).storage == Storage::factor);
      po.memory_budget_bytes = 1e9;
      const Model m = precompute(c.mesh, c.material, c.partition, po);
      CHECK(m.storage != Storage::dense);  // the paper's K*^-1 is never needed
      const double product_read = 8.0 * 9 * m.ns() * m.ni(), solve_read = 24.0 * m.memory.factor_nonzeros;
      CHECK(m.storage == (product_read > 0 && product_read <= solve_read ? Storage::product : Storage::factor));
      CHECK(m.memory.dense_bytes >= 8.0 * 9 * m.ns() * m.ns());
      CHECK(m.memory.product_bytes >= product_read);
      CHECK(describe(m).find(cat("storage ", to_string(m.storage))) != std::string::npos);
      product += m.storage == Storage::product;
    }
    CHECK(product > 0);
  }

  TEST_CASE("running sums do not drift over 1000 frames of changing loads") {
    std::mt19937 rng(1000);
    const HybridCase c = test::random_case(rng, 1, 3);
    PrecomputeOptions po;
    po.storage = Storage::dense;
    const Model model = precompute(c.mesh, c.material, c.partition, po);
    REQUIRE(model.storage == Storage::dense);
    REQUIRE(model.ns() > 0);
    State state = make_state(model, tight_cg());
    std::vector<Load> loads;
    for (int frame = 0; frame < 1000; ++frame) {
      // Drag: a few nodes keep their load and change it, others come and go.
      if (loads.size() > 4 || (frame % 7 == 0 && !loads.empty())) loads.erase(loads.begin());
      for (auto& l : loads) l.force *= 1.01;
      const auto fresh = test::random_loads(c.partition, rng, 1);
      loads.insert(loads.end(), fresh.begin(), fresh.end());
      update(model, state, loads);
    }
    const Eigen::VectorXd Ps = model.Ps0 + state.Ps_interact;
    const Eigen::VectorXd As_fresh = model.Kstar_inv * Ps;
    CHECK((state.As_loads - As_fresh).norm() <= 1e-12 * As_fresh.norm());
    if (model.ni() > 0) {
      const Eigen::VectorXd Pp_fresh = model.KI2_K22inv_s * Ps;
      CHECK((state.P_prime - Pp_fresh).norm() <= 1e-12 * Pp_fresh.norm());
    }
    // Ps_interact holds exactly this frame's surface loads.
    Eigen::MatrixX3d surface_loads = Eigen::MatrixX3d::Zero(c.mesh.num_nodes(), 3);
    for (const auto& l : loads)
      if (c.partition.node_set[size_t(l.node)] == NodeSet::surface) surface_loads.row(l.node) += l.force.transpose();
    CHECK((state.Ps_interact - gather_nodes(surface_loads, c.partition.surface)).norm() == 0);
    const Eigen::MatrixX3d ref =
        fem::solve_whole_mesh(c.mesh, c.material, c.fixed_mask, test::load_field(c.mesh.num_nodes(), loads));
    CHECK(test::relative_error(state.u, ref, visible_nodes(c.partition)) <= 1e-8);
  }

  TEST_CASE("degenerate partitions: pure condensed model and plain FEM") {
    std::mt19937 rng(3);
    for (int kind : {4, 5}) {
      const HybridCase c = test::random_case(rng, kind);
      const Model model = precompute(c.mesh, c.material, c.partition, {});
      if (kind == 4) {
        CHECK(model.operational->size() == 0);
        CHECK(c.partition.operational.empty());
        CHECK(c.partition.interface.empty());
      } else {
        CHECK(model.ns() == 0);
        CHECK(model.nonop_nodes.empty());
        CHECK(model.operational->num_interface == 0);
      }
      State state = make_state(model, tight_cg());
      const auto loads = test::random_loads(c.partition, rng, 4);
      update(model, state, loads);
      const Eigen::MatrixX3d ref =
          fem::solve_whole_mesh(c.mesh, c.material, c.fixed_mask, test::load_field(c.mesh.num_nodes(), loads));
      CHECK(test::relative_error(state.u, ref, visible_nodes(c.partition)) <= 1e-8);
    }
  }

  TEST_CASE("a rebuilt operational system (a crack with appended nodes) still matches the monolithic solve") {
    std::mt19937 rng(77);
    int cracked = 0;
    for (int trial = 0; trial < 20 && cracked < 5; ++trial) {
      const HybridCase c = test::random_case(rng, 1 + trial % 2);
      if (c.partition.operational.empty()) continue;
      const Model model = precompute(c.mesh, c.material, c.partition, {});
      const std::optional<mesh::TetMesh> crack = crack_one_node(c, rng);
      if (!crack) continue;
      const mesh::TetMesh& cut = *crack;
      ++cracked;
      State state = make_state(model, tight_cg());
      auto loads = test::random_loads(c.partition, rng, 3);
      update(model, state, loads);
      set_operational_system(state, rebuild_operational_system(model, cut, c.material, c.partition.operational_tets));
      loads.push_back({c.mesh.num_nodes(), Eigen::Vector3d(0.3, -0.2, 0.1)});
      update(model, state, loads);
      std::vector<char> fixed = c.fixed_mask;
      fixed.push_back(0);
      const Eigen::MatrixX3d ref = fem::solve_whole_mesh(cut, c.material, fixed, test::load_field(cut.num_nodes(), loads));
      std::vector<int> nodes = visible_nodes(c.partition);
      nodes.push_back(c.mesh.num_nodes());
      CHECK(test::relative_error(state.u, ref, nodes) <= 1e-8);
    }
    CHECK(cracked >= 3);
  }

  // DESIGN.md "Initial strain": the strains' forces reach interior
  // nonoperational nodes, which the precompute condenses into the constant
  // term; the operational tets' share follows the operational system through
  // a crack (its tets keep their strain).
  TEST_CASE("initial strains: hybrid == monolithic in every storage mode and backend, before and after a crack") {
    std::mt19937 rng(505);
    std::normal_distribution<double> g(0, 1);
    int checked = 0, interior_loaded = 0, cracked = 0;
    for (int trial = 0; trial < 24; ++trial) {
      HybridCase c = test::random_case(rng);
      for (int t = 0; t < c.mesh.num_tets(); ++t)
        if (rng() % 3)
          for (double& e : c.material[size_t(t)].initial_strain) e = 0.01 * g(rng);
      PrecomputeOptions po;
      po.storage = std::array{Storage::dense, Storage::product, Storage::factor}[size_t(trial % 3)];
      const Model model = precompute(c.mesh, c.material, c.partition, po);
      interior_loaded += model.Pi0.norm() > 0;
      State state = make_state(model, trial % 2 ? tight_cg() : std::make_unique<CholmodSolver>());
      INFO("trial ", trial, " kind ", c.partition_kind, " ", describe(c.partition.counts));
      for (int frame = 0; frame < 2; ++frame) {
        // Frame 0 has no interactive load: the initial strains alone move the body.
        const auto loads = frame == 0 ? std::vector<Load>{} : test::random_loads(c.partition, rng, 3);
        update(model, state, loads, with_interior(true));
        const Eigen::MatrixX3d ref =
            fem::solve_whole_mesh(c.mesh, c.material, c.fixed_mask, test::load_field(c.mesh.num_nodes(), loads));
        REQUIRE(ref.norm() > 0);
        CHECK(test::relative_error(state.u, ref, visible_nodes(c.partition)) <= 1e-8);
        CHECK(test::relative_error(state.u, ref, c.partition.interior) <= 1e-8);
        ++checked;
      }
      if (c.partition.operational.empty()) continue;
      const std::optional<mesh::TetMesh> crack = crack_one_node(c, rng);
      if (!crack) continue;
      const mesh::TetMesh& cut = *crack;
      set_operational_system(state, rebuild_operational_system(model, cut, c.material, c.partition.operational_tets));
      update(model, state, {}, with_interior(true));
      std::vector<char> fixed = c.fixed_mask;
      fixed.push_back(0);
      const Eigen::MatrixX3d ref = fem::solve_whole_mesh(cut, c.material, fixed, Eigen::MatrixX3d::Zero(cut.num_nodes(), 3));
      std::vector<int> nodes = visible_nodes(c.partition);
      nodes.push_back(c.mesh.num_nodes());
      CHECK(test::relative_error(state.u, ref, nodes) <= 1e-8);
      CHECK(test::relative_error(state.u, ref, c.partition.interior) <= 1e-8);
      ++cracked;
    }
    CHECK(checked == 48);
    CHECK(interior_loaded >= 8);  // the condensed interior loads are really exercised
    CHECK(cracked >= 4);
  }

  TEST_CASE("bad loads are refused with a message and leave the state unchanged") {
    std::mt19937 rng(9);
    HybridCase c;
    do c = test::random_case(rng, 0); while (c.partition.interior.empty() || c.partition.surface.empty());
    const Model model = precompute(c.mesh, c.material, c.partition, {});
    State state = make_state(model);
    const std::vector<Load> good = {{c.partition.surface[0], Eigen::Vector3d(0, 0, 1)}};
    update(model, state, good);
    const Eigen::MatrixX3d before = state.u;
    auto message = [&](std::vector<Load> loads) {
      loads.insert(loads.begin(), {c.partition.surface.back(), Eigen::Vector3d(1, 0, 0)});
      try {
        update(model, state, loads);
      } catch (const Error& e) {
        return std::string(e.what());
      }
      return std::string("no error");
    };
    const int inner = c.partition.interior[0];
    const std::string interior = message({{inner, Eigen::Vector3d(1, 0, 0)}});
    CHECK(interior.find("condensed away") != std::string::npos);
    CHECK(interior.find(std::to_string(inner)) != std::string::npos);
    CHECK(interior.find("operational") != std::string::npos);
    CHECK(message({{c.mesh.num_nodes() + 5, Eigen::Vector3d(1, 0, 0)}}).find("no such node") != std::string::npos);
    CHECK(message({{-1, Eigen::Vector3d(1, 0, 0)}}).find("no such node") != std::string::npos);
    CHECK(message({{c.partition.surface[0], Eigen::Vector3d(std::nan(""), 0, 0)}}).find("NaN") != std::string::npos);
    CHECK(message({{c.partition.fixed[0], Eigen::Vector3d(1, 0, 0)}}).find("fixed") != std::string::npos);
    CHECK(state.u == before);
    CHECK(state.loaded_surface.size() == 1);
    update(model, state, good);  // still consistent after the refusals
    CHECK((state.u - before).cwiseAbs().maxCoeff() <= 1e-12 * before.cwiseAbs().maxCoeff());
  }

  TEST_CASE("a second thread for the dense products changes no bit of a frame") {
    // The upper leg of the paper (its stage 5 block, 837 x 153, and its
    // 321-unknown operational inverse are split in halves): one state with
    // the helper thread, one without, the same 30 frames of loads on
    // operational, interface and surface nodes; u must be identical, and
    // equal to the monolithic solve.
    const mesh::TubeOptions o = mesh::upper_leg_preset();
    const mesh::TetMesh m = mesh::generate_tube(o);
    const std::vector<int> fixed = mesh::tube_hole_nodes(m, o);
    const Eigen::Vector3d c = o.base_center + Eigen::Vector3d(o.outer_radius, 0, 0.5 * o.length);
    const Partition p = make_partition(m, tets_in_sphere(m, c, 0.3 * o.outer_radius), fixed);
    REQUIRE(p.interface.size() > 20);
    const std::vector<fem::Material> mat(size_t(m.num_tets()), fem::Material{3e3, 0.45});
    const Model M = precompute(m, mat, p, {});
    REQUIRE(M.has_Kstar_inv_Pstar());
    StateOptions one, two;
    one.product_threads = 1;
    two.product_threads = 2;
    State a = make_state(M, std::make_unique<CholmodSolver>(), one);
    State b = make_state(M, std::make_unique<CholmodSolver>(), two);
    CHECK(!a.helper);
    REQUIRE(b.helper);
    std::vector<Load> loads;
    for (int f = 0; f < 30; ++f) {
      loads = {{p.surface[size_t(f) % p.surface.size()], Eigen::Vector3d(0.01, 0.002 * f, 0)},
               {p.interface[0], Eigen::Vector3d(0, 0, -0.005)}};
      if (f % 2) loads.push_back({p.operational[0], Eigen::Vector3d(0, 0.003, 0)});
      update(M, a, loads);
      update(M, b, loads);
      REQUIRE((a.u.array() == b.u.array()).all());
    }
    const auto* direct = dynamic_cast<const CholmodSolver*>(b.solver.get());
    REQUIRE(direct);
    CHECK(direct->uses_dense());
    CHECK(M.operational->size() >= 64);
    Eigen::MatrixX3d F = Eigen::MatrixX3d::Zero(m.num_nodes(), 3);
    for (const Load& l : loads) F.row(l.node) += l.force.transpose();
    std::vector<char> fixed_mask(size_t(m.num_nodes()), 0);
    for (int v : fixed) fixed_mask[size_t(v)] = 1;
    const Eigen::MatrixX3d mono = fem::solve_whole_mesh(m, mat, fixed_mask, F);
    double err = 0;
    for (int v : visible_nodes(p)) err = std::max(err, (b.u.row(v) - mono.row(v)).norm());
    CHECK(err <= 1e-8 * mono.rowwise().norm().maxCoeff());
  }
}
