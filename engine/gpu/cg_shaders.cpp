#include "gpu/cg_shaders.hpp"

#include "core/error.hpp"
#include "gpu/cg_layout.hpp"

namespace softcut::gpu {

std::string cg_layout::glsl_defines(bool fp64) {
  return cat("#define GROUP_SIZE ", kGroupSize, "\n#define REDUCE_GROUPS ", kReduceGroups,
             "\n#define B_ROW_PTR ", kRowPtr, "\n#define B_COL ", kCol, "\n#define B_VALUES ", kValues,
             "\n#define B_DENSE ", kDense, "\n#define B_DIAG_INV ", kDiagInv, "\n#define B_X ", kX, "\n#define B_R ",
             kR, "\n#define B_P ", kP, "\n#define B_AP ", kAp, "\n#define B_Z ", kZ, "\n#define B_PARTIAL ", kPartial,
             "\n#define B_SCALARS ", kScalars, "\n#define S_RZ ", kRz, "\n#define S_PAP ", kPap, "\n#define S_ALPHA ",
             kAlpha, "\n#define S_BETA ", kBeta, "\n#define S_RR ", kRr, "\n#define REAL ", fp64 ? "double" : "float",
             "\n");
}

namespace cg_shaders {
namespace {

// Header + every buffer declaration; unused ones cost nothing.
std::string prelude(bool fp64) {
  return "#version 450 core\n" + cg_layout::glsl_defines(fp64) + R"(
layout(local_size_x = GROUP_SIZE) in;
layout(std430, binding = B_ROW_PTR) readonly buffer RowPtr { uint row_ptr[]; };
layout(std430, binding = B_COL) readonly buffer Col { uint col[]; };
layout(std430, binding = B_VALUES) readonly buffer Values { REAL vals[]; };
layout(std430, binding = B_DENSE) readonly buffer Dense { REAL dense[]; };
layout(std430, binding = B_DIAG_INV) readonly buffer DiagInv { REAL dinv[]; };
layout(std430, binding = B_X) buffer X { REAL x[]; };
layout(std430, binding = B_R) buffer R { REAL r[]; };
layout(std430, binding = B_P) buffer P { REAL p[]; };
layout(std430, binding = B_AP) buffer AP { REAL ap[]; };
layout(std430, binding = B_Z) buffer Z { REAL z[]; };
layout(std430, binding = B_PARTIAL) buffer Partial { REAL partial[]; };
layout(std430, binding = B_SCALARS) buffer Scalars { REAL scalars[]; };
uniform uint nb;          // node blocks; n = 3 nb
uniform uint dense_off;   // first DOF of the dense block
uniform uint dense_m;     // size of the dense block
shared REAL red0[GROUP_SIZE];
shared REAL red1[GROUP_SIZE];

// Tree sums of a and b over the group into red0[0] and red1[0] (every
// invocation must call it: it holds barriers).
void group_sum2(REAL a, REAL b) {
  uint t = gl_LocalInvocationID.x;
  red0[t] = a; red1[t] = b;
  barrier();
  for (uint s = GROUP_SIZE / 2u; s > 0u; s >>= 1u) {
    if (t < s) { red0[t] += red0[t + s]; red1[t] += red1[t + s]; }
    barrier();
  }
}

// group_sum2, then thread 0 writes the group's partials.
void group_reduce2(REAL a, REAL b) {
  group_sum2(a, b);
  if (gl_LocalInvocationID.x == 0u) {
    partial[2u * gl_WorkGroupID.x] = red0[0];
    partial[2u * gl_WorkGroupID.x + 1u] = red1[0];
  }
}

// z_I = Dinv_I r_I for node I.
void precondition(uint I) {
  uint o = 9u * I, i = 3u * I;
  REAL r0 = r[i], r1 = r[i + 1u], r2 = r[i + 2u];
  z[i] = dinv[o] * r0 + dinv[o + 1u] * r1 + dinv[o + 2u] * r2;
  z[i + 1u] = dinv[o + 3u] * r0 + dinv[o + 4u] * r1 + dinv[o + 5u] * r2;
  z[i + 2u] = dinv[o + 6u] * r0 + dinv[o + 7u] * r1 + dinv[o + 8u] * r2;
}
)";
}

// Sums the 2 x REDUCE_GROUPS partials in one group: returns (sum0, sum1) in red0[0], red1[0].
const char* kFinalReduce = R"(
void final_reduce() {
  REAL a = REAL(0), b = REAL(0);
  for (uint g = gl_LocalInvocationID.x; g < REDUCE_GROUPS; g += GROUP_SIZE) { a += partial[2u * g]; b += partial[2u * g + 1u]; }
  group_sum2(a, b);
}
)";

}  // namespace

