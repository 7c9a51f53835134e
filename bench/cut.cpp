// softcut bench cut: cutting in the operational region against its size (the
// paper's Fig. 8 stage costs, collision excluded). For each region size a
// jittered Kuhn box is precomputed once (hybrid model), a straight blade is
// swept through the operational region in equal steps, and after each step
// the operational system is rebuilt and the frame solved, warm-started from
// the mapped field and, for comparison, cold-started from zero. The baseline,
// measured in the same run, is the whole cut mesh solved monolithically by
// CHOLMOD (what a frame after a cut costs without the hybrid split).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <memory>
#include <optional>

#include "bench/bench.hpp"
#include "app/options.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/threads.hpp"
#include "core/timer.hpp"
#include "cut/cutter.hpp"
#include "fem/assembly.hpp"
#include "fem/dof_map.hpp"
#include "fem/whole_mesh.hpp"
#include "gpu/compute_cg.hpp"
#include "gl/egl_context.hpp"
#include "gpu/operational_gpu_solver.hpp"
#include "hybrid/update.hpp"
#include "bench/box_problem.hpp"
#include "solve/cholesky.hpp"

namespace softcut::bench {

namespace {

using V = Eigen::Vector3d;

struct Stat {  // mean and max over the cut steps
  double sum = 0, max = 0;
  int n = 0;
  void add(double x) { sum += x, max = std::max(max, x), ++n; }
  double mean() const { return n ? sum / n : 0.0; }
};

struct SizeResult {
  int target = 0, cells = 0, tets = 0, nodes = 0;
  int op_tets = 0, op_nodes = 0, interface_nodes = 0, surface_nodes = 0;
  int tets_after = 0, nodes_after = 0, op_tets_after = 0;
  int steps = 0, steps_changed = 0, steps_snap_only = 0;  // steps that changed the mesh; of those, only snapped
  std::string storage;
  double precompute_ms = 0;
  int before_it = 0;
  double before_ms = 0;  // first frame on the uncut system, from zero
  Stat cut_ms, rebuild_ms, warm_it, warm_ms, cold_it, cold_ms;
  Stat selective_ms, operational_ms, nonoperational_ms;  // warm frame stages
  Stat default_ms;   // the frame with the default backend (CHOLMOD: kept factor + low-rank correction)
  Stat refactor_ms;  // the same backend refactoring after every cut (what it did before)
  Stat correction_rank;  // DOFs changed since the default backend's kept factor
  Stat gpu_ms, gpu_it;   // --gpu: the gpu backend's frame (warm start from the mapped field) and its CG iterations
  long default_factors = 0, default_background = 0, default_fallbacks = 0;  // factors the default backend made; of those, on the second thread
  double mono_assemble_ms = 0, mono_factor_ms = 0, mono_solve_ms = 0;
  double rel_err = 0;  // hybrid (warm CG and default backend, after the last cut) vs monolithic
};

// Box region touching the top face (z = 1), centred in x and y, whose
// centroid test selects about `target` tets; *side gets its edge length.
std::vector<char> region_with_tets(const mesh::TetMesh& m, int target, double* side) {
  auto box = [&](double s) {
    return hybrid::tets_in_box(m, V(0.5 - s / 2, 0.5 - s / 2, 1 - s), V(0.5 + s / 2, 0.5 + s / 2, 2));
  };
  double lo = 0, hi = 1;
  for (int it = 0; it < 40; ++it) {
    const double s = 0.5 * (lo + hi);
    const auto mask = box(s);
    (int(std::count(mask.begin(), mask.end(), 1)) < target ? lo : hi) = s;
  }
  *side = hi;
  return box(hi);
}

bool changed_mesh(const cut::CutRecord& r) {
  return !r.new_nodes.empty() || !r.changed_tets.empty() || r.nodes_snapped > 0 || r.faces_separated > 0;
}

SizeResult run_size(int cells, int target, int steps, gl::EglContext* context) {
  SizeResult r;
  r.target = target, r.cells = cells, r.steps = steps;
  BoxProblem box = box_problem({{cells, cells, cells}, Eigen::Vector3d::Ones(), 0.15, 2});  // z = 0 held
  mesh::TetMesh m = std::move(box.mesh);
  r.tets = m.num_tets(), r.nodes = m.num_nodes();
  double side = 0;
  const std::vector<char> op_mask = region_with_tets(m, target, &side);
  const hybrid::Partition part = hybrid::make_partition(m, op_mask, box.fixed);
  r.op_tets = part.counts.operational_tets;
  r.op_nodes = part.counts.operational_region_nodes;
  r.interface_nodes = part.counts.interface;
  r.surface_nodes = part.counts.surface;
  std::vector<fem::Material> mat = std::move(box.materials);

  Timer timer;
  const hybrid::Model model = hybrid::precompute(m, mat, part);
  r.precompute_ms = timer.ms();
  r.storage = hybrid::to_string(model.storage);

  // Standing load: the free top node of the region nearest (c + s/4, 0.5 + s/4),
  // off the cut plane, pulling it up and away from the cut.
  int load_node = -1;
  const V want(0.5 + side / 4, 0.5 + side / 4, 1);
  for (int v : part.operational)
    if (load_node < 0 || (m.node(v) - want).squaredNorm() < (m.node(load_node) - want).squaredNorm()) load_node = v;
  if (load_node < 0) fail("bench cut: the operational region of ", target, " tets has no free node");
  const std::vector<hybrid::Load> loads = {{load_node, V(0.1, 0.5, 0.3)}};

  hybrid::State warm = hybrid::make_state(model), cold = hybrid::make_state(model);
  // The default backend (`auto`): CHOLMOD on the operational system, its
  // factor kept through cuts by a low-rank correction; and the same backend
  // refactoring after every cut, for comparison.
  auto direct_solver = std::make_unique<hybrid::CholmodSolver>();
  const hybrid::CholmodSolver& direct_cholmod = *direct_solver;
  hybrid::State direct = hybrid::make_state(model, std::move(direct_solver));
  hybrid::State refactor = hybrid::make_state(model, std::make_unique<hybrid::CholmodSolver>(true, false));
  hybrid::update(model, direct, loads);
  hybrid::update(model, refactor, loads);
  std::optional<hybrid::State> on_gpu;  // --gpu: the gpu backend as a run builds it (CG on the device)
  if (context) {
    on_gpu.emplace(hybrid::make_state(model, std::make_unique<gpu::OperationalGpuSolver>(
                                                 *context, gpu::compile_cg_kernels(*context, false),
                                                 gpu::ComputeCgOptions{})));
    hybrid::update(model, *on_gpu, loads);
  }
  {
    const hybrid::FrameReport& f = hybrid::update(model, warm, loads);
    r.before_it = f.solve.iterations, r.before_ms = f.total_ms;
  }

  // Cut state as sim/cutting.cpp sets it up: cuttable = operational tets,
  // locked = interface nodes (make_cut_state adds nodes of nonoperational tets).
  std::vector<char> op_tet = part.operational_tet;
  std::vector<char> node_fixed(size_t(m.num_nodes()), 0);
  for (int v : part.fixed) node_fixed[size_t(v)] = 1;
  std::vector<char> locked(size_t(m.num_nodes()), 0);
  for (int v : part.interface) locked[size_t(v)] = 1;
  cut::CutState cs = cut::make_cut_state(m, op_tet, std::move(locked));

  // Vertical blade edge from just above the top to 0.6 of the region's depth,
  // moved across the region in x on a plane slanted against the lattice.
  const double x0 = 0.5 - side / 2 - 0.05, x1 = 0.5 + side / 2 + 0.05;
  auto blade_at = [&](double x, V& a, V& b) {
    const double y = 0.513 + 0.1 * (x - 0.5);
    a = V(x, y, 1.05), b = V(x, y, 1 - 0.6 * side);
  };
  for (int k = 0; k < steps; ++k) {
    V a0, b0, a1, b1;
    blade_at(x0 + (x1 - x0) * k / steps, a0, b0);
    blade_at(x0 + (x1 - x0) * (k + 1) / steps, a1, b1);
    const cut::SweptSurface sweep = cut::sweep_segment(a0, b0, a1, b1);
    timer.reset();
    const cut::CutRecord rec = cut::cut_step(m, cs, sweep);
    r.cut_ms.add(timer.ms());
    if (!changed_mesh(rec)) continue;
    ++r.steps_changed;

    // Rebuild as sim/cutting.cpp update_after_cut + HybridSolver::apply_cut.
    timer.reset();
    const int nt = m.num_tets(), nn = m.num_nodes();
    std::vector<fem::Material> mat2(static_cast<size_t>(nt));
    std::vector<char> op2(static_cast<size_t>(nt));
    for (int t = 0; t < nt; ++t) {
      mat2[size_t(t)] = mat[size_t(rec.tet_parent[size_t(t)])];
      op2[size_t(t)] = op_tet[size_t(rec.tet_parent[size_t(t)])];
    }
    mat = std::move(mat2), op_tet = std::move(op2);
    node_fixed.resize(size_t(nn), 0);
    for (const cut::NewNode& v : rec.new_nodes) {
      bool fx = true;
      for (int k2 = 0; k2 < 2; ++k2)
        if (v.parent[size_t(k2)] >= 0 && v.weight[size_t(k2)] != 0) fx &= node_fixed[size_t(v.parent[size_t(k2)])] != 0;
      node_fixed[size_t(v.id)] = fx;
    }
    std::vector<int> op;
    for (int t = 0; t < nt; ++t)
      if (op_tet[size_t(t)]) op.push_back(t);
    const auto sys = hybrid::rebuild_operational_system(model, m, mat, op, node_fixed, warm.operational.get());
    // A state onto the cut system: its field carried onto the new nodes (the
    // warm start) or zeroed, its forces grown to the new node count.
    auto onto_cut = [&](hybrid::State& st, bool carry) {
      hybrid::set_operational_system(st, sys);
      if (!carry) st.u.setZero();
      else if (st.u.rows() == rec.nodes_before) st.u = cut::map_node_field(rec, st.u);
      const Eigen::Index had = st.forces.rows();
      if (had < nn) {
        st.forces.conservativeResize(nn, 3);
        st.forces.bottomRows(nn - had).setZero();
      }
    };
    onto_cut(warm, true);
    r.rebuild_ms.add(timer.ms());

    const hybrid::FrameReport& f = hybrid::update(model, warm, loads);
    // A step that only snapped nodes onto the cut leaves the system as it
    // was (0 CG iterations): kept out of the frame statistics.
    if (rec.new_nodes.empty() && rec.changed_tets.empty() && rec.faces_separated == 0) {
      ++r.steps_snap_only;
      continue;
    }
    r.warm_it.add(f.solve.iterations), r.warm_ms.add(f.total_ms);
    r.selective_ms.add(f.selective_ms), r.operational_ms.add(f.operational_ms);
    r.nonoperational_ms.add(f.nonoperational_ms);

    hybrid::set_operational_system(cold, sys);
    cold.u.setZero();  // the CG start is gathered from u (new system generation)
    const hybrid::FrameReport& c = hybrid::update(model, cold, loads);
    r.cold_it.add(c.solve.iterations), r.cold_ms.add(c.total_ms);

    onto_cut(direct, false);
    onto_cut(refactor, false);
    const hybrid::FrameReport& d = hybrid::update(model, direct, loads);
    r.default_ms.add(d.total_ms);
    r.correction_rank.add(d.solve.correction_rank);
    r.refactor_ms.add(hybrid::update(model, refactor, loads).total_ms);
    if (on_gpu) {
      onto_cut(*on_gpu, true);
      const hybrid::FrameReport& fg = hybrid::update(model, *on_gpu, loads);
      r.gpu_ms.add(fg.total_ms), r.gpu_it.add(fg.solve.iterations);
    }
  }
  r.default_factors = direct_cholmod.refactors();
  r.default_background = direct_cholmod.adopted();
  r.default_fallbacks = direct_cholmod.fallbacks();
  // A refactor still running on the second thread holds OpenBLAS on one
  // thread (and a core): it ends with its solver, before the baselines.
  direct.solver.reset();
  if (r.warm_it.n == 0) fail("bench cut: the blade changed no tet of the ", target, "-tet region");
  r.tets_after = m.num_tets(), r.nodes_after = m.num_nodes();
  r.op_tets_after = int(std::count(op_tet.begin(), op_tet.end(), 1));

  // Baseline: the whole cut mesh, assembled, factored and solved by CHOLMOD.
  Eigen::MatrixX3d f = Eigen::MatrixX3d::Zero(m.num_nodes(), 3);
  for (const auto& l : loads) f.row(l.node) += l.force.transpose();
  // Minimum of 3 runs: single runs are noisy on a loaded machine.
  Eigen::MatrixX3d u_mono;
  r.mono_assemble_ms = r.mono_factor_ms = r.mono_solve_ms = INFINITY;
  for (int rep = 0; rep < 3; ++rep) {
    const fem::WholeMeshSolver mono(m, mat, node_fixed, "monolithic stiffness of the cut mesh");
    r.mono_assemble_ms = std::min(r.mono_assemble_ms, mono.system().assemble_ms());
    r.mono_factor_ms = std::min(r.mono_factor_ms, mono.factor_ms());
    const Eigen::VectorXd rhs = mono.system().load(f);
    timer.reset();
    solve::SolveWorkspace ws;
    Eigen::VectorXd x;
    mono.factor().solve_into(rhs, x, ws);
    u_mono = mono.system().field(x);
    r.mono_solve_ms = std::min(r.mono_solve_ms, timer.ms());
  }

  // Invariant: hybrid == monolithic on every node the hybrid frame solves
  // (interior nonoperational rows are not recovered per frame).
  double err = 0;
  for (int v = 0; v < m.num_nodes(); ++v)
    if (v >= model.num_nodes || part.node_set[size_t(v)] != hybrid::NodeSet::interior)
      err = std::max({err, (warm.u.row(v) - u_mono.row(v)).norm(), (direct.u.row(v) - u_mono.row(v)).norm(),
                      (refactor.u.row(v) - u_mono.row(v)).norm(),
                      on_gpu ? (on_gpu->u.row(v) - u_mono.row(v)).norm() : 0.0});
  r.rel_err = err / std::max(1e-300, u_mono.rowwise().norm().maxCoeff());
  if (!(r.rel_err <= 1e-8))
    fail("bench cut: the hybrid frame after the last cut differs from the monolithic solve by ", r.rel_err,
         " (relative, > 1e-8) for the ", target, "-tet region");
  return r;
}

Json json_of(const SizeResult& r) {
  auto st = [](const Stat& s) { return Json{{"mean", field(s.mean())}, {"max", field(s.max)}}; };
  Json j = {{"target_tets", r.target}, {"cells", r.cells}, {"tets", r.tets}, {"nodes", r.nodes},
          {"operational_tets", r.op_tets}, {"operational_nodes", r.op_nodes}, {"interface_nodes", r.interface_nodes},
          {"surface_nodes", r.surface_nodes}, {"storage", r.storage}, {"precompute_ms", field(r.precompute_ms)},
          {"steps", r.steps}, {"steps_changed", r.steps_changed}, {"steps_snap_only", r.steps_snap_only},
          {"tets_after", r.tets_after}, {"nodes_after", r.nodes_after}, {"operational_tets_after", r.op_tets_after},
          {"before", {{"cg_iterations", field(r.before_it)}, {"frame_ms", field(r.before_ms)}}},
          {"cut_ms", st(r.cut_ms)}, {"rebuild_ms", st(r.rebuild_ms)},
          {"warm",
           {{"cg_iterations", st(r.warm_it)}, {"frame_ms", st(r.warm_ms)}, {"selective_ms", st(r.selective_ms)},
            {"operational_ms", st(r.operational_ms)}, {"nonoperational_ms", st(r.nonoperational_ms)}}},
          {"cold", {{"cg_iterations", st(r.cold_it)}, {"frame_ms", st(r.cold_ms)}}},
          {"default_backend",
           {{"backend", "direct"}, {"frame_ms", st(r.default_ms)}, {"correction_rank", st(r.correction_rank)},
            {"factors", r.default_factors}, {"factors_on_second_thread", r.default_background},
            {"corrected_solves_refactored", r.default_fallbacks}}},
          {"refactor_each_cut", {{"frame_ms", st(r.refactor_ms)}}},
          {"monolithic", {{"assemble_ms", field(r.mono_assemble_ms)}, {"factor_ms", field(r.mono_factor_ms)},
                          {"solve_ms", field(r.mono_solve_ms)}}},
          {"relative_error", field(r.rel_err)}};
  if (r.gpu_ms.n) j["gpu_backend"] = {{"frame_ms", st(r.gpu_ms)}, {"cg_iterations", st(r.gpu_it)}};
  return j;
}

}  // namespace

int bench_cut(const Args& args) {
  app::Options o("softcut bench cut", "Sweeps a blade through operational regions of growing size in a jittered "
                 "Kuhn box (15^3 cells, 20250 tets; --quick: 8^3 cells, two small regions) and times cut, rebuild "
                 "and the frame after each step against a monolithic CHOLMOD solve of the cut mesh.");
  bool quick = false;
  std::string json_path;
  o.app().add_flag("--quick", quick, "the small box and two regions");
  bool use_gpu = false;
  o.app().add_flag("--gpu", use_gpu, "also time the frame after each cut with the gpu backend (compute-shader CG, "
                   "warm-started from the mapped field) on the EGL device");
  o.app().add_option("--json", json_path, "also write the results as JSON")->type_name("FILE");
  if (!o.parse(args)) return 0;
  std::optional<gl::EglContext> context;
  if (use_gpu) context.emplace();
  const int cells = quick ? 8 : 15, steps = 10;
  const std::vector<int> targets = quick ? std::vector<int>{300, 800} : std::vector<int>{500, 1000, 2000, 5000, 8000};
  std::vector<SizeResult> rows;
  for (int t : targets) rows.push_back(run_size(cells, t, steps, context ? &*context : nullptr));

  const SizeResult& r0 = rows.front();
  std::printf("Box %d^3 cells (%d tets, %d nodes), E = 3 kPa, nu = 0.45, bottom face fixed, one standing load;\n"
              "%d blade steps across the operational region. Times in ms per frame: cut over all steps,\n"
              "rebuild over steps that changed the mesh, frames (mean / max) over steps that split or\n"
              "separated tets (a step that only snaps nodes onto the cut leaves the system unchanged).\n"
              "Collision detection is not part of this benchmark. warm: CG from the mapped field; cold: the\n"
              "same frame from zero. Monolithic: the cut mesh assembled + CHOLMOD factor + solve (minimum of\n"
              "3 runs); ratio = monolithic / (rebuild + warm frame), the cut itself being common to both.\n"
              "default: the frame with the default backend (CHOLMOD on the operational system; after a cut its\n"
              "kept factor solves the cut system through a low-rank correction of rank k, refactored on a second\n"
              "thread once the corrections have cost most of a factorization); default ratio = monolithic /\n"
              "(rebuild + default frame). refactor: the same backend refactoring after every cut.\n\n",
              cells, r0.tets, r0.nodes, steps);
  std::printf("| op tets | op nodes | I nodes | storage | steps split / snap only / total | cut ms | rebuild ms | selective ms | "
              "operational ms | nonop ms | before: CG it / ms | warm: CG it | warm frame ms | cold: CG it | "
              "cold frame ms | mono assemble + factor + solve ms | ratio | default frame ms | k mean / max | factors (2nd thread) | default ratio | refactor frame ms | refactor ratio | rel. err |\n"
              "|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const SizeResult& r : rows) {
    const double mono = r.mono_assemble_ms + r.mono_factor_ms + r.mono_solve_ms;
    std::printf("| %d | %d | %d | %s | %d / %d / %d | %.2f / %.2f | %.2f / %.2f | %.2f | %.2f | %.2f | %d / %.1f | "
                "%.1f / %.0f | %.1f / %.1f | %.1f / %.0f | %.1f / %.1f | %.0f + %.0f + %.1f | %.2f | %.2f / %.2f | %.0f / %.0f | "
                "%ld (%ld) | %.2f | %.2f / %.2f | %.2f | %.1e |\n",
                r.op_tets, r.op_nodes, r.interface_nodes, r.storage.c_str(), r.steps_changed - r.steps_snap_only, r.steps_snap_only, r.steps,
                r.cut_ms.mean(), r.cut_ms.max, r.rebuild_ms.mean(), r.rebuild_ms.max, r.selective_ms.mean(),
                r.operational_ms.mean(), r.nonoperational_ms.mean(), r.before_it, r.before_ms, r.warm_it.mean(),
                r.warm_it.max, r.warm_ms.mean(), r.warm_ms.max, r.cold_it.mean(), r.cold_it.max, r.cold_ms.mean(),
                r.cold_ms.max, r.mono_assemble_ms, r.mono_factor_ms, r.mono_solve_ms,
                mono / (r.rebuild_ms.mean() + r.warm_ms.mean()), r.default_ms.mean(), r.default_ms.max,
                r.correction_rank.mean(), r.correction_rank.max, r.default_factors, r.default_background,
                mono / (r.rebuild_ms.mean() + r.default_ms.mean()), r.refactor_ms.mean(), r.refactor_ms.max,
                mono / (r.rebuild_ms.mean() + r.refactor_ms.mean()), r.rel_err);
  }
  if (context) {
    std::printf("\ngpu backend on %s: the frame after each cut (mean / max ms), CG iterations (mean / max), "
                "gpu ratio = monolithic / (rebuild + gpu frame), against the default ratio\n\n"
                "| op tets | gpu frame ms | gpu CG it | gpu ratio | default frame ms | default ratio |\n"
                "|---:|---:|---:|---:|---:|---:|\n",
                context->info().summary().c_str());
    for (const SizeResult& r : rows) {
      const double mono = r.mono_assemble_ms + r.mono_factor_ms + r.mono_solve_ms;
      std::printf("| %d | %.2f / %.2f | %.0f / %.0f | %.2f | %.2f / %.2f | %.2f |\n", r.op_tets, r.gpu_ms.mean(),
                  r.gpu_ms.max, r.gpu_it.mean(), r.gpu_it.max, mono / (r.rebuild_ms.mean() + r.gpu_ms.mean()),
                  r.default_ms.mean(), r.default_ms.max, mono / (r.rebuild_ms.mean() + r.default_ms.mean()));
    }
  }
  if (!json_path.empty()) {
    Json json = {{"benchmark", "cut"}, {"quick", quick}, {"threads", thread_policy().threads},
                 {"blas_threads", thread_policy().blas_threads}, {"sizes", Json::array()}};
    if (context) json["gpu_device"] = context->info().summary();
    for (const SizeResult& r : rows) json["sizes"].push_back(json_of(r));
    write_file_atomic(json_path, json_text(json));
  }
  return 0;
}

}  // namespace softcut::bench
