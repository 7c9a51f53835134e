#include "solve/newton.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"

namespace softcut::solve {

namespace {

enum class CgStatus { converged, negative_curvature, max_iterations };

// PCG on T d = r from d = 0 (see the header for how T p is formed);
// stops at |r - T d| <= target.
CgStatus pcg_step(const NewtonProblem& p, const Eigen::VectorXd& r, Eigen::VectorXd& d, double target,
                  int max_iterations, int& iterations) {
  const Eigen::Index n = r.size();
  d.setZero(n);
  Eigen::VectorXd rr = r, z, dir, Pdir, q(n), Dq(n);
  p.precondition(rr, z);
  dir = z;
  Pdir = rr;  // P dir = P z = rr
  double rz = rr.dot(z);
  for (int k = 0; k < max_iterations; ++k) {
    Dq.setZero();
    p.tangent_difference(dir, Dq);
    if (p.apply_base) {
      q.setZero();
      p.apply_base(dir, q);
      q += Dq;
    } else {
      q = Pdir + Dq;  // T dir
    }
    const double curvature = dir.dot(q);
    if (!(curvature > 0)) return CgStatus::negative_curvature;
    const double alpha = rz / curvature;
    d.noalias() += alpha * dir;
    rr.noalias() -= alpha * q;
    ++iterations;
    if (rr.norm() <= target) return CgStatus::converged;
    p.precondition(rr, z);
    const double rz_next = rr.dot(z);
    const double beta = rz_next / rz;
    rz = rz_next;
    dir = z + beta * dir;
    if (!p.apply_base) Pdir = rr + beta * Pdir;
  }
  return CgStatus::max_iterations;
}

// Newton from x, counting into rep: "" when it converged, else why not
// (what the caller's error says after `what`).
std::string newton_from(const NewtonProblem& p, Eigen::VectorXd& x, const NewtonOptions& opt, NewtonReport& rep) {
  Eigen::VectorXd r, d, xt, rt;
  double energy = p.residual(x, r);
  double rn = r.norm(), rn_before = HUGE_VAL;
  auto scale_at = [&](const Eigen::VectorXd& at) { return std::max(p.scale(at), 1e-300); };
  double scale = scale_at(x);
  auto too_large = [] {
    return "; the load or motion of this frame is too large for the mesh: apply it over more frames, refine the "
           "mesh, or lower the load";
  };
  for (;;) {
    if (!std::isfinite(rn))
      return cat(": the residual is not finite after ", rep.iterations, " Newton steps (an element degenerated?)");
    rep.relative_residual = rn / scale;
    if (rn == 0 || rep.relative_residual <= opt.tolerance) return {};
    const bool near_floor = rep.relative_residual <= opt.floor_tolerance;
    if (near_floor && rn > 0.5 * rn_before) {  // the last step stopped halving |r|: stagnation at the floor
      rep.at_floor = true;
      return {};
    }
    if (rep.iterations >= opt.max_iterations)
      return cat(": Newton's method did not converge in ", opt.max_iterations, " steps (relative residual ",
                 rep.relative_residual, ", tolerance ", opt.tolerance, "; ", rep.cg_iterations, " CG iterations, ",
                 rep.line_search_cuts, " step halvings)", too_large());
    // Never solved past what the tolerance needs: a tenth of it leaves room
    // for the step's quadratic error (bench nonlinear: a frame's last step
    // from 1.6e-7 took 17 PCG iterations to 1.6e-14, to 1e-11 it takes 11).
    const double target =
        std::max(std::min(opt.max_forcing, rep.relative_residual) * rn, 0.1 * opt.tolerance * scale);
    CgStatus status = pcg_step(p, r, d, target, opt.max_cg_iterations, rep.cg_iterations);
    if (status == CgStatus::negative_curvature) {
      ++rep.projected_steps;
      p.project();
      status = pcg_step(p, r, d, target, opt.max_cg_iterations, rep.cg_iterations);
      if (status == CgStatus::negative_curvature)
        return cat(": the tangent is not positive definite even with projected element tangents (step ",
                   rep.iterations + 1, "); is every part of the body held?");
    }
    // Backtracking: the full step first, halved until |r| or the energy
    // decreases (Armijo; the energy's slope along d is -r.d).
    const double slope = -r.dot(d);
    double alpha = 1;
    bool accepted = false;
    for (int k = 0; k <= opt.max_line_search; ++k) {
      xt = x + alpha * d;
      const double et = p.residual(xt, rt);
      const double rtn = rt.norm();
      const bool lower_residual = std::isfinite(rtn) && rtn <= (1 - 1e-4 * alpha) * rn;
      const bool lower_energy = std::isfinite(rtn) && std::isfinite(et) && std::isfinite(energy) && slope < 0 &&
                                et <= energy + 1e-4 * alpha * slope;
      if (lower_residual || lower_energy) {
        accepted = true;
        rn_before = rn;
        x.swap(xt);
        r.swap(rt);
        rn = rtn;
        energy = et;
        break;
      }
      alpha *= 0.5;
      ++rep.line_search_cuts;
    }
    ++rep.iterations;
    if (!accepted && near_floor) {  // no direction lowers |r| any more: at the floor
      rep.at_floor = true;
      return {};
    }
    if (!accepted)
      return cat(": Newton's line search found no decrease of the residual (step ", rep.iterations,
                 ", relative residual ", rn / scale, ")", too_large());
    scale = scale_at(x);
  }
}

}  // namespace

NewtonReport newton(const NewtonProblem& p, Eigen::VectorXd& x, const NewtonOptions& opt, const std::string& what,
                    const Eigen::VectorXd* start) {
  NewtonReport rep;
  if (start && start->size() == x.size() && x.size() > 0) {
    Eigen::VectorXd from = *start;
    if (newton_from(p, from, opt, rep).empty()) {
      x.swap(from);
      return rep;
    }
    // The prediction led Newton astray: from x, with the failed attempt's
    // work still counted.
    const NewtonReport failed = rep;
    rep = {};
    const std::string why = newton_from(p, x, opt, rep);
    rep.iterations += failed.iterations, rep.cg_iterations += failed.cg_iterations;
    rep.line_search_cuts += failed.line_search_cuts, rep.projected_steps += failed.projected_steps;
    if (!why.empty()) fail(what, why);
    return rep;
  }
  const std::string why = newton_from(p, x, opt, rep);
  if (!why.empty()) fail(what, why);
  return rep;
}

void SecantStart::clear() {
  increment_.resize(0);
  theta_ = 0;
  steady_ = 0;
}

const Eigen::VectorXd* SecantStart::predict(const Eigen::VectorXd& x) {
  if (increment_.size() != x.size() || x.size() == 0 || steady_ < 2) return nullptr;
  start_ = x + theta_ * increment_;
  return &start_;
}

void SecantStart::record(const Eigen::VectorXd& from, const Eigen::VectorXd& solution) {
  if (from.size() != solution.size()) {
    clear();
    return;
  }
  Eigen::VectorXd step = solution - from;
  if (increment_.size() == step.size()) {
    const double dd = increment_.squaredNorm();
    const double ratio = dd > 0 ? step.dot(increment_) / dd : 0.0;
    steady_ = ratio >= 0.5 && ratio <= 1.5 ? steady_ + 1 : 0;
    theta_ = std::clamp(ratio, 0.0, 1.0);
  }
  increment_.swap(step);
}

}  // namespace softcut::solve
