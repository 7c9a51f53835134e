#pragma once
// Mesh files carry no unit; softcut works in metres. These say what a file's
// unit is worth, guess one from a body's size, and warn when a body's size is
// implausible for an organ (the usual sign of a file in millimetres read as
// metres: a 19 cm liver becomes 190 m across and a probe never reaches it).
#include <Eigen/Geometry>
#include <string>

#include "core/error.hpp"
#include "mesh/tet_mesh.hpp"

namespace softcut::mesh {

// Organs, vessels and lesions span about 1 mm to 1 m (the largest side of
// their bounding box).
inline constexpr double kPlausibleMinSize = 1e-3, kPlausibleMaxSize = 1.0;  // m

// The units a mesh may be given in, for messages: "m, cm, mm or um".
const char* known_units();

// Metres per `unit` ("m" 1, "cm" 0.01, "mm" 0.001, "um" 1e-6); fails naming
// `what` ("option --unit", "scenario.lua:3: mesh") for any other text.
double unit_metres(const std::string& unit, const std::string& what);

// The unit a surface or mesh in unknown units most likely uses, from the
// largest side of its bounding box in the file's numbers: "m" up to 1,
// "mm" up to 1000 (most CT / 3D Slicer / ITK-SNAP exports), "um" up to 1e6.
// Fails naming `what` when no unit makes the size plausible (asking for one).
std::string guess_unit(double largest_side, const std::string& what);

// Warns (code implausible_size) when the largest side of `box` (m) is over
// kPlausibleMaxSize or under kPlausibleMinSize, naming `what`, the size, and
// the unit (or scale) that would make it an organ's. Returns whether it warned.
bool check_plausible_size(const Eigen::AlignedBox3d& box, const std::string& what, Diagnostics& diag);

// The bounding box of the nodes (empty for no nodes).
Eigen::AlignedBox3d bounding_box(const TetMesh& m);

// Every node times `factor` (> 0 and finite, else fails naming `what`).
void scale_nodes(TetMesh& m, double factor, const std::string& what);

}  // namespace softcut::mesh
