#pragma once
// Wu & Heng's hybrid condensed model as a run's solver: hybrid::precompute
// once (through the precompute cache), hybrid::update per frame, with the
// operational solver the choice names (CHOLMOD, CG, or compute-shader CG on
// the application's context); unit responses in one batch for operational
// nodes (the paper's selective columns otherwise).
#include <memory>
#include <vector>

#include "backend/solver.hpp"

namespace softcut::backend {

// need_interior: interior nonoperational rows of u are wanted every frame.
// context: the application's, for choice.backend == gpu (outlives the solver).
std::unique_ptr<Solver> make_hybrid_solver(const mesh::TetMesh& m, const std::vector<fem::Material>& tet_material,
                                           const hybrid::Partition& partition, const SolverSpec& spec,
                                           bool need_interior, BackendChoice choice, gl::EglContext* context,
                                           const StopFlags& stop = {});

}  // namespace softcut::backend
