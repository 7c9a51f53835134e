#pragma once
// The ONE place where the elastic solve is chosen: make_solver() returns the
// hybrid backend (hybrid::precompute once, hybrid::update per frame) with the
// operational backend named by SolverSpec::backend, or the whole-mesh CHOLMOD
// reference ("monolithic"). Nothing else in engine/sim knows which.
#include <Eigen/Core>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "fem/material.hpp"
#include "hybrid/partition.hpp"
#include "mesh/tet_mesh.hpp"

namespace softcut::sim {

struct SolverSpec;

// Backend-owned per-run data (e.g. hybrid::State: warm start, running sums).
struct SolverRunState {
  virtual ~SolverRunState() = default;
};

// Per-run mutable solver data kept in State, created by the first solve.
// Copying a State shares it: use make_state() for an independent run.
struct SolverWarmStart {
  std::shared_ptr<SolverRunState> backend;
};

struct SolveStats {
  int cg_iterations = 0;          // 0 for direct solves
  double relative_residual = 0;   // of the operational system
  double loads_ms = 0;            // stage 2: checking and sorting the loads
  double operational_ms = 0;      // stage 4
  double nonoperational_ms = 0;   // stages 3 + 5
};

class Solver {
 public:
  virtual ~Solver() = default;
  virtual std::string name() const = 0;  // e.g. "hybrid (dense storage, operational cg)"
  // forces (nnode x 3), N -> u (nnode x 3), m. Fixed nodes get zero. Rows of
  // nonoperational interior nodes are valid only when interior_valid().
  virtual void solve(const Eigen::MatrixX3d& forces, Eigen::MatrixX3d& u, SolverWarmStart& warm,
                     SolveStats& stats) const = 0;
  virtual bool interior_valid() const = 0;
  // Precompute timings, ms, by stage name (Table 3), in a stable order.
  virtual std::vector<std::pair<std::string, double>> precompute_ms() const = 0;
};

// tet_material (ntet). need_interior: interior nonoperational rows of u are
// wanted every frame (logged or exported), at one extra factor solve a frame.
// Notes (backend fallbacks) go to diag.
std::unique_ptr<Solver> make_solver(const mesh::TetMesh& m, const std::vector<fem::Material>& tet_material,
                                    const hybrid::Partition& partition, const SolverSpec& spec, bool need_interior,
                                    Diagnostics& diag);

}  // namespace softcut::sim
