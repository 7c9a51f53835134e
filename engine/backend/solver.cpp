#include "backend/solver.hpp"

#include "backend/hybrid_solver.hpp"
#include "backend/monolithic_solver.hpp"
#include "gl/egl_context.hpp"

namespace softcut::backend {

void check_solve_residual(double r, const char* what) {
  if (!(r <= kMaxRelativeResidual))
    fail(what, ": the relative residual of the solve is ", r, " (more than ", kMaxRelativeResidual,
         "): the system is singular or nearly so; is a part of the body held only by a node or an edge?");
}

BackendChoice choose_backend(const SolverSpec& spec, const gl::ContextInfo* info) {
  BackendChoice c;
  c.requested = spec.backend;
  if (info) c.device = info->renderer + (info->software ? ", software" : "");
  if (spec.whole_body) {
    if (spec.backend != Backend::automatic && spec.backend != Backend::monolithic)
      fail("solver: whole_body solves every tet by its law with no condensation, on the whole-mesh factor: backend ",
           "'", to_string(spec.backend), "' cannot; use backend \"auto\" or \"monolithic\"");
    c.backend = Backend::monolithic;
    c.reason = "whole_body: every tet by its law, nothing condensed (Newton on the whole-mesh factor)";
    return c;
  }
  switch (spec.backend) {
    case Backend::cpu:
    case Backend::direct:
    case Backend::monolithic:
      c.backend = spec.backend;
      c.reason = "requested";
      break;
    case Backend::gpu:
      if (!info)
        fail("solver: backend 'gpu' needs an OpenGL context, and none was created (the CLI makes one for --backend "
             "gpu; check the EGL error above, or use --backend cpu)");
      if (!info->compute)
        fail("solver: backend 'gpu': the OpenGL context (", info->summary(),
             ") has no compute shaders (OpenGL 4.3 needed); use --backend cpu");
      c.backend = Backend::gpu;
      c.device_product = true;
      c.reason = info->software ? "requested (on a software rasteriser: correct but slower than cpu)" : "requested";
      break;
    case Backend::automatic:
      // Measured (bench hybrid and bench cut --gpu, docs/bench-gpu.md): on an
      // NVIDIA H100 the kept CHOLMOD factor of the operational system beats
      // compute-shader CG at every size, before and after cuts (a GPU CG
      // iteration costs 47-140 us of dispatch and synchronisation; it needs
      // 140-900 of them), while stage 5's dense product runs there in well
      // under a millisecond where the CPU streams it in 6-12 ms. So on a
      // hardware GPU auto keeps CHOLMOD and moves stage 5 to the device;
      // llvmpipe is the CPU itself and is never chosen.
      c.backend = Backend::direct;
      if (info && !info->software && info->compute) {
        c.device_product = true;
        c.reason = "auto: CHOLMOD on the operational system (kept factor), measured faster than GPU CG on a hardware "
                   "GPU";  // the hybrid solver adds "; (K*^-1 P*) AI on the GPU" when it puts it there
      } else {
        c.reason = "auto: CHOLMOD on the operational system (kept factor), the fastest exact solver on a CPU";
      }
      break;
  }
  c.gpu_fp64 = c.backend == Backend::gpu && spec.gpu_fp64;
  return c;
}

std::unique_ptr<Solver> make_solver(const mesh::TetMesh& m, const std::vector<fem::Material>& tet_material,
                                    const hybrid::Partition& partition, const SolverSpec& spec, bool need_interior,
                                    const RunResources& resources, Diagnostics& diag) {
  resources.stop.poll("compile");
  BackendChoice choice = choose_backend(spec, resources.context ? &resources.context->info() : nullptr);
  if (spec.gpu_fp64 && choice.backend != Backend::gpu)
    diag.warn("solver: gpu_fp64 ignored: the operational backend is ", to_string(choice.backend), " (", choice.reason,
              ")");
  if (choice.backend == Backend::monolithic)
    return make_monolithic_solver(m, tet_material, partition, std::move(choice), spec);
  return make_hybrid_solver(m, tet_material, partition, spec, need_interior, std::move(choice), resources.context,
                            resources.stop);
}

}  // namespace softcut::backend
