#include "tools/path.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "core/error.hpp"

namespace softcut::tools {

Path Path::fixed_at(const Eigen::Vector3d& p) {
  Path r;
  r.kind = Kind::fixed;
  r.points = {p};
  r.times = {0.0};
  return r;
}

Path Path::polyline(std::vector<double> times, std::vector<Eigen::Vector3d> points) {
  Path r;
  r.kind = Kind::polyline;
  r.times = std::move(times);
  r.points = std::move(points);
  return r;
}

Path Path::catmull_rom(std::vector<double> times, std::vector<Eigen::Vector3d> points) {
  Path r = polyline(std::move(times), std::move(points));
  r.kind = Kind::catmull_rom;
  return r;
}

Path Path::arc(const Eigen::Vector3d& center, const Eigen::Vector3d& axis, const Eigen::Vector3d& start,
               double sweep, double t0, double t1) {
  Path r;
  r.kind = Kind::arc;
  r.center = center, r.axis = axis, r.start = start, r.sweep = sweep, r.t0 = t0, r.t1 = t1;
  return r;
}

void check_path(const Path& p, const std::string& where) {
  auto finite3 = [&](const Eigen::Vector3d& v, const char* field) {
    if (!v.allFinite()) fail(where, ": path field '", field, "' must be finite, got (", v.transpose(), ")");
  };
  switch (p.kind) {
    case Path::Kind::fixed:
      if (p.points.empty()) fail(where, ": fixed path needs one point");
      finite3(p.points[0], "points[1]");
      break;
    case Path::Kind::polyline:
    case Path::Kind::catmull_rom:
      if (p.points.empty()) fail(where, ": ", to_string(p.kind), " path needs at least one key");
      if (p.points.size() != p.times.size())
        fail(where, ": ", to_string(p.kind), " path has ", p.points.size(), " points but ", p.times.size(), " times");
      for (size_t k = 0; k < p.points.size(); ++k) {
        if (!p.points[k].allFinite() || !std::isfinite(p.times[k]))
          fail(where, ": path key ", k + 1, " is not finite");
        if (k > 0 && !(p.times[k] > p.times[k - 1]))
          fail(where, ": path times must increase (key ", k + 1, " at t = ", p.times[k], " after ", p.times[k - 1], ")");
      }
      break;
    case Path::Kind::arc:
      finite3(p.center, "center"), finite3(p.axis, "axis"), finite3(p.start, "start");
      if (!(p.axis.norm() > 0)) fail(where, ": arc path axis must be nonzero");
      if (!std::isfinite(p.sweep) || !std::isfinite(p.t0) || !std::isfinite(p.t1))
        fail(where, ": arc path sweep, t0, t1 must be finite");
      if (!(p.t1 > p.t0)) fail(where, ": arc path needs t1 > t0 (got t0 = ", p.t0, ", t1 = ", p.t1, ")");
      break;
  }
}

namespace {

// Index k with times[k] <= t < times[k+1]; callers clamp t to the key range first.
size_t segment(const std::vector<double>& T, double t) {
  const size_t k = size_t(std::upper_bound(T.begin(), T.end(), t) - T.begin());
  return std::min(k, T.size() - 1) - 1;
}

// Finite-difference tangent (m/s) at key k of a non-uniform Catmull-Rom spline.
Eigen::Vector3d tangent(const Path& p, size_t k) {
  const size_t n = p.points.size();
  const size_t a = k == 0 ? 0 : k - 1, b = k + 1 == n ? n - 1 : k + 1;
  return (p.points[b] - p.points[a]) / (p.times[b] - p.times[a]);
}

}  // namespace

Eigen::Vector3d evaluate(const Path& p, double t) {
  switch (p.kind) {
    case Path::Kind::fixed:
      return p.points.empty() ? Eigen::Vector3d::Zero() : p.points[0];
    case Path::Kind::polyline:
    case Path::Kind::catmull_rom: {
      if (p.points.empty()) return Eigen::Vector3d::Zero();
      if (p.points.size() == 1 || t <= p.times.front()) return p.points.front();
      if (t >= p.times.back()) return p.points.back();
      const size_t k = segment(p.times, t);
      const double h = p.times[k + 1] - p.times[k];
      const double s = (t - p.times[k]) / h;
      if (p.kind == Path::Kind::polyline) return p.points[k] + s * (p.points[k + 1] - p.points[k]);
      // Cubic Hermite basis on [0, 1]; tangents scaled by the segment length h.
      const double s2 = s * s, s3 = s2 * s;
      const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
      return h00 * p.points[k] + h10 * h * tangent(p, k) + h01 * p.points[k + 1] + h11 * h * tangent(p, k + 1);
    }
    case Path::Kind::arc: {
      const double s = std::clamp((t - p.t0) / (p.t1 - p.t0), 0.0, 1.0);
      const Eigen::AngleAxisd rot(s * p.sweep, p.axis.normalized());
      return p.center + rot * (p.start - p.center);
    }
  }
  return Eigen::Vector3d::Zero();
}

const char* to_string(Path::Kind k) {
  switch (k) {
    case Path::Kind::fixed: return "fixed";
    case Path::Kind::polyline: return "polyline";
    case Path::Kind::catmull_rom: return "catmull_rom";
    case Path::Kind::arc: return "arc";
  }
  return "?";
}

Path::Kind path_kind_from_string(const std::string& name, const std::string& where) {
  for (auto k : {Path::Kind::fixed, Path::Kind::polyline, Path::Kind::catmull_rom, Path::Kind::arc})
    if (name == to_string(k)) return k;
  fail(where, ": unknown path kind '", name, "' (use fixed, polyline, catmull_rom or arc)");
}

}  // namespace softcut::tools
