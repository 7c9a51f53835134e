#include "backend/monolithic_solver.hpp"

#include "core/timer.hpp"
#include "fem/whole_mesh.hpp"

namespace softcut::backend {

namespace {

// Whole-mesh reference (fem/whole_mesh.hpp): one CHOLMOD factor at compile
// time (and one per cut, kept in the run state), one solve per frame.
struct MonolithicSystem {
  fem::WholeMeshSolver solver;
  long generation = 0;

  MonolithicSystem(const mesh::TetMesh& m, const std::vector<fem::Material>& tet_material,
                   const std::vector<char>& node_fixed, long gen, double max_bytes)
      : solver(m, tet_material, node_fixed, "whole-mesh stiffness (is every part of the body fixed somewhere?)",
               max_bytes),
        generation(gen) {}
};

struct MonolithicRunState final : SolverRunState {
  std::shared_ptr<const MonolithicSystem> cut;  // system of the cut mesh, null before the first cut
  solve::SolveWorkspace ws;                     // this run's solves with the (shared) factor
};

class MonolithicSolver final : public Solver {
 public:
  MonolithicSolver(const mesh::TetMesh& m, const std::vector<fem::Material>& tet_material,
                   const hybrid::Partition& p, BackendChoice choice, double max_bytes)
      : choice_(std::move(choice)), max_bytes_(max_bytes) {
    std::vector<char> fixed(size_t(m.num_nodes()), 0);
    for (int n : p.fixed) fixed[size_t(n)] = 1;
    rest_ = std::make_shared<const MonolithicSystem>(m, tet_material, fixed, 0, max_bytes_);
    timings_ = {{"assemble", rest_->solver.system().assemble_ms()}, {"factor", rest_->solver.factor_ms()}};
  }

  std::string name() const override { return "monolithic (whole-mesh CHOLMOD)"; }
  bool interior_valid() const override { return true; }
  std::vector<std::pair<std::string, double>> precompute_ms() const override { return timings_; }
  const BackendChoice& backend() const override { return choice_; }
  long system_generation(const SolverRun& warm) const override { return system(warm).generation; }

  void start_run(SolverRun& warm, const CutBody* cut) const override {
    auto rs = std::make_unique<MonolithicRunState>();
    if (cut)
      rs->cut = std::make_shared<const MonolithicSystem>(cut->mesh, cut->tet_material, cut->node_fixed, 1, max_bytes_);
    warm.backend = std::move(rs);
  }

  void apply_cut(const CutBody& cm, SolverRun& warm) const override {
    if (!dynamic_cast<MonolithicRunState*>(warm.backend.get())) start_run(warm, nullptr);
    auto& rs = static_cast<MonolithicRunState&>(*warm.backend);
    const long gen = system(warm).generation + 1;
    rs.cut = std::make_shared<const MonolithicSystem>(cm.mesh, cm.tet_material, cm.node_fixed, gen, max_bytes_);
  }

  void unit_responses(const std::vector<int>& nodes, SolverRun& warm, Eigen::MatrixXd& out) const override {
    out = system(warm).solver.unit_responses(nodes, run_state(warm).ws);
  }

  void solve(const Eigen::MatrixX3d& forces, Eigen::MatrixX3d& u, SolverRun& warm,
             SolveStats& stats) const override {
    Timer t;
    stats = SolveStats{};
    u = system(warm).solver.solve(forces, run_state(warm).ws, {}, &stats.relative_residual);
    check_solve_residual(stats.relative_residual, "whole-mesh solve");
    stats.operational_ms = t.ms();
  }

 private:
  MonolithicRunState& run_state(SolverRun& warm) const {
    if (!dynamic_cast<MonolithicRunState*>(warm.backend.get())) start_run(warm, nullptr);
    return static_cast<MonolithicRunState&>(*warm.backend);
  }
  const MonolithicSystem& system(const SolverRun& warm) const {
    const auto* rs = dynamic_cast<const MonolithicRunState*>(warm.backend.get());
    return rs && rs->cut ? *rs->cut : *rest_;
  }

  BackendChoice choice_;
  double max_bytes_;  // the factor's bound (SolverSpec::max_bytes)
  std::shared_ptr<const MonolithicSystem> rest_;
  std::vector<std::pair<std::string, double>> timings_;
};

}  // namespace

std::unique_ptr<Solver> make_monolithic_solver(const mesh::TetMesh& m, const std::vector<fem::Material>& tet_material,
                                               const hybrid::Partition& partition, BackendChoice choice,
                                               double max_bytes) {
  return std::make_unique<MonolithicSolver>(m, tet_material, partition, std::move(choice), max_bytes);
}

}  // namespace softcut::backend
