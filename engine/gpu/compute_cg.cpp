#include "gpu/compute_cg.hpp"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <cmath>
#include <cstring>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "core/timer.hpp"
#include "gpu/block_system_diff.hpp"
#include "gpu/cg_layout.hpp"
#include "gpu/cg_shaders.hpp"
#include "gpu/compute_program.hpp"

namespace softcut::gpu {
namespace L = cg_layout;

namespace {

// Device scalars are float or double; host data is double.
std::vector<unsigned char> to_device(const double* v, std::size_t n, bool fp64) {
  std::vector<unsigned char> out(n * (fp64 ? 8 : 4));
  if (fp64) {
    std::memcpy(out.data(), v, n * 8);
  } else {
    auto* f = reinterpret_cast<float*>(out.data());
    for (std::size_t i = 0; i < n; ++i) f[i] = float(v[i]);
  }
  return out;
}

std::vector<double> from_device(const std::vector<unsigned char>& bytes, bool fp64) {
  const std::size_t n = bytes.size() / (fp64 ? 8 : 4);
  std::vector<double> out(n);
  if (fp64) {
    std::memcpy(out.data(), bytes.data(), n * 8);
  } else {
    const auto* f = reinterpret_cast<const float*>(bytes.data());
    for (std::size_t i = 0; i < n; ++i) out[i] = f[i];
  }
  return out;
}

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

struct ComputeCg::Impl {
  std::shared_ptr<const CgKernels> kernels;  // shared; uniforms are set before each use
  bool fp64;
  const ComputeProgram &spmv, &dense, &dot_p_ap, &reduce_alpha, &update, &reduce_beta, &direction, &start, &shift;
  StorageBuffer buf[12];
  StorageBuffer scratch;  // staging for kept runs that move within a buffer
  BlockSystem cached;     // what the device holds (values in double)
  bool have_system = false;
  SystemUpload upload;    // what the last set_system did

  std::size_t scalar() const { return fp64 ? 8 : 4; }

  explicit Impl(std::shared_ptr<const CgKernels> k)
      : kernels(std::move(k)), fp64(kernels->fp64), spmv(kernels->spmv), dense(kernels->dense),
        dot_p_ap(kernels->dot_p_ap), reduce_alpha(kernels->reduce_alpha), update(kernels->update),
        reduce_beta(kernels->reduce_beta), direction(kernels->direction), start(kernels->start),
        shift(kernels->shift) {}

  void set_sizes() {
    for (const ComputeProgram* p : {&spmv, &dense, &dot_p_ap, &reduce_alpha, &update, &reduce_beta, &direction, &start}) {
      p->set_uint("nb", std::uint32_t(cached.num_blocks));
      p->set_uint("dense_off", std::uint32_t(cached.dense_offset));
      p->set_uint("dense_m", std::uint32_t(cached.dense_size));
    }
  }

  // Before dispatching: this system's buffers and sizes (the kernels may
  // have been used by another ComputeCg since).
  void prepare() {
    set_sizes();
    for (std::uint32_t b = 0; b < 12; ++b) buf[b].bind(b);
  }

  // Uploads only the runs of 9-value blocks (or dense rows) that differ.
  std::size_t upload_changed(StorageBuffer& dst, const std::vector<double>& old_v, const std::vector<double>& new_v,
                             std::size_t run) {
    std::size_t sent = 0;
    const std::size_t units = new_v.size() / run;
    std::size_t u = 0;
    while (u < units) {
      if (std::memcmp(&old_v[u * run], &new_v[u * run], run * sizeof(double)) == 0) {
        ++u;
        continue;
      }
      std::size_t e = u + 1;
      while (e < units && std::memcmp(&old_v[e * run], &new_v[e * run], run * sizeof(double)) != 0) ++e;
      const auto bytes = to_device(&new_v[u * run], (e - u) * run, fp64);
      dst.upload_range(u * run * scalar(), bytes.data(), bytes.size());
      sent += bytes.size();
      u = e;
    }
    return sent;
  }

  // Room for `bytes`, with 25% spare so that a growing system (cut after
  // cut) does not reallocate every time; contents are dropped when it grows.
  void reserve(StorageBuffer& b, std::size_t bytes) {
    if (b.capacity() < bytes || b.capacity() == 0) {
      b.allocate(bytes + bytes / 4);
      upload.reallocated = true;
    }
  }

