#include "backend/monolithic_solver.hpp"

#include "core/timer.hpp"
#include "fem/whole_mesh.hpp"

namespace softcut::backend {

namespace {

// Whole-mesh reference (fem/whole_mesh.hpp): one CHOLMOD factor at compile
// time (and one per cut, kept in the run state), one solve per frame; the
// same mixed model as the hybrid one (operational tets by their laws, the
// rest linear; every tet by its law for a whole-body solve) by Newton with
// that factor as the preconditioner.
struct MonolithicSystem {
  fem::WholeMeshSolver solver;
  long generation = 0;
  // The tets a nonlinear frame evaluates itself (fem/nonlinear_tets.hpp):
  // those of a nonlinear law that take it, and those with a fixed corner.
  fem::NonlinearTets nonlinear;
  bool nonlinear_law = false;

  MonolithicSystem(const mesh::TetMesh& m, const std::vector<fem::Material>& tet_material,
                   const std::vector<char>& node_fixed, const std::vector<char>& operational_tet, bool whole_body,
                   long gen, double max_bytes)
      : solver(m, tet_material, node_fixed, "whole-mesh stiffness (is every part of the body fixed somewhere?)",
               max_bytes),
        generation(gen) {
    // The condensed region of the hybrid model is linear: outside the
    // operational tets a law applies only to a whole-body solve.
    std::vector<fem::Material> laws = tet_material;
    std::vector<int> own;
    for (int t = 0; t < m.num_tets(); ++t) {
      if (!whole_body && !operational_tet[size_t(t)]) laws[size_t(t)].model = fem::MaterialModel::linear;
      bool take = laws[size_t(t)].model != fem::MaterialModel::linear;
      nonlinear_law = nonlinear_law || take;
      for (int k = 0; k < 4 && !take; ++k) take = node_fixed[size_t(m.tets(t, k))];
      if (take) own.push_back(t);
    }
    nonlinear = fem::NonlinearTets(m, laws, std::move(own), fem::unknown_nodes(solver.system()));
  }
};

struct MonolithicRunState final : SolverRunState {
  std::shared_ptr<const MonolithicSystem> cut;  // system of the cut mesh, null before the first cut
  solve::SolveWorkspace ws;                     // this run's solves with the (shared) factor
  fem::NonlinearWork work;                      // a nonlinear frame's element tangents
  Eigen::VectorXd x;                            // the free DOFs' last solution (a nonlinear frame's warm start)
  solve::SecantStart secant;                    // a nonlinear frame's predicted Newton start
  long x_generation = -1;                       // the system x and secant belong to
  Eigen::MatrixX3d last_u;                      // the last frame's field (carried onto a cut mesh)
};

// The free DOFs of a field (nnode x 3) in a whole-mesh system's order.
Eigen::VectorXd restrict_field(const fem::WholeMesh& sys, const Eigen::MatrixX3d& u) {
  return fem::restrict_vector(fem::flatten(u), sys.dofs());
}

class MonolithicSolver final : public Solver {
 public:
  MonolithicSolver(const mesh::TetMesh& m, const std::vector<fem::Material>& tet_material,
                   const hybrid::Partition& p, BackendChoice choice, double max_bytes, bool whole_body,
                   const solve::NewtonOptions& newton)
      : choice_(std::move(choice)), max_bytes_(max_bytes), whole_body_(whole_body), newton_(newton) {
    std::vector<char> fixed(size_t(m.num_nodes()), 0);
    for (int n : p.fixed) fixed[size_t(n)] = 1;
    rest_ = std::make_shared<const MonolithicSystem>(m, tet_material, fixed, p.operational_tet, whole_body_, 0,
                                                     max_bytes_);
    timings_ = {{"assemble", rest_->solver.system().assemble_ms()}, {"factor", rest_->solver.factor_ms()}};
  }

  std::string name() const override {
    return whole_body_ ? "monolithic (whole body by its laws, Newton on the whole-mesh CHOLMOD factor)"
                       : "monolithic (whole-mesh CHOLMOD)";
  }
  bool nonlinear() const override { return rest_->nonlinear_law; }
  bool interior_valid() const override { return true; }
  std::vector<std::pair<std::string, double>> precompute_ms() const override { return timings_; }
  const BackendChoice& backend() const override { return choice_; }
  long system_generation(const SolverRun& warm) const override { return system(warm).generation; }

