// Checks and labels a user's closed surfaces with CGAL's Polygon Mesh
// Processing (merging points, orienting, self-intersections) and AABB trees
// (which piece lies inside which). Lighter than Mesh_3, but CGAL all the
// same: only this file (and mesh_surface.cpp) include it.
#include "mesh/mesher/surface_domain.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <numeric>

#include "core/warning.hpp"

namespace softcut::mesh {

namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using Polygon = std::vector<std::size_t>;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
using Side = CGAL::Side_of_triangle_mesh<SurfaceMesh, K>;

// "(12.5, -3, 40.25)": a point in the file's unit, for messages.
std::string at(const Point& p) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.6g, %.6g, %.6g)", p.x(), p.y(), p.z());
  return buf;
}

// Counts the faces orient_polygon_soup turns, per polygon, and remembers a
// point where pieces meet at a single vertex.
struct OrientVisitor : PMP::Default_orientation_visitor {
  std::vector<char>* reversed;
  std::size_t* singular;
  void polygon_orientation_reversed(std::size_t p) { (*reversed)[p] = !(*reversed)[p]; }
  void non_manifold_vertex(std::size_t v, std::size_t) {
    if (*singular == std::size_t(-1)) *singular = v;
  }
};

// Thrown out of PMP::self_intersections at the first pair: one is enough to report.
struct FirstPair {
  std::size_t a, b;
};
struct StopAtFirst {
  using iterator_category = std::output_iterator_tag;
  using value_type = void;
  using difference_type = std::ptrdiff_t;
  using pointer = void;
  using reference = void;
  StopAtFirst& operator*() { return *this; }
  StopAtFirst& operator++() { return *this; }
  StopAtFirst operator++(int) { return *this; }
  template <class Pair>
  StopAtFirst& operator=(const Pair& p) {
    throw FirstPair{std::size_t(p.first), std::size_t(p.second)};
  }
};

// Connected pieces of a soup (faces sharing an edge), by union-find.
std::vector<int> pieces_of(const std::vector<Polygon>& polys, int& count) {
  std::vector<std::size_t> parent(polys.size());
  std::iota(parent.begin(), parent.end(), 0);
  const auto find = [&](std::size_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::map<std::pair<std::size_t, std::size_t>, std::size_t> first_face;
  for (std::size_t f = 0; f < polys.size(); ++f)
    for (int e = 0; e < 3; ++e) {
      const std::size_t a = polys[f][std::size_t(e)], b = polys[f][std::size_t((e + 1) % 3)];
      const auto [it, fresh] = first_face.emplace(std::minmax(a, b), f);
      if (!fresh) parent[find(f)] = find(it->second);
    }
  std::vector<int> piece(polys.size());
  std::map<std::size_t, int> ids;
  for (std::size_t f = 0; f < polys.size(); ++f) piece[f] = ids.emplace(find(f), int(ids.size())).first->second;
  count = int(ids.size());
  return piece;
}

// What a point-in-solid test needs of a shell, kept alive with its tree.
struct ShellTest {
  SurfaceMesh mesh;
  std::unique_ptr<Side> side;
  Eigen::AlignedBox3d box;
  int file = 0;  // 1-based
};

// The label at p from the shells' solids: the last file whose solid holds it
// (inside an odd number of that file's pieces).
int label_at(const std::vector<std::unique_ptr<ShellTest>>& tests, int files, const Eigen::Vector3d& p) {
  std::vector<int> parity(std::size_t(files) + 1, 0);
  for (const auto& t : tests)
    if (t->box.contains(p) && (*t->side)(Point(p.x(), p.y(), p.z())) == CGAL::ON_BOUNDED_SIDE) parity[std::size_t(t->file)] ^= 1;
  for (int f = files; f >= 1; --f)
    if (parity[std::size_t(f)]) return f;
  return 0;
}

}  // namespace

