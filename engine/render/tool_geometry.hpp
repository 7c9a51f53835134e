#pragma once
// Tool shapes as plain data and their tessellation into triangles.
#include <Eigen/Core>
#include <variant>

#include "render/primitives.hpp"

namespace softcut::render {

// A ball-tipped rod: a steel sphere of `radius` at `tip`, a dark shaft of
// radius/2 from the tip along `axis` (towards the handle) for `length`.
struct ProbeShape {
  Eigen::Vector3d tip{0, 0, 0};       // m
  Eigen::Vector3d axis{0, 0, 1};      // direction from tip to handle (normalised here)
  double radius = 0.002, length = 0.04;  // m
};

// A laparoscopic grasper: two steel jaws hinged at `pivot`, each jaw_length
// long, jaw_width wide at the hinge tapering to half that at its tip and
// jaw_width/3 thick, opened by +-opening_deg/2 about `hinge` from `axis`
// (closed: they meet along the axis); a steel clevis across the hinge (a
// cylinder of diameter jaw_width); a dark round shaft of diameter jaw_width
// from the pivot backwards (-axis) for shaft_length.
struct GrasperShape {
  Eigen::Vector3d pivot{0, 0, 0};   // m
  Eigen::Vector3d axis{0, 0, -1};   // direction the closed jaws point to
  Eigen::Vector3d hinge{1, 0, 0};   // hinge axis, normal to `axis`
  double opening_deg = 30.0;
  double jaw_length = 0.01, jaw_width = 0.003, shaft_length = 0.04;  // m
};

// A scalpel: a steel blade, thin at its spine and sharp at its edge (the
// cutting edge edge_a-edge_b, the spine corner thickened across the blade's
// plane), and a flat dark handle from the spine to handle_end, handle_radius
// x 3 wide in the blade's plane and handle_radius x 1.2 thick.
struct ScalpelShape {
  Eigen::Vector3d edge_a{0, 0, 0}, edge_b{0.01, 0, 0};  // m
  Eigen::Vector3d spine{0, 0, 0.005};                     // m
  Eigen::Vector3d handle_end{0, 0, 0.05};                 // m
  double handle_radius = 0.0015;                          // m
};

using ToolShape = std::variant<ProbeShape, GrasperShape, ScalpelShape>;

// Appends the triangles of one tool, the steel parts in `steel` and shafts
// and handles in `dark`; returns how many it added.
int add_tool(Triangles& out, const ToolShape& tool, int segments, const Rgba& steel, const Rgba& dark);
// The same in one colour.
int add_tool(Triangles& out, const ToolShape& tool, int segments, const Rgba& color);

// Triangle counts of the tool tessellations for `segments` facets around.
int sphere_triangles(int segments);
int cylinder_triangles(int segments);  // side plus both caps

}  // namespace softcut::render
