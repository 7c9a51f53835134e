#pragma once
// Triangulated surfaces as users have them (an STL or OBJ exported from 3D
// Slicer or ITK-SNAP, a PLY from a scan, an OFF from a paper's data set),
// read with CGAL's own readers (CGAL::IO::read_STL / read_OBJ / read_PLY /
// read_OFF, CGAL 5.5) from the bytes softcut's checked open read, after a
// structure scan that bounds what those readers allocate (surface_scan.hpp).
// What the surfaces must be to be meshed (closed, oriented, not
// self-intersecting) is checked by mesh/mesher/surface_domain.hpp.
#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <string_view>

#include "core/error.hpp"
#include "mesh/io/mesh_io.hpp"

namespace softcut::mesh {

struct SurfaceSoup {
  std::string source;          // file name, for messages
  Eigen::MatrixX3d points;     // (npoint x 3) in the file's unit
  Eigen::MatrixX3i triangles;  // (ntri x 3) point ids (polygons split into fans)
};

// Surfaces of more triangles are refused (a segmentation's surface has
// 1e4..1e6; meshing 1e7 would take hours).
inline constexpr int kMaxSurfaceTriangles = 10'000'000;

// ".stl, .obj, .ply or .off", for messages; whether `path` has one of them.
const char* surface_extensions();
bool is_surface_file(const std::filesystem::path& path);

// Reads a surface file by extension (.stl ASCII or binary, .obj, .ply ASCII
// or binary, .off ASCII), through the checked open as `opt` allows. Fails
// naming the file and what is wrong: unreadable, empty, a face index out of
// range, a coordinate that is not finite, too many triangles. Warnings (faces
// that are not triangles, points no face uses) go to `diag`.
SurfaceSoup read_surface(const std::filesystem::path& path, Diagnostics& diag, const ReadOptions& opt = {});

// The same from bytes in memory; `ext` is ".stl", ".obj", ".ply" or ".off".
SurfaceSoup read_surface_bytes(const std::string& source, const std::string& ext, std::string_view bytes,
                               Diagnostics& diag);

}  // namespace softcut::mesh
