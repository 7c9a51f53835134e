#include "backend/hybrid_solver.hpp"

#include <algorithm>
#include <span>

#include "core/timer.hpp"
#include "fem/dof_map.hpp"
#include "gpu/dense_product.hpp"
#include "gl/egl_context.hpp"
#include "gpu/operational_gpu_solver.hpp"
#include "hybrid/loads.hpp"
#include "hybrid/precompute.hpp"
#include "hybrid/update.hpp"
#include "solve/cholesky.hpp"

namespace softcut::backend {

namespace {

struct HybridRunState final : SolverRunState {
  hybrid::State state;  // its solver: CHOLMOD, CG, or the device CG with this run's buffers
  std::vector<hybrid::Load> loads;  // scratch
  std::unique_ptr<hybrid::State> unit;  // scratch state for unit_responses(), created on first use
};

// Wu & Heng's hybrid condensed model: precompute once, update per frame.
class HybridSolver final : public Solver {
 public:
  HybridSolver(const mesh::TetMesh& m, const std::vector<fem::Material>& tet_material, const hybrid::Partition& p,
               const SolverSpec& spec, bool need_interior, BackendChoice choice, gl::EglContext* context,
               const StopFlags& stop)
      : spec_(spec), need_interior_(need_interior), choice_(std::move(choice)) {
    hybrid::PrecomputeOptions opt;
    opt.storage = spec.mode;
    opt.max_bytes = spec.max_bytes;
    opt.stop = stop;
    model_ = hybrid::precompute_cached(m, tet_material, p, opt, {spec.cache_dir}, &cache_);
    if (choice_.backend == Backend::gpu) {
      // The kernels compile once, here, so a context without what they need
      // fails at compile time; each run gets its own device buffers.
      Timer tg;
      kernels_ = gpu::compile_cg_kernels(*context, spec.gpu_fp64);
      gpu_ms_ = tg.ms();
    }
    // Stage 5's dense product on the device when the choice allows it and the
    // block is large enough for the device to pay off (bandwidth-bound;
    // double precision).
    context_ = context;
    device_product_ = choice_.device_product && context && model_.has_Kstar_inv_Pstar() &&
                      double(model_.Kstar_inv_Pstar.size()) >= choice_.device_product_min_entries;
    choice_.device_product = device_product_;  // from "may" to "does"
    if (device_product_ && choice_.backend != Backend::gpu) choice_.reason += "; (K*^-1 P*) AI on the GPU";
    const hybrid::PrecomputeTimings& t = model_.timings;
    timings_ = {{"assemble", t.assemble_ms},           {"factor", t.factor_ms},
                {"K_prime", t.K_prime_ms},             {"KI2_K22inv", t.KI2_K22inv_ms},
                {"Kstar_inv", t.Kstar_inv_ms},         {"Kstar_inv_Pstar", t.Kstar_inv_Pstar_ms},
                {"Kstar_inv_Ps0", t.Kstar_inv_Ps0_ms}, {"operational_system", t.operational_ms},
                {"hybrid_total", t.total_ms}};
    if (kernels_) timings_.emplace_back("gpu_kernels", gpu_ms_);
  }

  std::string name() const override {
    return cat("hybrid (", hybrid::to_string(model_.storage), " storage, operational ", backend_name(), ")");
  }
  bool interior_valid() const override { return need_interior_; }
  std::vector<std::pair<std::string, double>> precompute_ms() const override { return timings_; }
  const BackendChoice& backend() const override { return choice_; }
  const hybrid::CacheReport* precompute_cache() const override { return cache_.enabled ? &cache_ : nullptr; }
  std::optional<hybrid::ColumnStats> column_stats(const SolverRun& warm) const override {
    const auto* rs = dynamic_cast<const HybridRunState*>(warm.backend.get());
    if (!rs || !rs->state.columns) return std::nullopt;
    return rs->state.columns->stats();
  }
  void prefetch(const std::vector<int>& nodes, SolverRun& warm) const override {
    hybrid::prefetch_columns(model_, run_state(warm).state, nodes);
  }