  void upload_full(StorageBuffer& b, const void* data, std::size_t bytes) {
    reserve(b, bytes);
    b.upload_range(0, data, bytes);
    upload.sent_bytes += bytes;
  }

  // Turns the device array `b` into the new one (new_len units of `unit`
  // bytes). Kept runs that stay at their offset are left alone; the others
  // are staged through `scratch` (GL forbids overlapping copies within one
  // buffer, and runs may move either way), all read before any is written.
  // When the array outgrows its buffer, every run is copied into a fresh,
  // larger one instead. The gaps between runs are sent from the host,
  // `gap(first, count, out)` giving their bytes.
  template <class Gap>
  void apply_runs(StorageBuffer& b, std::size_t unit, std::size_t new_len,
                  const std::vector<BlockSystemDiff::Run>& runs, Gap gap) {
    if (new_len * unit > b.capacity()) {
      StorageBuffer grown;
      grown.allocate(new_len * unit + new_len * unit / 4);
      for (const auto& r : runs) grown.copy_from(b, r.from * unit, r.to * unit, r.count * unit);
      for (const auto& r : runs) upload.moved_bytes += r.count * unit;
      b = std::move(grown);
      upload.reallocated = true;
    } else {
      std::size_t staged = 0;
      for (const auto& r : runs) staged += r.from != r.to ? r.count * unit : 0;
      if (staged > 0) {
        if (scratch.capacity() < staged) scratch.allocate(staged + staged / 4);
        std::size_t at = 0;
        for (const auto& r : runs)
          if (r.from != r.to) {
            scratch.copy_from(b, r.from * unit, at, r.count * unit);
            at += r.count * unit;
          }
        at = 0;
        for (const auto& r : runs)
          if (r.from != r.to) {
            b.copy_from(scratch, at, r.to * unit, r.count * unit);
            at += r.count * unit;
          }
        upload.moved_bytes += staged;
      }
    }
    std::vector<unsigned char> bytes;
    std::size_t next = 0;  // first unit not yet written
    auto send = [&](std::size_t first, std::size_t count) {
      if (count == 0) return;
      gap(first, count, bytes);
      b.upload_range(first * unit, bytes.data(), bytes.size());
      upload.sent_bytes += bytes.size();
    };
    for (const auto& r : runs) {
      send(next, r.to - next);
      next = r.to + r.count;
    }
    send(next, new_len - next);
  }

  // Renumbers every block column of the old array on the device (kept runs
  // need it; the others are overwritten).
  void shift_cols(std::size_t count, const BlockSystemDiff& d) {
    if (count == 0) return;
    shift.set_uint("k_first", 0);
    shift.set_uint("k_last", std::uint32_t(count));
    shift.set_uint("threshold", d.col_threshold);
    shift.set_uint("delta", std::uint32_t(d.col_shift));  // modulo 2^32: negative shifts wrap
    buf[L::kCol].bind(L::kCol);
    shift.dispatch(groups_for(std::uint32_t(count)));
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);  // before the copies read it
  }

  // Bytes an incremental update sends (row_ptr whole, the gaps; dense as a full upload would).
  std::size_t incremental_bytes(const BlockSystem& s, const BlockSystemDiff& d) const {
    return 4 * s.row_ptr.size() + (s.col.size() - d.kept_blocks()) * (4 + 9 * scalar()) +
           (std::size_t(s.num_blocks) - d.kept_rows()) * 9 * scalar();
  }

  void set_incremental(const BlockSystem& s, const BlockSystemDiff& d) {
    upload_full(buf[L::kRowPtr], s.row_ptr.data(), 4 * s.row_ptr.size());
    if (d.col_shift != 0 && d.col_threshold < std::uint32_t(cached.num_blocks)) shift_cols(cached.col.size(), d);
    apply_runs(buf[L::kCol], 4, s.col.size(), d.blocks,
               [&](std::size_t first, std::size_t count, std::vector<unsigned char>& out) {
                 out.resize(4 * count);
                 std::memcpy(out.data(), s.col.data() + first, 4 * count);
               });
    apply_runs(buf[L::kValues], 9 * scalar(), s.col.size(), d.blocks,
               [&](std::size_t first, std::size_t count, std::vector<unsigned char>& out) {
                 out = to_device(s.values.data() + 9 * first, 9 * count, fp64);
               });
    apply_runs(buf[L::kDiagInv], 9 * scalar(), std::size_t(s.num_blocks), d.rows,
               [&](std::size_t first, std::size_t count, std::vector<unsigned char>& out) {
                 out = to_device(s.diag_inverse.data() + 9 * first, 9 * count, fp64);
               });
  }

