#include "gpu/compute_cg.hpp"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <cmath>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "core/timer.hpp"
#include "gpu/cg_layout.hpp"
#include "gpu/cg_shaders.hpp"
#include "gpu/compute_program.hpp"
#include "gpu/device_system.hpp"

namespace softcut::gpu {
namespace L = cg_layout;

namespace {
std::uint32_t groups_for(std::uint32_t items) { return (items + L::kGroupSize - 1) / L::kGroupSize; }
}  // namespace

struct CgKernels {
  bool fp64;
  ComputeProgram spmv, dense, dot_p_ap, reduce_alpha, update, reduce_beta, direction, start;
  ComputeProgram shift;  // renumbers kept block columns after rows were inserted or removed

  explicit CgKernels(bool fp64_) : fp64(fp64_) {
    namespace S = cg_shaders;
    spmv = ComputeProgram("cg.spmv", S::spmv(fp64));
    dense = ComputeProgram("cg.dense", S::dense(fp64));
    dot_p_ap = ComputeProgram("cg.dot_p_ap", S::dot_p_ap(fp64));
    reduce_alpha = ComputeProgram("cg.reduce_alpha", S::reduce_alpha(fp64));
    update = ComputeProgram("cg.update", S::update(fp64));
    reduce_beta = ComputeProgram("cg.reduce_beta", S::reduce_beta(fp64));
    direction = ComputeProgram("cg.direction", S::direction(fp64));
    start = ComputeProgram("cg.start", S::start(fp64));
    shift = ComputeProgram("cg.shift_cols", S::shift_cols());
  }
};

// One solver's device data: the system (DeviceSystem) and the CG vectors.
// The kernels are shared and hold nothing of it: every dispatch passes this
// system's sizes.
struct ComputeCg::Impl {
  std::shared_ptr<const CgKernels> kernels;
  bool fp64;
  DeviceSystem system;
  StorageBuffer x, r, p, ap, z, partial, scalars;  // at cg_layout's kX .. kScalars
  bool have_vectors = false;

  std::size_t scalar() const { return fp64 ? 8 : 4; }

  explicit Impl(std::shared_ptr<const CgKernels> k) : kernels(std::move(k)), fp64(kernels->fp64), system(fp64) {}

  // The sizes every kernel reads, as this system has them.
  void run(const ComputeProgram& kernel, std::uint32_t groups) const {
    const BlockSystem& s = system.host();
    kernel.dispatch(groups, {{"nb", std::uint32_t(s.num_blocks)}, {"dense_off", std::uint32_t(s.dense_offset)},
                             {"dense_m", std::uint32_t(s.dense_size)}});
  }

  // Before dispatching: this system's buffers at their binding points (the
  // kernels may have been used by another ComputeCg since).
  void prepare() const {
    system.bind();
    x.bind(L::kX), r.bind(L::kR), p.bind(L::kP), ap.bind(L::kAp), z.bind(L::kZ);
    partial.bind(L::kPartial), scalars.bind(L::kScalars);
  }

  std::size_t set_system(const BlockSystem& s) {
    const std::size_t sent = system.set(s, kernels->shift);
    const std::size_t vec = std::max<std::size_t>(std::size_t(s.size()) * scalar(), 16);
    for (StorageBuffer* b : {&x, &r, &p, &ap, &z})
      if (b->capacity() < vec) b->allocate(vec + vec / 4), system.note_reallocated();
    if (!have_vectors) {
      partial.allocate(2 * L::kReduceGroups * scalar());
      const std::vector<double> zeros(L::kNumScalars, 0.0);
      const auto bytes = to_device(zeros.data(), zeros.size(), fp64);
      scalars.upload(bytes.data(), bytes.size());
      have_vectors = true;
    }
    return sent;
  }

  double read_scalar(L::Scalar slot) const {
    std::vector<unsigned char> bytes(scalar());
    scalars.download(bytes.data(), bytes.size(), slot * scalar());
    return from_device(bytes, fp64)[0];
  }

