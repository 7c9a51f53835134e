#include "render/camera.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/error.hpp"

namespace softcut::render {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

bool finite(const Eigen::Vector3d& v) { return v.allFinite(); }

Eigen::Matrix4d look_at(const Eigen::Vector3d& eye, const Eigen::Vector3d& f, const Eigen::Vector3d& s,
                        const Eigen::Vector3d& u) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<1, 3>(0, 0) = s.transpose();
  m.block<1, 3>(1, 0) = u.transpose();
  m.block<1, 3>(2, 0) = -f.transpose();
  m(0, 3) = -s.dot(eye);
  m(1, 3) = -u.dot(eye);
  m(2, 3) = f.dot(eye);
  return m;
}

Eigen::Matrix4d perspective(double fov_y_rad, double aspect, double near, double far) {
  const double f = 1.0 / std::tan(0.5 * fov_y_rad);
  Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
  m(0, 0) = f / aspect;
  m(1, 1) = f;
  m(2, 2) = (far + near) / (near - far);
  m(2, 3) = 2.0 * far * near / (near - far);
  m(3, 2) = -1.0;
  return m;
}

}  // namespace

Eigen::Vector3d Camera::to_ndc(const Eigen::Vector3d& p) const {
  const Eigen::Vector4d clip = projection * view * p.homogeneous();
  return clip.head<3>() / clip.w();
}

Camera resolve_camera(const CameraSettings& cs, int width, int height, const std::vector<Eigen::Vector3d>& frame_in,
                      const std::vector<const std::vector<Eigen::Vector3f>*>& extent) {
  if (width < 1 || height < 1) fail("render: image size ", width, " x ", height, " must be at least 1 x 1 pixel");
  if (!(cs.fov_y_deg > 0.0 && cs.fov_y_deg < 180.0))
    fail("render camera: fov_y_deg = ", cs.fov_y_deg, " must lie in (0, 180) degrees");
  if (!finite(cs.up) || cs.up.norm() == 0.0) fail("render camera: `up` must be a finite, non-zero vector");
  // Nothing to frame: a 2 cm box around the origin.
  const std::vector<Eigen::Vector3d> frame =
      frame_in.empty() ? std::vector<Eigen::Vector3d>{Eigen::Vector3d::Constant(-0.01), Eigen::Vector3d::Constant(0.01)}
                       : frame_in;
  Eigen::Vector3d lo = frame.front(), hi = frame.front();
  for (const Eigen::Vector3d& p : frame) {
    if (!finite(p)) fail("render camera: a point of the model to frame is not finite");
    lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  }
  if ((hi - lo).norm() == 0.0) lo.array() -= 0.01, hi.array() += 0.01;
  Camera cam;
  cam.fov_y_deg = cs.fov_y_deg;
  cam.aspect = double(width) / double(height);
  const Eigen::Vector3d up = cs.up.normalized();
  if (cs.auto_frame) {
    if (!(cs.elevation_deg > -90.0 && cs.elevation_deg < 90.0))
      fail("render camera: elevation_deg = ", cs.elevation_deg, " must lie in (-90, 90) degrees");
    if (!(cs.margin > 0.0 && std::isfinite(cs.margin)) || !std::isfinite(cs.azimuth_deg))
      fail("render camera: margin must be positive and azimuth_deg finite");
    // Orbit frame: e1 is the world axis least aligned with `up`, made normal to it.
    int axis = 0;
    up.cwiseAbs().minCoeff(&axis);
    const Eigen::Vector3d e1 = (Eigen::Vector3d::Unit(axis) - up[axis] * up).normalized();
    const Eigen::Vector3d e2 = up.cross(e1);
    const double az = cs.azimuth_deg * kDeg, el = cs.elevation_deg * kDeg;
    const Eigen::Vector3d dir = std::cos(el) * (std::cos(az) * e1 + std::sin(az) * e2) + std::sin(el) * up;
    // The nearest eye distance along `dir` that keeps every point inside the
    // frustum shrunk by `margin`: for a point at offset q from the target,
    // screen |x| <= 1 needs d >= margin |q.s| / tan(half_x) - q.f (same in y).
    const Eigen::Vector3d f = -dir, s = f.cross(up).normalized(), u = s.cross(f);
    const double tan_y = std::tan(0.5 * cs.fov_y_deg * kDeg), tan_x = tan_y * cam.aspect;
    cam.target = 0.5 * (lo + hi);
    const double size = (hi - lo).norm();
    double d = 0.0;
    for (const Eigen::Vector3d& p : frame) {
      const Eigen::Vector3d q = p - cam.target;
      d = std::max(d, cs.margin * std::max(std::abs(q.dot(s)) / tan_x, std::abs(q.dot(u)) / tan_y) - q.dot(f));
      d = std::max(d, 0.05 * size - q.dot(f));  // every point well in front of the eye
    }
    cam.eye = cam.target + dir * d;
  } else {
    if (!finite(cs.eye) || !finite(cs.target)) fail("render camera: eye and target must be finite");
    if ((cs.eye - cs.target).norm() == 0.0) fail("render camera: eye and target coincide; move the eye back");
    cam.eye = cs.eye;
    cam.target = cs.target;
  }
  const Eigen::Vector3d f = (cam.target - cam.eye).normalized();
  const Eigen::Vector3d s_raw = f.cross(up);
  if (s_raw.norm() < 1e-9)
    fail("render camera: `up` is parallel to the view direction; choose another up or eye");
  const Eigen::Vector3d s = s_raw.normalized();
  cam.up = s.cross(f);
  cam.view = look_at(cam.eye, f, s, cam.up);

  // Near/far hug the content (the framed points and every vertex drawn), so
  // depth precision is spent where the model is.
  double dmin = std::numeric_limits<double>::infinity(), dmax = 0.0;
  auto depth = [&](const Eigen::Vector3d& p) {
    const double d = f.dot(p - cam.eye);
    dmin = std::min(dmin, d);
    dmax = std::max(dmax, d);
  };
  for (const Eigen::Vector3d& p : frame) depth(p);
  for (const auto* pts : extent)
    for (const Eigen::Vector3f& p : *pts) depth(p.cast<double>());
  if (!(dmax > 0.0)) dmax = (cam.target - cam.eye).norm() * 2.0;
  cam.far = dmax * 1.05;
  cam.near = std::max(dmin * 0.95, cam.far * 1e-4);
  cam.projection = perspective(cs.fov_y_deg * kDeg, cam.aspect, cam.near, cam.far);
  return cam;
}

}  // namespace softcut::render