  void start_run(SolverRun& warm, const CutBody* cut) const override {
    auto rs = std::make_unique<HybridRunState>();
    rs->state = hybrid::make_state(model_, make_operational_solver());
    if (device_product_)
      rs->state.nonoperational_product = std::make_shared<gpu::DeviceDenseProduct>(*context_, model_.Kstar_inv_Pstar);
    if (cut) hybrid::set_operational_system(rs->state, cut_system(*cut, model_.operational.get()));
    warm.backend = std::move(rs);
  }

  long system_generation(const SolverRun& warm) const override {
    const auto* rs = dynamic_cast<const HybridRunState*>(warm.backend.get());
    return rs ? rs->state.operational->generation : model_.operational->generation;
  }

  void apply_cut(const CutBody& cm, SolverRun& warm) const override {
    HybridRunState& rs = run_state(warm);
    hybrid::set_operational_system(rs.state, cut_system(cm, rs.state.operational.get()));
    // Warm start and running state onto the new nodes (the next update
    // gathers the CG start from u because the system generation changed).
    if (cm.carry && rs.state.u.rows() == cm.nodes_before) rs.state.u = cm.carry(rs.state.u);
    const Eigen::Index old = rs.state.forces.rows(), nn = cm.mesh.num_nodes();
    if (old < nn) {
      rs.state.forces.conservativeResize(nn, 3);
      rs.state.forces.bottomRows(nn - old).setZero();
    }
  }

  void unit_responses(const std::vector<int>& nodes, SolverRun& warm, Eigen::MatrixXd& out) const override {
    HybridRunState& rs = run_state(warm);
    const hybrid::OperationalSystem& op = *rs.state.operational;
    if (std::all_of(nodes.begin(), nodes.end(), [&](int n) {
          return n >= 0 && size_t(n) < op.node_index.size() && op.node_index[size_t(n)] >= 0;
        })) {
      operational_unit_responses(nodes, rs, out);
      return;
    }
    // A nonoperational surface node among them: each column through a whole update.
    if (!rs.unit) {
      // The run's solver (and its helper thread) does stage 4; the scratch
      // state's stage 5 stays on this thread: one helper thread per run.
      hybrid::StateOptions one;
      one.product_threads = 1;
      rs.unit = std::make_unique<hybrid::State>(hybrid::make_state(model_, nullptr, one));
    }
    hybrid::State& scratch = *rs.unit;
    if (scratch.operational != rs.state.operational) hybrid::set_operational_system(scratch, rs.state.operational);
    hybrid::UpdateOptions opt;
    opt.recover_interior = need_interior_;
    // Responses are measured against the zero-load state, so the model's
    // initial loads (the initial strains' forces) cancel.
    std::vector<hybrid::Load> none;
    hybrid::update(model_, scratch, none, *rs.state.solver, opt);
    const Eigen::VectorXd u_zero = fem::flatten(scratch.u);
    out.resize(u_zero.size(), 3 * Eigen::Index(nodes.size()));
    for (size_t j = 0; j < nodes.size(); ++j)
      for (int a = 0; a < 3; ++a) {
        const hybrid::NodeSet set = nodes[j] < model_.num_nodes ? model_.partition.node_set[size_t(nodes[j])]
                                                                : hybrid::NodeSet::operational;
        if (set == hybrid::NodeSet::fixed || set == hybrid::NodeSet::interior)
          fail("unit_responses: node ", nodes[j], " is ", set == hybrid::NodeSet::fixed ? "fixed" : "interior");
        hybrid::Load unit{nodes[j], Eigen::Vector3d::Unit(a)};
        scratch.x_operational.setZero();  // each column from zero: no dependence on column order
        hybrid::update(model_, scratch, std::span<const hybrid::Load>(&unit, 1), *rs.state.solver, opt);
        out.col(Eigen::Index(3 * j + a)) = fem::flatten(scratch.u) - u_zero;
      }
  }

