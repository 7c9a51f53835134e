#pragma once
// Preconditioned CG on the device (OpenGL 4.5 compute shaders in the
// application's EGL context), DESIGN.md §3. The matrix and every CG vector stay
// on the device; alpha and beta are computed by reduce kernels, so an
// iteration is 7 dispatches with no read-back; the residual norm is read every
// `check_every` iterations.
//
// Precision: fp32 kernels inside an fp64 refinement loop on the CPU
// (mixed-precision iterative refinement): r = b - A x in double with the exact
// operator, the device solves A d = r to `inner_tolerance`, x += d, until
// ||b - A x|| <= tolerance ||b||. So the answer meets the CPU solver's
// tolerance although the device computes in float. Each device solve sees r
// scaled to a largest entry of 1, so fp32 dot products neither underflow nor
// overflow whatever the load's magnitude. With fp64 = true the same
// kernels run in double (GL 4.0+ core; llvmpipe and NVIDIA offer it).
#include <Eigen/Core>
#include <cstddef>
#include <memory>

#include "gl/egl_context.hpp"
#include "gpu/block_system.hpp"
#include "gpu/device_system.hpp"
#include "solve/cg.hpp"

namespace softcut::gpu {

struct ComputeCgOptions {
  bool fp64 = false;             // double-precision kernels
  double tolerance = 1e-10;      // outer: ||b - A x|| <= tolerance ||b|| (fp64, CPU)
  double inner_tolerance = 0;    // device solve; 0: 1e-4 for fp32, tolerance/10 for fp64
  int max_refinements = 60;      // outer iterations
  int max_inner_iterations = 0;  // per inner solve; 0: 10 n
  int check_every = 8;           // device iterations between residual read-backs
};

struct ComputeCgReport {
  int refinements = 0;            // outer iterations (CPU residual evaluations - 1)
  int iterations = 0;             // device CG iterations, all refinements together
  double relative_residual = 0;   // final ||b - A x|| / ||b||, computed in double on the CPU
  bool converged = false;
  std::size_t uploaded_bytes = 0; // matrix bytes sent by the last set_system()
};

// The CG kernels of one precision, compiled in one context: fixed data,
// shared by every ComputeCg made from them (a Model compiles them once; each
// run gets its own buffers). A kernel holds no run's data: each dispatch
// passes its system's sizes (ComputeProgram::dispatch).
struct CgKernels;
// Throws softcut::Error when the context has no compute shaders (or no fp64
// when asked).
std::shared_ptr<const CgKernels> compile_cg_kernels(gl::EglContext& context, bool fp64);

class ComputeCg {
 public:
  // Compiles its own kernels in `context` (made current); throws as compile_cg_kernels.
  ComputeCg(gl::EglContext& context, ComputeCgOptions options = {});
  // Uses shared kernels of the precision options.fp64.
  ComputeCg(gl::EglContext& context, std::shared_ptr<const CgKernels> kernels, ComputeCgOptions options);
  ~ComputeCg();
  ComputeCg(const ComputeCg&) = delete;
  ComputeCg& operator=(const ComputeCg&) = delete;

  // Uploads a system. When the block pattern is unchanged (e.g. a cut that
  // only changed values, or the same system again) only the changed byte
  // ranges of the values and the dense block are sent. When it changed (a cut
  // appends nodes before the interface nodes and rewrites the rows near the
  // cut), the block rows both systems share (diff_block_systems) stay on
  // the device: those whose offset changed are moved through a scratch
  // buffer, their block columns renumbered by a kernel; only row_ptr and the
  // other rows are sent, and K' stays. Buffers grow with 25% spare capacity. A
  // full upload is made when that is not cheaper. Returns bytes sent.
  std::size_t set_system(const BlockSystem& system);
  const SystemUpload& last_upload() const;

  // Debug read-backs: the matrix as the device holds it (values in device
  // precision, converted to double), and y = A x by the device kernels.
  BlockSystem device_system() const;
  void apply_device(const Eigen::VectorXd& x, Eigen::VectorXd& y);

  // Solves A x = b starting from x (warm start). `exact` applies A in double
  // for the refinement residual (e.g. BlockSystem::apply or the operational
  // system's own apply).
  ComputeCgReport solve(const solve::LinearOperator& exact, const Eigen::VectorXd& b, Eigen::VectorXd& x);

  // One device solve A d = r from d = 0 to a relative residual `tolerance`
  // (device arithmetic); returns the iterations. For benchmarks and tests.
  int solve_device(const Eigen::VectorXd& r, Eigen::VectorXd& d, double tolerance);

  // Times `repeats` device SpMVs (K p and the dense block) and returns
  // seconds per product (glFinish before and after).
  double time_spmv(int repeats);

  const ComputeCgOptions& options() const { return opt_; }
  ComputeCgOptions& options() { return opt_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  ComputeCgOptions opt_;
  gl::EglContext& context_;
};

}  // namespace softcut::gpu
