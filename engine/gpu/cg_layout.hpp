#pragma once
// Buffer layout of the compute-shader CG, shared by host and shaders: the
// shaders are compiled with glsl_defines() prepended, so both sides read the
// same binding points and scalar slots from these constants.
#include <cstdint>
#include <string>

namespace softcut::gpu::cg_layout {

inline constexpr std::uint32_t kGroupSize = 128;   // invocations per work group
inline constexpr std::uint32_t kReduceGroups = 64; // partial sums per dot product

// Shader storage binding points.
enum Binding : std::uint32_t {
  kRowPtr = 0,   // uint[nb + 1]
  kCol = 1,      // uint[nnzb]
  kValues = 2,   // REAL[9 nnzb], row-major 3x3 blocks
  kDense = 3,    // REAL[m m], row-major dense block on DOFs [offset, offset + m)
  kDiagInv = 4,  // REAL[9 nb], inverse diagonal blocks (block-Jacobi)
  kX = 5,        // REAL[n] solution of the inner solve
  kR = 6,        // REAL[n] residual; holds the right-hand side on entry
  kP = 7,        // REAL[n] search direction
  kAp = 8,       // REAL[n] A p
  kZ = 9,        // REAL[n] preconditioned residual
  kPartial = 10, // REAL[2 kReduceGroups] per-group partial dot products
  kScalars = 11, // REAL[kNumScalars]
};

// Slots of the scalar buffer; the reduce kernels compute alpha and beta on
// the device so an iteration needs no read-back.
enum Scalar : std::uint32_t { kRz = 0, kPap = 1, kAlpha = 2, kBeta = 3, kRr = 4, kNumScalars = 8 };

// "#define NAME value" lines for every constant above, plus REAL.
std::string glsl_defines(bool fp64);

}  // namespace softcut::gpu::cg_layout
