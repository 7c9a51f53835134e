#pragma once
// The whole-mesh reference backend ("monolithic"): one CHOLMOD factor of the
// whole mesh's stiffness at compile time (fem/whole_mesh), one more per cut
// kept in the run's state, one solve per frame. No hybrid split; for checks.
#include <memory>
#include <vector>

#include "backend/solver.hpp"

namespace softcut::backend {

// max_bytes: the factor's bound (SolverSpec::max_bytes).
std::unique_ptr<Solver> make_monolithic_solver(const mesh::TetMesh& m, const std::vector<fem::Material>& tet_material,
                                               const hybrid::Partition& partition, BackendChoice choice,
                                               double max_bytes);

}  // namespace softcut::backend