SurfaceDomain surface_domain(const std::vector<SurfaceSoup>& soups, double scale, Diagnostics& diag) {
  if (soups.empty()) fail("surface: no surface file given");
  if (!(scale > 0) || !std::isfinite(scale)) fail("surface: the scale must be a positive number, got ", scale);
  SurfaceDomain out;
  out.name = "surface " + soups[0].source;
  for (std::size_t f = 1; f < soups.size(); ++f) out.name += " + " + soups[f].source;
  const int files = int(soups.size());
  std::vector<Shell> shells;
  std::vector<int> shell_file;
  for (int fi = 0; fi < files; ++fi) {
    const SurfaceSoup& soup = soups[std::size_t(fi)];
    const std::string& src = soup.source;
    std::vector<Point> points;
    points.reserve(std::size_t(soup.points.rows()));
    for (Eigen::Index i = 0; i < soup.points.rows(); ++i) points.emplace_back(soup.points(i, 0), soup.points(i, 1), soup.points(i, 2));
    std::vector<Polygon> polys;
    polys.reserve(std::size_t(soup.triangles.rows()));
    for (Eigen::Index t = 0; t < soup.triangles.rows(); ++t) {
      for (int k = 0; k < 3; ++k)
        if (soup.triangles(t, k) < 0 || soup.triangles(t, k) >= soup.points.rows())
          fail(src, ": triangle ", t, " uses point ", soup.triangles(t, k), " of ", soup.points.rows());
      polys.push_back({std::size_t(soup.triangles(t, 0)), std::size_t(soup.triangles(t, 1)), std::size_t(soup.triangles(t, 2))});
    }
    if (polys.empty()) fail(src, ": the file is empty: no triangles to mesh");
    // Exporters repeat a point once per face (OBJ, PLY, OFF; CGAL's STL
    // reader merges them already): equal points are one point.
    PMP::merge_duplicate_points_in_polygon_soup(points, polys);
    std::size_t degenerate = 0;
    polys.erase(std::remove_if(polys.begin(), polys.end(),
                               [&](const Polygon& p) {
                                 const bool d = p[0] == p[1] || p[1] == p[2] || p[0] == p[2];
                                 return degenerate += d, d;
                               }),
                polys.end());
    const std::size_t before = polys.size();
    PMP::merge_duplicate_polygons_in_polygon_soup(points, polys);
    const std::size_t doubled = before - polys.size();
    if (degenerate + doubled > 0)
      diag.warn(src, ": removed ", degenerate, " triangles with a repeated corner and ", doubled, " repeated triangles");
    if (polys.empty()) fail(src, ": no triangle is left after removing degenerate ones: no surface to mesh");

    // Closed: every edge in exactly two triangles.
    std::map<std::pair<std::size_t, std::size_t>, int> edges;
    for (const Polygon& p : polys)
      for (int e = 0; e < 3; ++e) ++edges[std::minmax(p[std::size_t(e)], p[std::size_t((e + 1) % 3)])];
    std::size_t border = 0, crowded = 0;
    std::pair<std::size_t, std::size_t> border_at{}, crowded_at{};
    for (const auto& [e, n] : edges) {
      if (n == 1 && border++ == 0) border_at = e;
      if (n > 2 && crowded++ == 0) crowded_at = e;
    }
    if (border > 0)
      fail(src, ": the surface is not closed: ", border, " border edges (edges of only one triangle), e.g. from ",
           at(points[border_at.first]), " to ", at(points[border_at.second]),
           " (file units); close its holes (3D Slicer: Surface Toolbox, fill holes; MeshLab: Close Holes) and export again");
    if (crowded > 0)
      fail(src, ": ", crowded, " edges are shared by more than two triangles (the surface is not a manifold), e.g. from ",
           at(points[crowded_at.first]), " to ", at(points[crowded_at.second]), " (file units)");

    int npieces = 0;
    const std::vector<int> piece = pieces_of(polys, npieces);
    if (int(shells.size()) + npieces > kMaxSurfacePieces)
      fail(src, ": ", npieces, " separate pieces of surface; softcut meshes at most ", kMaxSurfacePieces,
           " (remove the small ones: MeshLab, Remove Isolated pieces)");
    // Orientation: consistent within each piece (CGAL turns faces), outward after.
    std::vector<char> reversed(polys.size(), 0);
    std::size_t singular = std::size_t(-1);
    OrientVisitor visitor;
    visitor.reversed = &reversed;
    visitor.singular = &singular;
    const std::size_t npoints = points.size();
    if (!PMP::orient_polygon_soup(points, polys, CGAL::parameters::visitor(visitor)) || points.size() != npoints)
      fail(src, ": the surface is not a manifold at ", points.size() - npoints, " points (pieces that touch at a point",
           singular < npoints ? ", e.g. at " + at(points[singular]) : std::string(), ", file units, or a surface that "
           "cannot be oriented); separate them");
    std::vector<std::size_t> turned(std::size_t(npieces), 0), size(std::size_t(npieces), 0);
    for (std::size_t f = 0; f < polys.size(); ++f) ++size[std::size_t(piece[f])], turned[std::size_t(piece[f])] += reversed[f];
    std::size_t inconsistent = 0;
    for (int c = 0; c < npieces; ++c) inconsistent += std::min(turned[std::size_t(c)], size[std::size_t(c)] - turned[std::size_t(c)]);
    if (inconsistent > 0)
      warn_coded(diag, "surface_reoriented", src, ": ", inconsistent, " of ", polys.size(),
                      " triangles faced the other way from their neighbours; they were turned to match");

    for (int c = 0; c < npieces; ++c) {
      Shell s;
      std::map<std::size_t, int> local;
      std::vector<std::array<int, 3>> tris;
      for (std::size_t f = 0; f < polys.size(); ++f) {
        if (piece[f] != c) continue;
        std::array<int, 3> t;
        for (int k = 0; k < 3; ++k) t[std::size_t(k)] = local.emplace(polys[f][std::size_t(k)], int(local.size())).first->second;
        tris.push_back(t);
      }
      s.points.resize(Eigen::Index(local.size()), 3);
      for (const auto& [g, l] : local) s.points.row(l) << points[g].x(), points[g].y(), points[g].z();
      s.triangles.resize(Eigen::Index(tris.size()), 3);
      for (std::size_t t = 0; t < tris.size(); ++t) s.triangles.row(Eigen::Index(t)) << tris[t][0], tris[t][1], tris[t][2];
      // Enclosed volume by the divergence theorem (file units): its sign says
      // which way the faces wind; zero, that there is nothing inside.
      double v = 0;
      Eigen::AlignedBox3d box;
      for (Eigen::Index t = 0; t < s.triangles.rows(); ++t) {
        const Eigen::Vector3d a = s.points.row(s.triangles(t, 0)), b = s.points.row(s.triangles(t, 1)), d = s.points.row(s.triangles(t, 2));
        v += a.dot(b.cross(d)) / 6;
      }
      for (Eigen::Index i = 0; i < s.points.rows(); ++i) box.extend(Eigen::Vector3d(s.points.row(i)));
      s.where = npieces == 1 ? src : cat(src, " (piece ", c + 1, " of ", npieces, ")");
      if (!(std::abs(v) > 1e-9 * std::pow(box.sizes().maxCoeff(), 3)))
        fail(s.where, ": the surface encloses no volume (", v, " cubic file units within a box of ",
             box.sizes().maxCoeff(), "): it is flat or folded onto itself");
      if (v < 0) s.triangles.col(1).swap(s.triangles.col(2));
      s.volume = std::abs(v) * scale * scale * scale;
      s.points *= scale;
      shells.push_back(std::move(s));
      shell_file.push_back(fi + 1);
    }
  }

  // Self-intersections of all pieces together (two files' surfaces that cross
  // are as bad as one that crosses itself).
  std::vector<std::unique_ptr<ShellTest>> tests;
  {
    SurfaceMesh all;
    std::vector<std::size_t> face_shell;
    for (std::size_t s = 0; s < shells.size(); ++s) {
      std::vector<SurfaceMesh::Vertex_index> v;
      for (Eigen::Index i = 0; i < shells[s].points.rows(); ++i)
        v.push_back(all.add_vertex(Point(shells[s].points(i, 0), shells[s].points(i, 1), shells[s].points(i, 2))));
      for (Eigen::Index t = 0; t < shells[s].triangles.rows(); ++t) {
        all.add_face(v[std::size_t(shells[s].triangles(t, 0))], v[std::size_t(shells[s].triangles(t, 1))],
                     v[std::size_t(shells[s].triangles(t, 2))]);
        face_shell.push_back(s);
      }
    }
    try {
      PMP::self_intersections(all, StopAtFirst());
    } catch (const FirstPair& p) {
      const auto corner = [&](std::size_t f) {
        const auto h = all.halfedge(SurfaceMesh::Face_index(SurfaceMesh::size_type(f)));
        const Point& q = all.point(all.target(h));
        return at(Point(q.x() / scale, q.y() / scale, q.z() / scale));
      };
      const std::string& a = shells[face_shell[p.a]].where, & b = shells[face_shell[p.b]].where;
      fail(a == b ? a + ": the surface intersects itself" : a + " and " + b + " intersect",
           ": triangles near ", corner(p.a), " and ", corner(p.b), " (file units) cross or touch; "
           "repair it (MeshLab: Select Self Intersecting Faces; 3D Slicer: Surface Toolbox, clean) and export again");
    }
  }

  // Which piece lies inside which: one corner of each against every other.
  for (std::size_t s = 0; s < shells.size(); ++s) {
    auto t = std::make_unique<ShellTest>();
    std::vector<SurfaceMesh::Vertex_index> v;
    for (Eigen::Index i = 0; i < shells[s].points.rows(); ++i) {
      v.push_back(t->mesh.add_vertex(Point(shells[s].points(i, 0), shells[s].points(i, 1), shells[s].points(i, 2))));
      t->box.extend(Eigen::Vector3d(shells[s].points.row(i)));
    }
    for (Eigen::Index k = 0; k < shells[s].triangles.rows(); ++k)
      t->mesh.add_face(v[std::size_t(shells[s].triangles(k, 0))], v[std::size_t(shells[s].triangles(k, 1))],
                       v[std::size_t(shells[s].triangles(k, 2))]);
    t->side = std::make_unique<Side>(t->mesh);
    t->file = shell_file[s];
    tests.push_back(std::move(t));
  }
  std::vector<Shell> kept;
  for (std::size_t s = 0; s < shells.size(); ++s) {
    const Eigen::Vector3d p = shells[s].points.row(0);
    std::vector<int> parity(std::size_t(files) + 1, 0);
    for (std::size_t o = 0; o < shells.size(); ++o)
      if (o != s && tests[o]->box.contains(p) && (*tests[o]->side)(Point(p.x(), p.y(), p.z())) == CGAL::ON_BOUNDED_SIDE)
        parity[std::size_t(shell_file[o])] ^= 1;
    const auto top = [&] {
      for (int f = files; f >= 1; --f)
        if (parity[std::size_t(f)]) return f;
      return 0;
    };
    shells[s].outside = top();
    parity[std::size_t(shell_file[s])] ^= 1;
    shells[s].inside = top();
    if (shells[s].inside == shells[s].outside)
      diag.warn(shells[s].where, ": lies inside the solid of a later file (label ", shells[s].inside,
                " on both of its sides): it separates nothing and is not meshed");
    else
      kept.push_back(shells[s]);
  }
  if (kept.empty()) fail(out.name, ": no surface separates two regions: nothing to mesh");
  out.shells = std::move(kept);

  int max_label = 0;
  for (const Shell& s : out.shells) max_label = std::max({max_label, s.inside, s.outside});
  out.volumes.assign(std::size_t(max_label) + 1, 0.0);
  for (const Shell& s : out.shells) out.volumes[std::size_t(s.inside)] += s.volume, out.volumes[std::size_t(s.outside)] -= s.volume;
  out.volumes[0] = 0;
  for (int l = 1; l <= max_label; ++l)
    if (out.volumes[std::size_t(l)] > 0) out.shape.labels.push_back(l);

  Eigen::AlignedBox3d box;
  for (const Shell& s : out.shells)
    for (Eigen::Index i = 0; i < s.points.rows(); ++i) box.extend(Eigen::Vector3d(s.points.row(i)));
  const Eigen::Vector3d margin = Eigen::Vector3d::Constant(0.02 * box.sizes().maxCoeff());
  out.shape.name = out.name;
  out.shape.bounds = Eigen::AlignedBox3d(box.min() - margin, box.max() + margin);
  std::shared_ptr<const std::vector<std::unique_ptr<ShellTest>>> shared =
      std::make_shared<std::vector<std::unique_ptr<ShellTest>>>(std::move(tests));
  out.shape.label = [shared, files](const Eigen::Vector3d& p) { return label_at(*shared, files, p); };
  return out;
}

}  // namespace softcut::mesh
