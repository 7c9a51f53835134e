#pragma once
// Node and tet selectors of a scenario: geometric shapes, labels, explicit
// lists, surfaces, and set algebra. Evaluated on the REST mesh at compile
// time (and on demand by the Lua layer), results sorted and unique.
#include <Eigen/Core>
#include <map>
#include <string>
#include <vector>

#include "mesh/surface.hpp"
#include "mesh/tet_mesh.hpp"

namespace softcut::sim {

struct NodeSelector {
  enum class Kind {
    all,           // every node referenced by a tet
    box,           // min <= x <= max (componentwise, inclusive, tol below)
    sphere,        // |x - center| <= radius
    halfspace,     // (x - point) . normal >= 0
    label,         // nodes of the tets with `label`
    nodes,         // explicit 0-based ids
    surface,       // boundary nodes of the tets with `label` (label < 0: the whole body)
    named,         // a node set the mesh source provides, e.g. "hole" (inner surface of a tube)
    union_of,      // any of `children`
    intersection,  // all of `children`
    difference,    // children[0] minus the others
  };
  Kind kind = Kind::all;
  Eigen::Vector3d min = Eigen::Vector3d::Zero(), max = Eigen::Vector3d::Zero();  // box corners, m
  Eigen::Vector3d center = Eigen::Vector3d::Zero();                            // sphere, m
  double radius = 0.0;                                                         // sphere, m
  Eigen::Vector3d point = Eigen::Vector3d::Zero(), normal = Eigen::Vector3d::UnitZ();  // half-space
  int label = -1;                   // label, surface
  std::vector<int> ids;             // nodes
  std::string name;                 // named
  std::vector<NodeSelector> children;  // union_of, intersection, difference
  // Geometric tests accept points up to tolerance * (mesh bounding-box
  // diagonal) outside the shape, so nodes exactly on a box face are caught.
  double tolerance = 1e-9;
  std::string where;  // "scenario.lua:12" (prefixes messages), may be empty

  // Shorthands (tests, C++ callers).
  static NodeSelector box(const Eigen::Vector3d& min, const Eigen::Vector3d& max);
  static NodeSelector sphere(const Eigen::Vector3d& center, double radius);
  static NodeSelector halfspace(const Eigen::Vector3d& point, const Eigen::Vector3d& normal);
  static NodeSelector list(std::vector<int> ids);
  static NodeSelector combine(Kind op, std::vector<NodeSelector> children);
};

struct TetSelector {
  enum class Kind { all, none, label, box, sphere, halfspace, tets, union_of };
  Kind kind = Kind::none;
  // Geometric kinds take a tet when its centroid is inside the shape.
  Eigen::Vector3d min = Eigen::Vector3d::Zero(), max = Eigen::Vector3d::Zero();
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double radius = 0.0;
  Eigen::Vector3d point = Eigen::Vector3d::Zero(), normal = Eigen::Vector3d::UnitZ();
  int label = -1;
  std::vector<int> ids;               // tets
  std::vector<TetSelector> children;  // union_of
  std::string where;  // "scenario.lua:12" (prefixes messages), may be empty

  static TetSelector of(Kind k) {
    TetSelector s;
    s.kind = k;
    return s;
  }
};

// What selectors are evaluated against.
struct SelectContext {
  const mesh::TetMesh& mesh;
  const mesh::Surface& surface;                            // whole-body boundary
  const std::map<std::string, std::vector<int>>& named;   // named node sets of the mesh source
};

// Sorted unique node ids. Throws softcut::Error naming `where` (e.g.
// "fixed", "load 'push'") for out-of-range ids, unknown labels or names,
// a negative radius, an empty child list.
std::vector<int> select_nodes(const NodeSelector& sel, const SelectContext& ctx, const std::string& where);

// Sorted unique tet ids; same error rules.
std::vector<int> select_tets(const TetSelector& sel, const SelectContext& ctx, const std::string& where);

const char* to_string(NodeSelector::Kind k);
const char* to_string(TetSelector::Kind k);

}  // namespace softcut::sim
