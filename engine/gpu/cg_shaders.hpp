#pragma once
// GLSL sources of the compute-shader CG kernels (see cg_layout.hpp).
#include <string>

namespace softcut::gpu::cg_shaders {

// Each returns a complete compute shader for REAL = float or double.
std::string spmv(bool fp64);         // Ap = K p (block rows)
std::string dense(bool fp64);        // Ap[off..] += D p[off..]
std::string dot_p_ap(bool fp64);     // partial sums of p . Ap
std::string reduce_alpha(bool fp64); // pAp, alpha = rz / pAp
std::string update(bool fp64);       // x += a p; r -= a Ap; z = M r; partial r.z, r.r
std::string reduce_beta(bool fp64);  // rz_new, rr, beta = rz_new / rz, rz = rz_new
std::string direction(bool fp64);    // p = z + beta p
std::string start(bool fp64);        // x = 0; z = M r; p = z; partial r.z, r.r
// col[k] += delta where col[k] >= threshold, k in [first, last): renumbers the
// block columns a device-side move kept when rows were inserted or removed.
std::string shift_cols();

}  // namespace softcut::gpu::cg_shaders
