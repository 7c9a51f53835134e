// Surface files through CGAL's readers. CGAL IO is header-only templates, but
// light next to Mesh_3: only this file includes it.
#include <CGAL/IO/OBJ.h>
#include <CGAL/IO/OFF.h>
#include <CGAL/IO/PLY.h>
#include <CGAL/IO/STL.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <cctype>
#include <new>
#include <sstream>
#include <vector>

#include "core/printable.hpp"
#include "mesh/io/formats.hpp"
#include "mesh/io/surface_io.hpp"
#include "mesh/io/surface_scan.hpp"

namespace softcut::mesh {

namespace {

using Point = CGAL::Simple_cartesian<double>::Point_3;
using Polygon = std::vector<std::size_t>;

std::string lower_extension(const std::filesystem::path& p) {
  std::string e = p.extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return e;
}

SurfaceSoup read_unescaped(const std::string& source, const std::string& ext, std::string_view bytes, Diagnostics& diag) {
  if (ext == ".stl") io::scan_stl(source, bytes);
  else if (ext == ".off") io::scan_off(source, bytes);
  else if (ext == ".ply") io::scan_ply(source, bytes);
  else if (ext != ".obj")
    fail(source, ": unknown surface file extension '", ext, "'; supported: ", surface_extensions());
  std::vector<Point> points;
  std::vector<Polygon> polygons;
  bool ok = false;
  try {
    std::istringstream in{std::string(bytes), std::ios::in | std::ios::binary};
    if (ext == ".stl") ok = CGAL::IO::read_STL(in, points, polygons);
    else if (ext == ".obj") ok = CGAL::IO::read_OBJ(in, points, polygons);
    else if (ext == ".ply") ok = CGAL::IO::read_PLY(in, points, polygons);
    else ok = CGAL::IO::read_OFF(in, points, polygons);
  } catch (const std::bad_alloc&) {
    fail(source, ": out of memory while reading the surface (", bytes.size(), " bytes)");
  } catch (const std::exception& e) {  // CGAL's failed preconditions throw
    fail(source, ": cannot read the surface: ", e.what());
  }
  if (!ok) {
    // An empty OBJ is "not read"; say empty, as for the others.
    if (points.empty() && polygons.empty() && ext == ".obj" &&
        std::all_of(bytes.begin(), bytes.end(), [](char c) { return std::isspace(static_cast<unsigned char>(c)); }))
      fail(source, ": the file is empty: no triangles to mesh");
    fail(source, ": not a readable ", ext.substr(1), " surface (CGAL's reader stopped; the file is truncated or "
         "malformed, or holds no faces)");
  }
  if (polygons.empty()) fail(source, ": the file holds no faces: no surface to mesh (", points.size(), " points)");
  std::size_t triangles = 0, split = 0;
  for (std::size_t f = 0; f < polygons.size(); ++f) {
    const Polygon& p = polygons[f];
    if (p.size() < 3) fail(source, ": face ", f, " has ", p.size(), " vertices; a face needs at least 3");
    for (const std::size_t i : p)
      if (i >= points.size())
        fail(source, ": face ", f, " uses point ", i, " but the file has ", points.size(), " points (ids from 0; OBJ from 1)");
    triangles += p.size() - 2;
    split += p.size() > 3;
    if (triangles > std::size_t(kMaxSurfaceTriangles))
      fail(source, ": more than ", kMaxSurfaceTriangles, " triangles; decimate the surface first (3D Slicer: Surface "
           "Toolbox, decimate) - an organ needs far fewer");
  }
  SurfaceSoup out;
  out.source = source;
  out.points.resize(Eigen::Index(points.size()), 3);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Point& q = points[i];
    if (!std::isfinite(q.x()) || !std::isfinite(q.y()) || !std::isfinite(q.z()))
      fail(source, ": point ", i, " has a coordinate that is not a finite number");
    out.points.row(Eigen::Index(i)) << q.x(), q.y(), q.z();
  }
  out.triangles.resize(Eigen::Index(triangles), 3);
  Eigen::Index t = 0;
  std::vector<char> used(points.size(), 0);
  for (const Polygon& p : polygons)
    for (std::size_t k = 1; k + 1 < p.size(); ++k) {  // a fan: exact for the convex polygons exporters write
      out.triangles.row(t++) << int(p[0]), int(p[k]), int(p[k + 1]);
      used[p[0]] = used[p[k]] = used[p[k + 1]] = 1;
    }
  if (split > 0) diag.warn(source, ": ", split, " faces with more than 3 vertices were split into triangles (fans)");
  if (const auto unused = std::count(used.begin(), used.end(), 0); unused > 0)
    diag.warn(source, ": ", unused, " points are used by no face (ignored)");
  return out;
}

}  // namespace

const char* surface_extensions() { return ".stl (ASCII or binary), .obj, .ply (ASCII or binary) or .off (ASCII)"; }

bool is_surface_file(const std::filesystem::path& path) {
  const std::string e = lower_extension(path);
  return e == ".stl" || e == ".obj" || e == ".ply" || e == ".off";
}

SurfaceSoup read_surface_bytes(const std::string& source, const std::string& ext, std::string_view bytes,
                               Diagnostics& diag) {
  // Messages quote the file's bytes: escaped, like read_mesh's.
  try {
    return read_unescaped(source, ext, bytes, diag);
  } catch (const Error& e) {
    throw Error(printable(e.what(), 4000));
  }
}

SurfaceSoup read_surface(const std::filesystem::path& path, Diagnostics& diag, const ReadOptions& opt) {
  const std::string ext = lower_extension(path);
  if (!is_surface_file(path))
    fail(printable(path.string()), ": unknown surface file extension '", printable(path.extension().string()),
         "'; supported: ", surface_extensions());
  // CGAL's soup takes up to ~4x the file (a point map, a vector per face).
  ReadOptions file = opt;
  file.max_bytes = opt.max_bytes / 4;
  const std::string bytes = io::read_file(path, file);
  return read_surface_bytes(path.string(), ext, bytes, diag);
}

}  // namespace softcut::mesh
