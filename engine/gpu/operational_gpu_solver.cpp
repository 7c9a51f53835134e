#include "gpu/operational_gpu_solver.hpp"

#include "core/error.hpp"

namespace softcut::gpu {

OperationalGpuSolver::OperationalGpuSolver(gl::EglContext& context, ComputeCgOptions options) : cg_(context, options) {}

OperationalGpuSolver::OperationalGpuSolver(gl::EglContext& context, std::shared_ptr<const CgKernels> kernels,
                                           ComputeCgOptions options)
    : cg_(context, std::move(kernels), options) {}

hybrid::SolveReport OperationalGpuSolver::solve(const hybrid::OperationalSystem& sys, const Eigen::VectorXd& b,
                                                Eigen::VectorXd& x) {
  if (sys.size() == 0) {
    x.resize(0);
    return {};
  }
  if (sys.generation != generation_) {
    uploaded_ = cg_.set_system(make_block_system(sys.K, sys.K_prime.get()));
    generation_ = sys.generation;
  }
  last_ = cg_.solve([&sys](const Eigen::VectorXd& v, Eigen::VectorXd& y) { sys.apply(v, y); }, b, x);
  last_.uploaded_bytes = uploaded_;
  if (!last_.converged)
    fail("GPU solver: the operational solve stalled at relative residual ", last_.relative_residual, " after ",
         last_.refinements, " refinements (tolerance ", cg_.options().tolerance,
         "); try --backend cpu or the fp64 kernels");
  return {last_.iterations, last_.relative_residual};
}

}  // namespace softcut::gpu