  // Unit responses of operational and interface nodes (a grasp in the
  // operational region, the usual case) in one batch, the same numbers as
  // through update() up to rounding: x = A^-1 e per column (the operational
  // system; the initial strains and P' cancel in a response), then the
  // nonoperational rows of all columns at once from AI = the interface part
  // of x: the surface by (K*^-1 P*) AI, and K22^-1 (-K2I AI) for the interior
  // (and the surface in factor storage) as one multi-column solve. At 93k
  // tets this takes a 37-node grasp's compliance from 3 s (111 whole updates,
  // each with a K22 solve) to a fraction of it.
  void operational_unit_responses(const std::vector<int>& nodes, HybridRunState& rs, Eigen::MatrixXd& out) const {
    const hybrid::OperationalSystem& op = *rs.state.operational;
    const Eigen::Index m3 = 3 * Eigen::Index(nodes.size()), ni3 = 3 * Eigen::Index(op.num_interface);
    const Eigen::Index nn = std::max<Eigen::Index>(model_.num_nodes, Eigen::Index(op.node_index.size()));
    out.setZero(3 * nn, m3);
    Eigen::MatrixXd AI(ni3, m3);
    Eigen::VectorXd b = Eigen::VectorXd::Zero(op.size()), x;
    for (size_t j = 0; j < nodes.size(); ++j)
      for (int a = 0; a < 3; ++a) {
        const Eigen::Index c = 3 * Eigen::Index(j) + a, dof = 3 * Eigen::Index(op.node_index[size_t(nodes[j])]) + a;
        b[dof] = 1;
        x.setZero(op.size());  // each column from zero: no dependence on column order
        check_solve_residual(rs.state.solver->solve(op, b, x).relative_residual, "operational solve");
        b[dof] = 0;
        for (size_t k = 0; k < op.nodes.size(); ++k)
          out.block<3, 1>(3 * Eigen::Index(op.nodes[k]), c) = x.segment<3>(3 * Eigen::Index(k));
        AI.col(c) = x.tail(ni3);
      }
    if (model_.nonop_nodes.empty() || ni3 == 0) return;
    const auto& surface = model_.partition.surface;
    const bool product = model_.has_Kstar_inv_Pstar();
    if (product) {
      const Eigen::MatrixXd As = model_.Kstar_inv_Pstar * AI;
      for (size_t p = 0; p < surface.size(); ++p)
        out.middleRows<3>(3 * Eigen::Index(surface[p])) = As.middleRows<3>(3 * Eigen::Index(p));
    }
    if (product && !need_interior_) return;
    const Eigen::MatrixXd W = model_.K22.solve(Eigen::MatrixXd(-(model_.K2I * AI)), *rs.state.ws);
    if (!product)
      for (size_t p = 0; p < surface.size(); ++p)
        out.middleRows<3>(3 * Eigen::Index(surface[p])) = W.middleRows<3>(3 * Eigen::Index(p));
    if (need_interior_) {
      const auto& interior = model_.partition.interior;
      const Eigen::Index off = 3 * Eigen::Index(surface.size());
      for (size_t k = 0; k < interior.size(); ++k)
        out.middleRows<3>(3 * Eigen::Index(interior[k])) = W.middleRows<3>(off + 3 * Eigen::Index(k));
    }
  }

  bool nonlinear() const override { return model_.operational->nonlinear_law; }

  void solve(const Eigen::MatrixX3d& forces, Eigen::MatrixX3d& u, SolverRun& warm, SolveStats& stats,
             const FrameInput& in) const override {
    HybridRunState* rs = &run_state(warm);
    rs->loads.clear();
    for (int n = 0; n < forces.rows(); ++n)
      if (forces.row(n).squaredNorm() > 0 &&
          (n >= model_.num_nodes || model_.partition.node_set[size_t(n)] != hybrid::NodeSet::fixed))
        rs->loads.push_back({n, forces.row(n).transpose()});
    hybrid::UpdateOptions opt;
    opt.recover_interior = need_interior_;
    const bool moving = in.prescribed && in.prescribed->size() > 0 && in.prescribed->squaredNorm() > 0;
    hybrid::NonlinearFrame frame;
    if (moving || in.springs || nonlinear()) {
      if (moving) frame.prescribed = *in.prescribed;
      frame.springs = in.springs;
      frame.newton = spec_.newton;
      opt.nonlinear = &frame;
    }
    const hybrid::FrameReport& rep = hybrid::update(model_, rs->state, rs->loads, *rs->state.solver, opt);
    check_solve_residual(rep.solve.relative_residual, "operational solve");
    u = rs->state.u;
    if (moving)
      for (int n : model_.partition.fixed) u.row(n) = in.prescribed->row(n);
    stats = SolveStats{};
    stats.cg_iterations = rep.solve.iterations;
    stats.relative_residual = rep.solve.relative_residual;
    stats.loads_ms = rep.loads_ms;
    stats.operational_ms = rep.operational_ms;
    stats.nonoperational_ms = rep.selective_ms + rep.nonoperational_ms;
    stats.newton = rep.newton;
    if (rep.newton) {
      stats.newton_iterations = rep.nonlinear.newton.iterations;
      stats.projected_steps = rep.nonlinear.newton.projected_steps;
      stats.at_floor = rep.nonlinear.newton.at_floor;
      stats.max_rotation = rep.nonlinear.max_rotation;
      stats.max_strain = rep.nonlinear.max_strain;
      stats.inverted = rep.nonlinear.inverted;
    }
  }