  std::size_t set_system(const BlockSystem& s) {
    upload = {};
    upload.full_bytes = s.bytes(scalar());
    // K' stays when rows are inserted before it: only its offset (a uniform) moves.
    const bool same_dense = have_system && s.dense_size == cached.dense_size;
    const bool same_pattern =
        same_dense && s.dense_offset == cached.dense_offset && s.row_ptr == cached.row_ptr && s.col == cached.col;
    if (same_pattern) {
      upload.sent_bytes += upload_changed(buf[L::kValues], cached.values, s.values, 9);
      upload.sent_bytes += upload_changed(buf[L::kDiagInv], cached.diag_inverse, s.diag_inverse, 9);
    } else {
      bool incremental = false;
      if (have_system) {
        const BlockSystemDiff d = diff_block_systems(cached, s);
        const std::size_t dense_bytes = same_dense ? 0 : s.dense.size() * scalar();
        incremental = incremental_bytes(s, d) + dense_bytes < upload.full_bytes;
        if (incremental) set_incremental(s, d);
      }
      if (!incremental) {
        upload_full(buf[L::kRowPtr], s.row_ptr.data(), 4 * s.row_ptr.size());
        upload_full(buf[L::kCol], s.col.data(), 4 * s.col.size());
        auto v = to_device(s.values.data(), s.values.size(), fp64);
        upload_full(buf[L::kValues], v.data(), v.size());
        v = to_device(s.diag_inverse.data(), s.diag_inverse.size(), fp64);
        upload_full(buf[L::kDiagInv], v.data(), v.size());
      }
      upload.incremental = incremental;
      const std::size_t vec = std::size_t(s.size()) * scalar();
      for (auto b : {L::kX, L::kR, L::kP, L::kAp, L::kZ}) reserve(buf[b], vec);
      if (!have_system) {
        buf[L::kPartial].allocate(2 * L::kReduceGroups * scalar());
        const std::vector<double> zeros(L::kNumScalars, 0.0);
        const auto z = to_device(zeros.data(), zeros.size(), fp64);
        buf[L::kScalars].upload(z.data(), z.size());
      }
    }
    if (s.dense_size > 0) {
      if (same_dense) {
        upload.sent_bytes += upload_changed(buf[L::kDense], cached.dense, s.dense, std::size_t(s.dense_size));
      } else {
        const auto v = to_device(s.dense.data(), s.dense.size(), fp64);
        upload_full(buf[L::kDense], v.data(), v.size());
      }
    } else {
      reserve(buf[L::kDense], 16);
    }
    cached = s;
    have_system = true;
    set_sizes();
    return upload.sent_bytes;
  }

  double read_scalar(L::Scalar slot) const {
    std::vector<unsigned char> bytes(scalar());
    buf[L::kScalars].download(bytes.data(), bytes.size(), slot * scalar());
    return from_device(bytes, fp64)[0];
  }

