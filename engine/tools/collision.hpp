#pragma once
// Contact between a tool tip (a sphere) and the CURRENT deformed boundary
// surface: which surface nodes the tool manipulates this frame.
#include <Eigen/Core>
#include <array>
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

// A point of the surface, bound to the three nodes of its triangle by
// barycentric weights (the usual embedded attachment): it moves with them,
// and a force on it acts on them in the same proportions.
struct SurfacePoint {
  std::array<int, 3> nodes{};                       // node ids of the triangle
  Eigen::Vector3d weights = Eigen::Vector3d::Zero(); // barycentric, >= 0, sum 1
  double share = 1;  // (0, 1]: this point's part of a patch's load, relative to the others
  Eigen::Vector3d at(const Eigen::MatrixX3d& positions) const;  // position, m
};

// The surface a jaw of `radius` closes on when its centre is at `center`
// (a grasper's patch): the surface point nearest the centre and a fixed
// pattern of points over the disc of that radius in the tangent plane there
// (rings at radius / 2 and radius, 6 and 12 points), each moved to the
// nearest surface point; samples that land more than radius / 2 away (past
// the body's edge) or on a face turned more than 60 degrees from the nearest
// face (a cut's wall, the back of a thin body) are dropped; then every
// surface node within `radius` of the nearest point, within radius / 2 of
// its tangent plane and with its normal within 60 degrees of that face's
// (weight 1 on itself). So the patch covers the jaw's area
// whatever the mesh: on coarse meshes the pattern spreads it over the
// triangles, on fine ones the jaw holds all the nodes under it (a load
// spread over an area, which converges as the mesh is refined), and a jaw
// smaller than the faces still holds the triangle under it. Empty when the
// surface is farther than `radius` from the centre. With `contact_circle`
// the disc is the circle the sphere cuts from the surface's tangent plane,
// radius sqrt(radius^2 - d^2) for the centre at distance d (a probe pressed
// in: its contact area), a single point when it just touches; its points
// then carry shares that fall to zero wherever a point would leave the patch
// (radially as Hertz's pressure sqrt(1 - (r/disc)^2) under a sphere; as
// (1 - u^2)^2 when a sample strays from its place or a node from the tangent
// plane; smoothly as a normal turns toward 60 degrees; normals interpolated
// from the vertices, so a point on an edge has one whichever face names it),
// so a probe's load moves continuously with the tissue: a point crossing the
// rim between two frames takes almost nothing with it (an equal split moved
// 1/n of the load at once, and 1e-15 of rounding could decide it).
std::vector<SurfacePoint> surface_patch(const ContactSurface& s, const Eigen::Vector3d& center, double radius,
                                        bool contact_circle = false);

// The nodes a set of surface points is bound to, sorted, each once.
std::vector<int> point_nodes(const std::vector<SurfacePoint>& points);

// The point of `surf` nearest to p (x: node positions), as a SurfacePoint;
// among faces as near (to 1e-12 relative) the one sharing most nodes with
// `prefer` (nodes with nonzero weight). `faces` limits the search (empty: all).
SurfacePoint nearest_surface_point(const Eigen::MatrixX3d& x, const mesh::Surface& surf, const Eigen::Vector3d& p,
                                   const SurfacePoint& prefer, const std::vector<int>& faces = {});

// Surface nodes whose deformed position lies within `radius` of the segment
// a-b (a capsule: the scalpel's contact), sorted by id. When none does (an
// edge passing between nodes), the nodes of the faces the capsule reaches.
std::vector<int> nodes_near_segment(const ContactSurface& s, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                    double radius);

// Distance from the segment a-b (a point when a == b) to the nearest face of
// the surface at `positions`, m (0 where it crosses a face; infinity for an
// empty surface). What a tool that never touched missed the tissue by.
double distance_to_surface(const ContactSurface& s, const Eigen::Vector3d& a, const Eigen::Vector3d& b);

// Closest point to p on the segment a-b.
Eigen::Vector3d closest_point_on_segment(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b);

// Closest point to p on triangle (a, b, c) (Ericson, Real-Time Collision
// Detection §5.1.5).
Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& b, const Eigen::Vector3d& c);

}  // namespace softcut::tools
