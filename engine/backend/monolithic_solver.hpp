#pragma once
// The whole-mesh reference backend ("monolithic"): one CHOLMOD factor of the
// whole mesh's stiffness at compile time (fem/whole_mesh), one more per cut
// kept in the run's state, one solve per frame (a Newton solve on that
// factor for a nonlinear model). No hybrid split; for checks, and for a
// whole body solved by its laws (SolverSpec::whole_body).
#include <memory>
#include <vector>

#include "backend/solver.hpp"

namespace softcut::backend {

// spec: max_bytes (the factor's bound), whole_body, newton.
std::unique_ptr<Solver> make_monolithic_solver(const mesh::TetMesh& m, const std::vector<fem::Material>& tet_material,
                                               const hybrid::Partition& partition, BackendChoice choice,
                                               const SolverSpec& spec);

}  // namespace softcut::backend
