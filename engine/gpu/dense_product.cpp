#include "gpu/dense_product.hpp"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include "core/error.hpp"

namespace softcut::gpu {
namespace {

constexpr unsigned kGroup = 64;

const char* kSource = R"(#version 450 core
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer M { double m[]; };
layout(std430, binding = 1) readonly buffer X { double x[]; };
layout(std430, binding = 2) writeonly buffer Y { double y[]; };
uniform uint rows;
uniform uint cols;
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= rows) return;
  double s = 0.0;
  uint o = i * cols;
  for (uint j = 0u; j < cols; ++j) s += m[o + j] * x[j];
  y[i] = s;
}
)";

}  // namespace

DeviceDenseProduct::DeviceDenseProduct(gl::EglContext& context, const Eigen::MatrixXd& matrix)
    : context_(context), rows_(int(matrix.rows())), cols_(int(matrix.cols())) {
  context_.make_current();
  if (!context_.info().compute)
    fail("GPU nonoperational product: the OpenGL context (", context_.info().summary(), ") has no compute shaders");
  program_ = ComputeProgram("nonoperational product", kSource);  // GL 4.0+ core has doubles
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rm = matrix;
  matrix_.upload(rm.data(), sizeof(double) * size_t(rm.size()));
  x_.upload(nullptr, sizeof(double) * size_t(cols_));
  y_.upload(nullptr, sizeof(double) * size_t(rows_));
}

DeviceDenseProduct::~DeviceDenseProduct() {
  try {
    context_.make_current();  // the buffers are freed in it
  } catch (const Error&) {
    // Current on another thread: the buffers' handles belong to the context,
    // which frees them with itself (a destructor must not throw).
    matrix_.release(), x_.release(), y_.release(), program_.release();
  }
}

void DeviceDenseProduct::apply(const Eigen::VectorXd& x, Eigen::VectorXd& y) {
  if (x.size() != cols_)
    fail("GPU nonoperational product: AI has ", x.size(), " entries for a matrix with ", cols_, " columns");
  context_.make_current();
  y.resize(rows_);
  if (rows_ == 0) return;
  x_.upload_range(0, x.data(), sizeof(double) * size_t(cols_));
  matrix_.bind(0);
  x_.bind(1);
  y_.bind(2);
  storage_barrier();
  program_.dispatch((unsigned(rows_) + kGroup - 1) / kGroup, {{"rows", unsigned(rows_)}, {"cols", unsigned(cols_)}});
  storage_barrier();
  y_.download(y.data(), sizeof(double) * size_t(rows_));
}

}  // namespace softcut::gpu
