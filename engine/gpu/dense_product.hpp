#pragma once
// (K*^-1 P*) AI on the device (issue: the nonoperational product "on the
// device when it is large"). The matrix (3|s| x 3|I|) is uploaded once in
// double precision — the product feeds the surface displacements directly,
// with no refinement loop to hide fp32 rounding — and each frame moves only
// AI up and the 3|s| result down. One invocation per row; rows are stored
// contiguously (row-major) so a work group reads consecutive memory.
#include <Eigen/Core>
#include <memory>

#include "gpu/compute_program.hpp"
#include "gl/egl_context.hpp"
#include "hybrid/nonoperational_product.hpp"

namespace softcut::gpu {

class DeviceDenseProduct : public hybrid::NonoperationalProduct {
 public:
  // Throws softcut::Error when the context has no compute shaders or no
  // double-precision support.
  DeviceDenseProduct(gl::EglContext& context, const Eigen::MatrixXd& matrix);
  ~DeviceDenseProduct() override;
  std::string name() const override { return "gpu-fp64"; }
  void apply(const Eigen::VectorXd& x, Eigen::VectorXd& y) override;

  // Entries from which a run attaches the device product (backend gpu, and
  // auto on a hardware GPU): 32 MB of doubles, ~3 ms per frame for the CPU
  // product at ~10 GB/s. Measured on an NVIDIA H100 at 17.3M entries: well
  // under 1 ms a frame against ~11 ms on the CPU (docs/bench-gpu.md); the
  // crossover below 4M was not measured, so the threshold stays conservative.
  static constexpr double kWorthwhileEntries = 4e6;

 private:
  gl::EglContext& context_;
  ComputeProgram program_;
  StorageBuffer matrix_, x_, y_;
  int rows_ = 0, cols_ = 0;
};

}  // namespace softcut::gpu
