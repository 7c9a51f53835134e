#pragma once
// The hybrid model's operational solve on the device: adapts ComputeCg to
// hybrid::OperationalSolver, so `--backend gpu` swaps it in for CgSolver.
#include <memory>

#include "gpu/compute_cg.hpp"
#include "hybrid/operational_solvers.hpp"

namespace softcut::gpu {

class OperationalGpuSolver : public hybrid::OperationalSolver {
 public:
  OperationalGpuSolver(gl::EglContext& context, ComputeCgOptions options = {});
  // One per run, sharing the Model's compiled kernels (of precision options.fp64).
  OperationalGpuSolver(gl::EglContext& context, std::shared_ptr<const CgKernels> kernels, ComputeCgOptions options);
  std::string name() const override { return cg_.options().fp64 ? "gpu-fp64" : "gpu"; }
  // Re-uploads (only what changed) when the system's generation changes;
  // throws softcut::Error when the tolerance is not reached.
  hybrid::SolveReport solve(const hybrid::OperationalSystem& sys, const Eigen::VectorXd& b,
                            Eigen::VectorXd& x) override;
  const ComputeCgReport& last_report() const { return last_; }

 private:
  ComputeCg cg_;
  long generation_ = -1;
  std::size_t uploaded_ = 0;
  ComputeCgReport last_;
};

}  // namespace softcut::gpu
