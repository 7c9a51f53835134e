#pragma once
// The surface a blade sweeps during one cut step, as a few triangles in the
// rest configuration, and the two geometric queries the cutter needs from it:
// where a mesh edge crosses it, and how far a point lies from it.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace softcut::cut {

struct SweptSurface {
  std::vector<Eigen::Matrix3d> triangles;  // each (3 x 3), one vertex per column, m
};

// Blade segment (a0, b0) moving to (a1, b1): the quad a0 b0 b1 a1 split along
// its diagonal a0-b1 into two triangles (a piecewise-planar stand-in for the
// bilinear patch; exact when the quad is planar). Degenerate triangles (no
// motion, zero-length blade) are dropped, so a blade at rest sweeps nothing.
// Non-finite coordinates throw softcut::Error.
SweptSurface sweep_segment(const Eigen::Vector3d& a0, const Eigen::Vector3d& b0,
                           const Eigen::Vector3d& a1, const Eigen::Vector3d& b1);

// A triangular blade (or a triangular patch of any sweep).
SweptSurface sweep_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& q,
                            const Eigen::Vector3d& r);

// Append the triangles of `more` to `s`.
void append(SweptSurface& s, const SweptSurface& more);

// Axis-aligned bounds of all triangles; empty surface -> min > max.
void bounds(const SweptSurface& s, Eigen::Vector3d& lo, Eigen::Vector3d& hi);

// Crossing of segment a-b with the surface: t in [0, 1] along a->b of the
// first triangle (in order) that the segment meets, or -1 when it meets none.
// A segment lying in a triangle's plane counts as not crossing (its end
// points are handled by snapping). `n_out` (optional) gets that triangle's
// unit normal.
double segment_crossing(const SweptSurface& s, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                        Eigen::Vector3d* n_out = nullptr);

// Euclidean distance from x to the nearest triangle (infinity when empty);
// `n_out` (optional) gets the unit normal of that triangle.
double distance(const SweptSurface& s, const Eigen::Vector3d& x, Eigen::Vector3d* n_out = nullptr);

// Distance from x to one triangle (columns = vertices).
double point_triangle_distance(const Eigen::Vector3d& x, const Eigen::Matrix3d& tri);

}  // namespace softcut::cut