  void spmv_p() {
    spmv.dispatch(groups_for(std::uint32_t(cached.num_blocks)));
    if (cached.dense_size > 0) {
      storage_barrier();
      dense.dispatch(groups_for(std::uint32_t(cached.dense_size)));
    }
    storage_barrier();
  }
};

std::shared_ptr<const CgKernels> compile_cg_kernels(EglContext& context, bool fp64) {
  context.make_current();
  const auto& info = context.info();
  if (!info.compute)
    fail("GPU solver: the OpenGL context (", info.summary(), ") has no compute shaders; use --backend cpu");
  return std::make_shared<const CgKernels>(fp64);
}

ComputeCg::ComputeCg(EglContext& context, ComputeCgOptions options)
    : ComputeCg(context, compile_cg_kernels(context, options.fp64), options) {}

ComputeCg::ComputeCg(EglContext& context, std::shared_ptr<const CgKernels> kernels, ComputeCgOptions options)
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

const SystemUpload& ComputeCg::last_upload() const { return impl_->upload; }

BlockSystem ComputeCg::device_system() const {
  if (!impl_->have_system) fail("GPU solver: device_system before set_system");
  context_.make_current();
  const Impl& m = *impl_;
  BlockSystem s;
  s.num_blocks = m.cached.num_blocks;
  s.dense_offset = m.cached.dense_offset;
  s.dense_size = m.cached.dense_size;
  s.row_ptr.resize(m.cached.row_ptr.size());
  m.buf[L::kRowPtr].download(s.row_ptr.data(), 4 * s.row_ptr.size());
  s.col.resize(m.cached.col.size());
  m.buf[L::kCol].download(s.col.data(), 4 * s.col.size());
  auto read = [&](L::Binding b, std::size_t count) {
    std::vector<unsigned char> bytes(count * m.scalar());
    m.buf[b].download(bytes.data(), bytes.size());
    return from_device(bytes, m.fp64);
  };
  s.values = read(L::kValues, m.cached.values.size());
  s.dense = read(L::kDense, m.cached.dense.size());
  s.diag_inverse = read(L::kDiagInv, m.cached.diag_inverse.size());
  return s;
}

void ComputeCg::apply_device(const Eigen::VectorXd& x, Eigen::VectorXd& y) {
  if (!impl_->have_system) fail("GPU solver: apply_device before set_system");
  Impl& m = *impl_;
  const int n = m.cached.size();
  if (x.size() != n) fail("GPU solver: vector of size ", x.size(), " for a system of size ", n);
  context_.make_current();
  m.prepare();
  const auto xb = to_device(x.data(), std::size_t(n), m.fp64);
  m.buf[L::kP].upload_range(0, xb.data(), xb.size());
  m.spmv_p();
  std::vector<unsigned char> yb(std::size_t(n) * m.scalar());
  m.buf[L::kAp].download(yb.data(), yb.size());
  const auto yd = from_device(yb, m.fp64);
  y = Eigen::Map<const Eigen::VectorXd>(yd.data(), n);
}

int ComputeCg::solve_device(const Eigen::VectorXd& r, Eigen::VectorXd& d, double tolerance) {
  if (!impl_->have_system) fail("GPU solver: solve before set_system");
  Impl& m = *impl_;
  const int n = m.cached.size();
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
  m.buf[L::kR].upload_range(0, rb.data(), rb.size());
  storage_barrier();
  m.start.dispatch(L::kReduceGroups);
  storage_barrier();
  m.reduce_beta.dispatch(1);  // rz, rr of the start residual (beta unused)
  storage_barrier();
  const double rr0 = m.read_scalar(L::kRr);
  if (!std::isfinite(rr0)) fail("GPU solver: the right-hand side has NaN or Inf entries");
  int it = 0;
  if (rr0 > 0) {
    const int max_it = opt_.max_inner_iterations > 0 ? opt_.max_inner_iterations : 10 * std::max(n, 10);
    const double goal = tolerance * tolerance * rr0;
    for (;;) {
      m.spmv_p();
      m.dot_p_ap.dispatch(L::kReduceGroups);
      storage_barrier();
      m.reduce_alpha.dispatch(1);
      storage_barrier();
      m.update.dispatch(L::kReduceGroups);
      storage_barrier();
      m.reduce_beta.dispatch(1);
      storage_barrier();
      ++it;
      if (it % opt_.check_every == 0 || it >= max_it) {
        const double rr = m.read_scalar(L::kRr);
        if (!std::isfinite(rr)) fail("GPU solver: the device iteration diverged (residual ", rr, ")");
        if (rr <= goal || it >= max_it) break;
      }
      m.direction.dispatch(groups_for(std::uint32_t(n)));
      storage_barrier();
    }
  }
  std::vector<unsigned char> xb(std::size_t(n) * m.scalar());
  m.buf[L::kX].download(xb.data(), xb.size());
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
  if (!impl_->have_system) fail("GPU solver: time_spmv before set_system");
  context_.make_current();
  impl_->prepare();
  glFinish();
  Timer t;
  for (int i = 0; i < repeats; ++i) impl_->spmv_p();
  glFinish();
  return t.seconds() / std::max(repeats, 1);
}

}  // namespace softcut::gpu
