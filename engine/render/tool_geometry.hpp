#pragma once
// Tool shapes as plain data and their tessellation into triangles.
#include <Eigen/Core>
#include <variant>

#include "render/primitives.hpp"

namespace softcut::render {

// A ball-tipped rod: sphere of `radius` at `tip`, shaft of radius/2 from the
// tip along `axis` (towards the handle) for `length`.
struct ProbeShape {
  Eigen::Vector3d tip{0, 0, 0};       // m
  Eigen::Vector3d axis{0, 0, 1};      // direction from tip to handle (normalised here)
  double radius = 0.002, length = 0.04;  // m
};

// Two jaws hinged at `pivot`, each a box jaw_length x jaw_width x jaw_width/3,
// opened by +-opening_deg/2 about `hinge` from `axis`; a round shaft of
// diameter jaw_width runs from the pivot backwards (-axis) for shaft_length.
struct GrasperShape {
  Eigen::Vector3d pivot{0, 0, 0};   // m
  Eigen::Vector3d axis{0, 0, -1};   // direction the closed jaws point to
  Eigen::Vector3d hinge{1, 0, 0};   // hinge axis, normal to `axis`
  double opening_deg = 30.0;
  double jaw_length = 0.01, jaw_width = 0.003, shaft_length = 0.04;  // m
};

// A blade triangle (the cutting edge edge_a-edge_b plus the spine corner,
// drawn from both sides) and a round handle from the spine to handle_end.
struct ScalpelShape {
  Eigen::Vector3d edge_a{0, 0, 0}, edge_b{0.01, 0, 0};  // m
  Eigen::Vector3d spine{0, 0, 0.005};                     // m
  Eigen::Vector3d handle_end{0, 0, 0.05};                 // m
  double handle_radius = 0.0015;                          // m
};

using ToolShape = std::variant<ProbeShape, GrasperShape, ScalpelShape>;

// Appends the triangles of one tool; returns how many it added.
int add_tool(Triangles& out, const ToolShape& tool, int segments, const Rgba& color);

// Triangle counts of the tool tessellations for `segments` facets around.
int sphere_triangles(int segments);
int cylinder_triangles(int segments);  // side plus both caps

}  // namespace softcut::render
