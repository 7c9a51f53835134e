#pragma once
// Boundary surface of a tet mesh (or of a subset of its tets): the faces used
// by exactly one tet of the set, oriented outward.
#include <Eigen/Core>
#include <vector>

#include "mesh/tet_mesh.hpp"

namespace softcut::mesh {

struct Surface {
  Eigen::MatrixX3i faces;    // (nface x 3) node ids, counter-clockwise seen from outside
  Eigen::VectorXi face_tet;  // (nface) the tet each face belongs to
  std::vector<int> nodes;    // sorted ids of the nodes on some boundary face
};

// Boundary of the tets with tet_mask[t] != 0 (all tets when the mask is empty).
// Faces come out in a deterministic order (by tet, then local face).
Surface extract_surface(const TetMesh& m, const std::vector<char>& tet_mask = {});

// The inner boundaries between tissue groups (tet_group: an id per tet):
// each face shared by tets of two groups, once, oriented outward from the
// inclusion: as the face of the tet not of the commonest group, or of the
// higher group where neither is. Faces come out ordered by node triple.
// Empty for an empty tet_group; throws when its size is not the tet count.
Surface group_boundaries(const TetMesh& m, const std::vector<int>& tet_group);

// Edges of a surface and how many are not in exactly two of its faces (a
// closed manifold has none; voxels that touch only along an edge make them).
struct SurfaceEdges {
  int edges = 0;      // distinct edges
  int odd = 0;        // edges in one face or in more than two
  int euler = 0;      // Euler characteristic: surface nodes - edges + faces
};
SurfaceEdges surface_edges(const Surface& s);

// Per node: true if the node lies on the surface. (nnode)
std::vector<char> surface_node_mask(const TetMesh& m, const Surface& s);

// Area-weighted outward normals at the surface nodes, unit length, (nnode x 3);
// zero rows for nodes not on the surface. `positions` (nnode x 3) lets callers
// pass deformed positions; the rest positions are used when it is empty.
Eigen::MatrixX3d vertex_normals(const TetMesh& m, const Surface& s,
                                const Eigen::MatrixX3d& positions = {});

}  // namespace softcut::mesh