  void spmv_p() const {
    const BlockSystem& s = system.host();
    run(kernels->spmv, groups_for(std::uint32_t(s.num_blocks)));
    if (s.dense_size > 0) {
      storage_barrier();
      run(kernels->dense, groups_for(std::uint32_t(s.dense_size)));
    }
    storage_barrier();
  }
};

std::shared_ptr<const CgKernels> compile_cg_kernels(gl::EglContext& context, bool fp64) {
  context.make_current();
  const auto& info = context.info();
  if (!info.compute)
    fail("GPU solver: the OpenGL context (", info.summary(), ") has no compute shaders; use --backend cpu");
  return std::make_shared<const CgKernels>(fp64);
}

ComputeCg::ComputeCg(gl::EglContext& context, ComputeCgOptions options)
    : ComputeCg(context, compile_cg_kernels(context, options.fp64), options) {}

ComputeCg::ComputeCg(gl::EglContext& context, std::shared_ptr<const CgKernels> kernels, ComputeCgOptions options)
    : opt_(options), context_(context) {
  if (!kernels || kernels->fp64 != options.fp64)
    fail("GPU solver: kernels of the wrong precision (fp64 = ", kernels && kernels->fp64, ") for fp64 = ", options.fp64);
  context_.make_current();
  impl_ = std::make_unique<Impl>(std::move(kernels));
}

ComputeCg::~ComputeCg() {
  if (!impl_) return;
  try {
    context_.make_current();  // the buffers are freed in it
  } catch (const Error&) {
    (void)impl_.release();  // current elsewhere: leave the buffers to the context (a destructor must not throw)
  }
}

std::size_t ComputeCg::set_system(const BlockSystem& system) {
  context_.make_current();
  return impl_->set_system(system);
}

const SystemUpload& ComputeCg::last_upload() const { return impl_->system.last_upload(); }

BlockSystem ComputeCg::device_system() const {
  context_.make_current();
  return impl_->system.read_back();
}

void ComputeCg::apply_device(const Eigen::VectorXd& x, Eigen::VectorXd& y) {
  if (!impl_->system.has_system()) fail("GPU solver: apply_device before set_system");
  Impl& m = *impl_;
  const int n = m.system.host().size();
  if (x.size() != n) fail("GPU solver: vector of size ", x.size(), " for a system of size ", n);
  context_.make_current();
  m.prepare();
  const auto xb = to_device(x.data(), std::size_t(n), m.fp64);
  m.p.upload_range(0, xb.data(), xb.size());
  m.spmv_p();
  std::vector<unsigned char> yb(std::size_t(n) * m.scalar());
  m.ap.download(yb.data(), yb.size());
  const auto yd = from_device(yb, m.fp64);
  y = Eigen::Map<const Eigen::VectorXd>(yd.data(), n);
}

int ComputeCg::solve_device(const Eigen::VectorXd& r, Eigen::VectorXd& d, double tolerance) {
  if (!impl_->system.has_system()) fail("GPU solver: solve before set_system");
  Impl& m = *impl_;
  const CgKernels& k = *m.kernels;
  const int n = m.system.host().size();
  if (r.size() != n) fail("GPU solver: right-hand side of size ", r.size(), " for a system of size ", n);
  if (opt_.check_every < 1) fail("GPU solver: check_every = ", opt_.check_every, " must be >= 1 (iterations)");
  // The device solves for r / scale: fp32 dot products of a tiny residual
  // (late refinements, micro-newton loads) underflow and those of a huge one
  // overflow; the system is linear, so d is scaled back at the end.
  const double scale = n > 0 ? r.cwiseAbs().maxCoeff() : 0.0;
  if (!std::isfinite(scale)) fail("GPU solver: the right-hand side has NaN or Inf entries");
  const Eigen::VectorXd r_unit = scale > 0 ? Eigen::VectorXd(r / scale) : r;
  context_.make_current();
  m.prepare();
  const auto rb = to_device(r_unit.data(), std::size_t(n), m.fp64);
  m.r.upload_range(0, rb.data(), rb.size());
  storage_barrier();
  m.run(k.start, L::kReduceGroups);
  storage_barrier();
  m.run(k.reduce_beta, 1);  // rz, rr of the start residual (beta unused)
  storage_barrier();
  const double rr0 = m.read_scalar(L::kRr);
  if (!std::isfinite(rr0)) fail("GPU solver: the right-hand side has NaN or Inf entries");
  int it = 0;
  if (rr0 > 0) {
    const int max_it = opt_.max_inner_iterations > 0 ? opt_.max_inner_iterations : 10 * std::max(n, 10);
    const double goal = tolerance * tolerance * rr0;
    for (;;) {
      m.spmv_p();
      m.run(k.dot_p_ap, L::kReduceGroups);
      storage_barrier();
      m.run(k.reduce_alpha, 1);
      storage_barrier();
      m.run(k.update, L::kReduceGroups);
      storage_barrier();
      m.run(k.reduce_beta, 1);
      storage_barrier();
      ++it;
      if (it % opt_.check_every == 0 || it >= max_it) {
        const double rr = m.read_scalar(L::kRr);
        if (!std::isfinite(rr)) fail("GPU solver: the device iteration diverged (residual ", rr, ")");
        if (rr <= goal || it >= max_it) break;
      }
      m.run(k.direction, groups_for(std::uint32_t(n)));
      storage_barrier();
    }
  }
  std::vector<unsigned char> xb(std::size_t(n) * m.scalar());
  m.x.download(xb.data(), xb.size());
  const auto xd = from_device(xb, m.fp64);
  d = scale * Eigen::Map<const Eigen::VectorXd>(xd.data(), n);
  if (rr0 == 0) d.setZero();
  return it;
}

ComputeCgReport ComputeCg::solve(const solve::LinearOperator& exact, const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  const Eigen::Index n = b.size();
  if (x.size() != n) x = Eigen::VectorXd::Zero(n);
  if (!b.allFinite()) fail("GPU solver: the right-hand side has NaN or Inf entries");
  ComputeCgReport rep;
  const double bnorm = b.norm();
  if (bnorm == 0) {
    x.setZero();
    rep.converged = true;
    return rep;
  }
  const double inner = opt_.inner_tolerance > 0 ? opt_.inner_tolerance : (opt_.fp64 ? opt_.tolerance / 10 : 1e-4);
  Eigen::VectorXd Ax(n), r(n), d;
  double last = INFINITY;
  for (;;) {
    exact(x, Ax);
    r = b - Ax;
    rep.relative_residual = r.norm() / bnorm;
    if (rep.relative_residual <= opt_.tolerance) {
      rep.converged = true;
      break;
    }
    // Refinement stalls when fp32 cannot resolve the correction any more.
    if (rep.refinements >= opt_.max_refinements || !(rep.relative_residual < last)) break;
    last = rep.relative_residual;
    rep.iterations += solve_device(r, d, inner);
    x += d;
    ++rep.refinements;
  }
  return rep;
}

double ComputeCg::time_spmv(int repeats) {
  if (!impl_->system.has_system()) fail("GPU solver: time_spmv before set_system");
  context_.make_current();
  impl_->prepare();
  glFinish();
  Timer t;
  for (int i = 0; i < repeats; ++i) impl_->spmv_p();
  glFinish();
  return t.seconds() / std::max(repeats, 1);
}

}  // namespace softcut::gpu
