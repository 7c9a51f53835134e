#include "sim/solver.hpp"

#include <vector>

#include "core/timer.hpp"
#include "fem/assembly.hpp"
#include "fem/dof_map.hpp"
#include "hybrid/loads.hpp"
#include "hybrid/precompute.hpp"
#include "hybrid/update.hpp"
#include "sim/scenario_spec.hpp"
#include "solve/cholesky.hpp"

namespace softcut::sim {

namespace {

// Whole-mesh reference: K u = f over every tet with the fixed DOFs
// eliminated, one CHOLMOD factor at compile time, one solve per frame.
class MonolithicSolver final : public Solver {
 public:
  MonolithicSolver(const mesh::TetMesh& m, const std::vector<fem::Material>& tet_material,
                   const hybrid::Partition& p) {
    nnode_ = m.num_nodes();
    Timer t;
    const fem::SparseMatrix K = fem::assemble_stiffness(m, tet_material);
    std::vector<char> free(nnode_, 0);
    for (int n = 0; n < nnode_; ++n)
      free[n] = p.node_set[n] != hybrid::NodeSet::unused && p.node_set[n] != hybrid::NodeSet::fixed;
    map_ = fem::make_dof_map(free);
    const fem::SparseMatrix Kf = fem::restrict_matrix(K, map_);
    timings_.emplace_back("assemble", t.ms());
    t.reset();
    factor_.factor(Kf, "whole-mesh stiffness (is every part of the body fixed somewhere?)");
    timings_.emplace_back("factor", t.ms());
  }

  std::string name() const override { return "monolithic (whole-mesh CHOLMOD)"; }
  bool interior_valid() const override { return true; }
  std::vector<std::pair<std::string, double>> precompute_ms() const override { return timings_; }

  void solve(const Eigen::MatrixX3d& forces, Eigen::MatrixX3d& u, SolverWarmStart&, SolveStats& stats) const override {
    Timer t;
    const Eigen::VectorXd f = fem::restrict_vector(fem::flatten(forces), map_);
    const Eigen::VectorXd x = f.squaredNorm() > 0 ? factor_.solve(f) : Eigen::VectorXd::Zero(f.size());
    u = fem::unflatten(fem::expand_vector(x, map_, nnode_));
    stats = SolveStats{};
    stats.operational_ms = t.ms();
  }

 private:
  int nnode_ = 0;
  fem::DofMap map_;
  solve::Cholesky factor_;
  std::vector<std::pair<std::string, double>> timings_;
};

struct HybridRunState final : SolverRunState {
  hybrid::State state;
  std::vector<hybrid::Load> loads;  // scratch
};

// Wu & Heng's hybrid condensed model: precompute once, update per frame.
class HybridSolver final : public Solver {
 public:
  HybridSolver(const mesh::TetMesh& m, const std::vector<fem::Material>& tet_material, const hybrid::Partition& p,
               const SolverSpec& spec, bool need_interior, Diagnostics& diag)
      : spec_(spec), need_interior_(need_interior) {
    hybrid::PrecomputeOptions opt;
    opt.storage = spec.mode == "dense"    ? hybrid::Storage::dense
                  : spec.mode == "factor" ? hybrid::Storage::factor
                                          : hybrid::Storage::automatic;
    model_ = hybrid::precompute(m, tet_material, p, opt);
    if (spec.backend == "gpu") diag.warn("solver: the GPU operational backend is not available yet; using the CPU CG");
    const hybrid::PrecomputeTimings& t = model_.timings;
    timings_ = {{"assemble", t.assemble_ms},           {"factor", t.factor_ms},
                {"K_prime", t.K_prime_ms},             {"KI2_K22inv", t.KI2_K22inv_ms},
                {"Kstar_inv", t.Kstar_inv_ms},         {"Kstar_inv_Pstar", t.Kstar_inv_Pstar_ms},
                {"Kstar_inv_Ps0", t.Kstar_inv_Ps0_ms}, {"operational_system", t.operational_ms},
                {"hybrid_total", t.total_ms}};
  }

  std::string name() const override {
    return cat("hybrid (", hybrid::to_string(model_.storage), " storage, operational ", backend_name(), ")");
  }
  bool interior_valid() const override { return need_interior_; }
  std::vector<std::pair<std::string, double>> precompute_ms() const override { return timings_; }

  void solve(const Eigen::MatrixX3d& forces, Eigen::MatrixX3d& u, SolverWarmStart& warm,
             SolveStats& stats) const override {
    auto* rs = dynamic_cast<HybridRunState*>(warm.backend.get());
    if (!rs) {
      auto fresh = std::make_shared<HybridRunState>();
      fresh->state = hybrid::make_state(model_, make_operational_solver());
      warm.backend = fresh;
      rs = fresh.get();
    }
    rs->loads.clear();
    for (int n = 0; n < forces.rows(); ++n)
      if (forces.row(n).squaredNorm() > 0 && model_.partition.node_set[n] != hybrid::NodeSet::fixed)
        rs->loads.push_back({n, forces.row(n).transpose()});
    hybrid::UpdateOptions opt;
    opt.recover_interior = need_interior_;
    const hybrid::FrameReport& rep = hybrid::update(model_, rs->state, rs->loads, opt);
    u = rs->state.u;
    stats = SolveStats{};
    stats.cg_iterations = rep.solve.iterations;
    stats.relative_residual = rep.solve.relative_residual;
    stats.loads_ms = rep.loads_ms;
    stats.operational_ms = rep.operational_ms;
    stats.nonoperational_ms = rep.selective_ms + rep.nonoperational_ms;
  }

 private:
  const char* backend_name() const { return spec_.backend == "direct" ? "cholmod" : "cg"; }

  std::unique_ptr<hybrid::OperationalSolver> make_operational_solver() const {
    if (spec_.backend == "direct") return std::make_unique<hybrid::CholmodSolver>();
    solve::CgOptions cg;
    cg.tolerance = spec_.cg_tolerance;
    cg.max_iterations = spec_.cg_max_iterations;
    return std::make_unique<hybrid::CgSolver>(cg);
  }

  SolverSpec spec_;
  bool need_interior_ = false;
  hybrid::Model model_;
  std::vector<std::pair<std::string, double>> timings_;
};

}  // namespace

std::unique_ptr<Solver> make_solver(const mesh::TetMesh& m, const std::vector<fem::Material>& tet_material,
                                    const hybrid::Partition& partition, const SolverSpec& spec, bool need_interior,
                                    Diagnostics& diag) {
  if (spec.backend == "monolithic") return std::make_unique<MonolithicSolver>(m, tet_material, partition);
  return std::make_unique<HybridSolver>(m, tet_material, partition, spec, need_interior, diag);
}

}  // namespace softcut::sim
