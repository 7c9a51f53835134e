#pragma once
// Reading and writing tetrahedral meshes; the format is chosen by extension.
// Readers keep tets only (other element types are skipped and counted),
// keep region / physical tags as integer labels, and run validate() so every
// mesh that comes back is positively oriented and clean.
#include <cstddef>
#include <filesystem>
#include <limits>

#include "mesh/tet_mesh.hpp"

namespace softcut::mesh {

// How a mesh file (and the sibling file of a two-file format) may be read.
struct ReadOptions {
  // Not empty: every file is opened below this folder only, through the
  // checked open (core/checked_file.hpp: no symlinks, regular files only);
  // the sandbox sets it to the scenario's folder.
  std::filesystem::path root;
  // Bytes a file and each decoded array (base64, zlib) may take; the sandbox
  // sets what is left of its memory budget.
  std::size_t max_bytes = std::numeric_limits<std::size_t>::max();
};

// .msh (Gmsh ASCII 1, 2.2, 4.1), .node/.ele (TetGen; either name), .mesh
// (medit), .vtk (legacy ASCII/BINARY), .vtu (XML ascii/base64/appended, zlib).
// Throws softcut::Error naming the file, the line or element, and what is
// wrong; warnings (skipped elements, flips, unused nodes) go to `diag`.
// What each reader accepts: docs/mesh-formats.md.
TetMesh read_mesh(const std::filesystem::path& path, Diagnostics& diag, const ReadOptions& opt = {});

// .vtu or .msh (Gmsh 2.2 ASCII), atomically (temp + rename).
void write_mesh(const std::filesystem::path& path, const TetMesh& m);

}  // namespace softcut::mesh