 private:
  std::string backend_name() const {
    const char* product = device_product_ ? "; (K*^-1 P*) AI on the device" : "";
    if (kernels_) return cat("gpu cg, ", spec_.gpu_fp64 ? "fp64" : "fp32 + fp64 refinement", product);
    return cat(choice_.backend == Backend::direct ? "cholmod" : "cg", product);
  }

  HybridRunState& run_state(SolverRun& warm) const {
    if (!dynamic_cast<HybridRunState*>(warm.backend.get())) start_run(warm, nullptr);
    return static_cast<HybridRunState&>(*warm.backend);
  }

  // The system of the cut mesh; `before` is the one it replaces (its rows
  // that the cut left alone are reused).
  std::shared_ptr<const hybrid::OperationalSystem> cut_system(const CutBody& cm,
                                                              const hybrid::OperationalSystem* before) const {
    std::vector<int> op;
    for (int t = 0; t < cm.mesh.num_tets(); ++t)
      if (cm.operational_tet[size_t(t)]) op.push_back(t);
    return hybrid::rebuild_operational_system(model_, cm.mesh, cm.tet_material, op, cm.node_fixed, before);
  }

  // One per run: CPU solvers keep a factor or warm start, the device solver
  // this run's buffers (it re-uploads only when the system's generation changes).
  std::unique_ptr<hybrid::OperationalSolver> make_operational_solver() const {
    if (kernels_) {
      gpu::ComputeCgOptions g;
      g.fp64 = spec_.gpu_fp64;
      g.tolerance = spec_.cg_tolerance;
      g.max_inner_iterations = spec_.cg_max_iterations;
      return std::make_unique<gpu::OperationalGpuSolver>(*context_, kernels_, g);
    }
    if (choice_.backend == Backend::direct) return std::make_unique<hybrid::CholmodSolver>();
    solve::CgOptions cg;
    cg.tolerance = spec_.cg_tolerance;
    cg.max_iterations = spec_.cg_max_iterations;
    return std::make_unique<hybrid::CgSolver>(cg);
  }

  SolverSpec spec_;
  bool need_interior_ = false;
  BackendChoice choice_;
  // Backend gpu: the application's context (outlives the Model) and the
  // compiled kernels every run shares; whether stage 5 runs on the device.
  gl::EglContext* context_ = nullptr;
  std::shared_ptr<const gpu::CgKernels> kernels_;
  bool device_product_ = false;  // a large dense K*^-1 P*
  double gpu_ms_ = 0;            // kernel compile time
  hybrid::Model model_;
  hybrid::CacheReport cache_;
  std::vector<std::pair<std::string, double>> timings_;
};

}  // namespace

std::unique_ptr<Solver> make_hybrid_solver(const mesh::TetMesh& m, const std::vector<fem::Material>& tet_material,
                                           const hybrid::Partition& partition, const SolverSpec& spec,
                                           bool need_interior, BackendChoice choice, gl::EglContext* context,
                                           const StopFlags& stop) {
  return std::make_unique<HybridSolver>(m, tet_material, partition, spec, need_interior, std::move(choice), context,
                                        stop);
}

}  // namespace softcut::backend