std::string spmv(bool fp64) {
  return prelude(fp64) + R"(
void main() {
  uint I = gl_GlobalInvocationID.x;
  if (I >= nb) return;
  REAL y0 = REAL(0), y1 = REAL(0), y2 = REAL(0);
  for (uint k = row_ptr[I]; k < row_ptr[I + 1u]; ++k) {
    uint j = 3u * col[k], o = 9u * k;
    REAL p0 = p[j], p1 = p[j + 1u], p2 = p[j + 2u];
    y0 += vals[o] * p0 + vals[o + 1u] * p1 + vals[o + 2u] * p2;
    y1 += vals[o + 3u] * p0 + vals[o + 4u] * p1 + vals[o + 5u] * p2;
    y2 += vals[o + 6u] * p0 + vals[o + 7u] * p1 + vals[o + 8u] * p2;
  }
  ap[3u * I] = y0; ap[3u * I + 1u] = y1; ap[3u * I + 2u] = y2;
}
)";
}

std::string dense(bool fp64) {
  return prelude(fp64) + R"(
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= dense_m) return;
  REAL y = REAL(0);
  uint row = i * dense_m;
  for (uint j = 0u; j < dense_m; ++j) y += dense[row + j] * p[dense_off + j];
  ap[dense_off + i] += y;
}
)";
}

std::string dot_p_ap(bool fp64) {
  return prelude(fp64) + R"(
void main() {
  REAL a = REAL(0);
  for (uint i = gl_GlobalInvocationID.x; i < 3u * nb; i += GROUP_SIZE * REDUCE_GROUPS) a += p[i] * ap[i];
  group_reduce2(a, REAL(0));
}
)";
}

std::string reduce_alpha(bool fp64) {
  return prelude(fp64) + kFinalReduce + R"(
void main() {
  final_reduce();
  if (gl_LocalInvocationID.x == 0u) {
    scalars[S_PAP] = red0[0];
    scalars[S_ALPHA] = red0[0] > REAL(0) ? scalars[S_RZ] / red0[0] : REAL(0);
  }
}
)";
}

std::string update(bool fp64) {
  return prelude(fp64) + R"(
void main() {
  REAL alpha = scalars[S_ALPHA];
  REAL rz = REAL(0), rr = REAL(0);
  for (uint I = gl_GlobalInvocationID.x; I < nb; I += GROUP_SIZE * REDUCE_GROUPS) {
    for (uint c = 0u; c < 3u; ++c) {
      uint i = 3u * I + c;
      x[i] += alpha * p[i];
      r[i] -= alpha * ap[i];
    }
    precondition(I);
    for (uint c = 0u; c < 3u; ++c) { uint i = 3u * I + c; rz += r[i] * z[i]; rr += r[i] * r[i]; }
  }
  group_reduce2(rz, rr);
}
)";
}

std::string reduce_beta(bool fp64) {
  return prelude(fp64) + kFinalReduce + R"(
void main() {
  final_reduce();
  if (gl_LocalInvocationID.x == 0u) {
    REAL rz_old = scalars[S_RZ];
    scalars[S_BETA] = rz_old != REAL(0) ? red0[0] / rz_old : REAL(0);
    scalars[S_RZ] = red0[0];
    scalars[S_RR] = red1[0];
  }
}
)";
}

std::string direction(bool fp64) {
  return prelude(fp64) + R"(
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= 3u * nb) return;
  p[i] = z[i] + scalars[S_BETA] * p[i];
}
)";
}

std::string start(bool fp64) {
  return prelude(fp64) + R"(
void main() {
  REAL rz = REAL(0), rr = REAL(0);
  for (uint I = gl_GlobalInvocationID.x; I < nb; I += GROUP_SIZE * REDUCE_GROUPS) {
    precondition(I);
    for (uint c = 0u; c < 3u; ++c) {
      uint i = 3u * I + c;
      x[i] = REAL(0);
      p[i] = z[i];
      rz += r[i] * z[i]; rr += r[i] * r[i];
    }
  }
  group_reduce2(rz, rr);
}
)";
}

std::string shift_cols() {
  return "#version 450 core\n" + cg_layout::glsl_defines(false) + R"(
layout(local_size_x = GROUP_SIZE) in;
layout(std430, binding = B_COL) buffer Col { uint col[]; };
uniform uint k_first;
uniform uint k_last;
uniform uint threshold;
uniform uint delta;  // two's complement: a removal wraps around
void main() {
  uint k = k_first + gl_GlobalInvocationID.x;
  if (k >= k_last) return;
  uint c = col[k];
  if (c >= threshold) col[k] = c + delta;
}
)";
}

}  // namespace cg_shaders
}  // namespace softcut::gpu
