#pragma once
// Tool trajectories: position of a tool tip (m) as a function of time (s).
// Deterministic; before the first key / after the last the end point is held.
#include <Eigen/Core>
#include <string>
#include <vector>

namespace softcut::tools {

struct Path {
  enum class Kind { fixed, polyline, catmull_rom, arc };
  Kind kind = Kind::fixed;

  // fixed: `points[0]` at every time.
  // polyline: straight segments between keys, constant speed on each.
  // catmull_rom: C1 cubic Hermite through every key, tangents
  //   (p[k+1] - p[k-1]) / (t[k+1] - t[k-1]) (one-sided at the ends), so the
  //   curve passes through each key at its time.
  std::vector<double> times;            // (nkey) s, strictly increasing
  std::vector<Eigen::Vector3d> points;  // (nkey) m

  // arc: `start` rotated about the line (center, axis) by an angle growing
  // linearly from 0 at t0 to `sweep` at t1 (right-hand rule about axis).
  // The radius is the distance of `start` from that line.
  Eigen::Vector3d center = Eigen::Vector3d::Zero();   // m
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();    // any length > 0
  Eigen::Vector3d start = Eigen::Vector3d::UnitX();   // m
  double sweep = 0.0;                                 // rad
  double t0 = 0.0, t1 = 1.0;                          // s, t1 > t0

  static Path fixed_at(const Eigen::Vector3d& p);
  static Path polyline(std::vector<double> times, std::vector<Eigen::Vector3d> points);
  static Path catmull_rom(std::vector<double> times, std::vector<Eigen::Vector3d> points);
  static Path arc(const Eigen::Vector3d& center, const Eigen::Vector3d& axis, const Eigen::Vector3d& start,
                  double sweep, double t0, double t1);
};

// Throws softcut::Error naming `where` for non-finite values, empty or
// unsorted keys, a zero axis, t1 <= t0.
void check_path(const Path& p, const std::string& where);

Eigen::Vector3d evaluate(const Path& p, double t);

const char* to_string(Path::Kind k);
Path::Kind path_kind_from_string(const std::string& name, const std::string& where);

}  // namespace softcut::tools
