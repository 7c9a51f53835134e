#pragma once
// Contact between a tool tip (a sphere) and the CURRENT deformed boundary
// surface: which surface nodes the tool manipulates this frame.
#include <Eigen/Core>
#include <vector>

#include "mesh/surface.hpp"

namespace softcut::tools {

// What a tool may touch this frame; references stay owned by the caller.
struct ContactSurface {
  const Eigen::MatrixX3d& positions;  // (nnode x 3) deformed positions, m
  const mesh::Surface& surface;       // boundary faces (node ids) of the body
  const Eigen::MatrixX3d& normals;    // (nnode x 3) unit outward normals at `positions`
};

// Surface nodes whose deformed position lies within `radius` of `center`,
// sorted by id. When none does but the sphere cuts a surface triangle (tip
// smaller than the faces), the three nodes of the nearest such triangle.
// Empty when the sphere misses the surface.
std::vector<int> nodes_in_sphere(const ContactSurface& s, const Eigen::Vector3d& center, double radius);

// Surface nodes whose deformed position lies within `radius` of the segment
// a-b (a capsule: the scalpel's contact), sorted by id. When none does (an
// edge passing between nodes), the nodes of the faces the capsule reaches.
std::vector<int> nodes_near_segment(const ContactSurface& s, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                    double radius);

// Closest point to p on the segment a-b.
Eigen::Vector3d closest_point_on_segment(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b);

// Closest point to p on triangle (a, b, c) (Ericson, Real-Time Collision
// Detection §5.1.5).
Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& b, const Eigen::Vector3d& c);

}  // namespace softcut::tools
