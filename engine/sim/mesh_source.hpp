#pragma once
// The rest mesh of a scenario from its MeshSource: a file, a generator with
// named numeric options, or a mesh handed in by the caller.
#include <map>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "mesh/io/mesh_io.hpp"
#include "mesh/tet_mesh.hpp"
#include "sim/scenario_spec.hpp"

namespace softcut::sim {

struct LoadedMesh {
  mesh::TetMesh mesh;                                   // validated
  std::map<std::string, std::vector<int>> named_sets;   // e.g. "hole" (tube, upper_leg)
  std::string description;                              // "file liver.msh" / "generator tube"
};

constexpr double kNoTetLimit = 2147483647.0;  // int ids

// Generators: box, cylinder, tube, band, ligament (band preset), upper_leg
// (tube preset), the CGAL-meshed organs liver, kidney, knee_ligament
// (mesh/mesher/organs.hpp), and surface: the closed surfaces in
// src.surfaces (mesh/mesher/mesh_surface.hpp). A file's or a generator's
// body of implausible size (mesh/units.hpp) is a warning in `diag`. Options are the generator's option names; vectors as
// name.x / name.y / name.z. Throws naming the source and the bad option.
// A mesh over `max_tets` tetrahedra is refused: a generator's before it is
// allocated (the sandbox's bound on what a few bytes of script may ask for),
// a file's after reading (its memory is bounded by the file's size).
// A file is read as `read` allows (the sandbox: below the scenario folder,
// within its memory budget).
LoadedMesh load_mesh_source(const MeshSource& src, Diagnostics& diag, double max_tets = kNoTetLimit,
                            const mesh::ReadOptions& read = {});

// Option names a generator accepts (for messages and docs).
std::vector<std::string> generator_options(const std::string& generator);
// The value each of them has when not given (vectors as name.x ...).
std::map<std::string, double> generator_defaults(const std::string& generator);
// One line about an option (a vector by its base name, "fine_center"), with
// its unit, for `softcut mesh generate KIND --help`; "" for an unknown name.
std::string generator_option_help(const std::string& name);

}  // namespace softcut::sim