  void start_run(SolverRun& warm, const CutBody* cut) const override {
    auto rs = std::make_unique<MonolithicRunState>();
    if (cut)
      rs->cut = std::make_shared<const MonolithicSystem>(cut->mesh, cut->tet_material, cut->node_fixed,
                                                         cut->operational_tet, whole_body_, 1, max_bytes_);
    warm.backend = std::move(rs);
  }

  void apply_cut(const CutBody& cm, SolverRun& warm) const override {
    if (!dynamic_cast<MonolithicRunState*>(warm.backend.get())) start_run(warm, nullptr);
    auto& rs = static_cast<MonolithicRunState&>(*warm.backend);
    const long gen = system(warm).generation + 1;
    rs.cut = std::make_shared<const MonolithicSystem>(cm.mesh, cm.tet_material, cm.node_fixed, cm.operational_tet,
                                                      whole_body_, gen, max_bytes_);
    // The warm start onto the new nodes (their free DOFs renumbered).
    if (cm.carry && rs.x_generation >= 0 && rs.last_u.rows() == cm.nodes_before) {
      rs.x = restrict_field(rs.cut->solver.system(), cm.carry(rs.last_u));
      rs.x_generation = gen;
    }
  }

  void unit_responses(const std::vector<int>& nodes, SolverRun& warm, Eigen::MatrixXd& out) const override {
    out = system(warm).solver.unit_responses(nodes, run_state(warm).ws);
  }

  void solve(const Eigen::MatrixX3d& forces, Eigen::MatrixX3d& u, SolverRun& warm, SolveStats& stats,
             const FrameInput& in) const override {
    Timer t;
    stats = SolveStats{};
    MonolithicRunState& rs = run_state(warm);
    const MonolithicSystem& sys = system(warm);
    const bool moving = in.prescribed && in.prescribed->size() > 0 && in.prescribed->squaredNorm() > 0;
    const Eigen::MatrixX3d none;
    const Eigen::MatrixX3d& prescribed = moving ? *in.prescribed : none;
    if (!sys.nonlinear_law && !in.springs) {
      u = sys.solver.solve(forces, rs.ws, prescribed, &stats.relative_residual);
      check_solve_residual(stats.relative_residual, "whole-mesh solve");
      rs.secant.clear();  // rs.x is not this frame's: no history through it
    } else {
      if (rs.x_generation != sys.generation) rs.x.resize(0), rs.secant.clear(), rs.x_generation = sys.generation;
      fem::NonlinearSolve ns;
      ns.linear = &sys.solver;
      ns.set = &sys.nonlinear;
      ns.springs = in.springs;
      ns.start = rs.secant.predict(rs.x);
      ns.options = newton_;
      const Eigen::VectorXd x_last = rs.x;
      const solve::NewtonReport rep = fem::solve_nonlinear(ns, forces, prescribed, rs.x, rs.work, rs.ws, "whole-mesh solve");
      rs.secant.record(x_last, rs.x);
      check_solve_residual(rep.relative_residual, "whole-mesh solve");
      u = sys.solver.system().field(rs.x, prescribed);
      stats.relative_residual = rep.relative_residual;
      stats.cg_iterations = rep.cg_iterations;
      stats.newton = true;
      stats.newton_iterations = rep.iterations;
      stats.projected_steps = rep.projected_steps;
      stats.at_floor = rep.at_floor;
      stats.max_rotation = rs.work.max_rotation;
      stats.max_strain = rs.work.max_strain;
      stats.inverted = rs.work.inverted;
    }
    rs.last_u = u;
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
  bool whole_body_ = false;
  solve::NewtonOptions newton_;
  std::shared_ptr<const MonolithicSystem> rest_;
  std::vector<std::pair<std::string, double>> timings_;
};

}  // namespace

std::unique_ptr<Solver> make_monolithic_solver(const mesh::TetMesh& m, const std::vector<fem::Material>& tet_material,
                                               const hybrid::Partition& partition, BackendChoice choice,
                                               const SolverSpec& spec) {
  return std::make_unique<MonolithicSolver>(m, tet_material, partition, std::move(choice), spec.max_bytes,
                                            spec.whole_body, spec.newton);
}

}  // namespace softcut::backend
