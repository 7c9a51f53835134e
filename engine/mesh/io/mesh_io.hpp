#pragma once
// Reading and writing tetrahedral meshes; the format is chosen by extension.
// Readers keep tets only (other element types are skipped and counted),
// keep region / physical tags as integer labels, and run validate() so every
// mesh that comes back is positively oriented and clean.
#include <filesystem>

#include "mesh/tet_mesh.hpp"

namespace softcut::mesh {

// .msh (Gmsh ASCII 1, 2.2, 4.1), .node/.ele (TetGen; either name), .mesh
// (medit), .vtk (legacy ASCII/BINARY), .vtu (XML ascii/base64/appended, zlib).
// Throws softcut::Error naming the file, the line or element, and what is
// wrong; warnings (skipped elements, flips, unused nodes) go to `diag`.
// What each reader accepts: docs/mesh-formats.md.
TetMesh read_mesh(const std::filesystem::path& path, Diagnostics& diag);

// .vtu or .msh (Gmsh 2.2 ASCII), atomically (temp + rename).
void write_mesh(const std::filesystem::path& path, const TetMesh& m);

}  // namespace softcut::mesh
