#pragma once
// The tetrahedral mesh every stage shares. A node is identified everywhere by
// its 0-based position in the file it was read from (or the order a generator
// made it); nodes referenced by no tet keep their id and stay out of the system.
#include <Eigen/Core>
// cross() is declared in Core but defined in Geometry: without this a file
// that only includes Core compiles and then fails to link.
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "core/error.hpp"

namespace softcut::mesh {

struct TetMesh {
  Eigen::MatrixX3d nodes;  // (nnode x 3) rest positions, m
  Eigen::MatrixX4i tets;   // (ntet x 4) node ids, positively oriented after validate()
  Eigen::VectorXi labels;  // (ntet) region / physical tag, 0 where the source had none

  int num_nodes() const { return int(nodes.rows()); }
  int num_tets() const { return int(tets.rows()); }
  Eigen::Vector3d node(int i) const { return nodes.row(i).transpose(); }
};

// Signed volume of (a, b, c, d), m^3: positive when d lies on the side of
// (b - a) x (c - a), the orientation every tet has after validate().
double signed_volume(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                     const Eigen::Vector3d& c, const Eigen::Vector3d& d);
double signed_volume(const TetMesh& m, int tet);

// Local vertex triples of the four faces of a positively oriented tet, each
// counter-clockwise seen from outside (outward normal by the right-hand rule).
// Face f is opposite local vertex f.
inline constexpr int kTetFaces[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

// Relative degeneracy threshold: |V| <= kDegenerateVolume * (longest edge)^3.
inline constexpr double kDegenerateVolume = 1e-10;

struct ValidateReport {
  int reoriented = 0;            // tets whose orientation was flipped
  std::vector<int> unreferenced; // node ids used by no tet
};

// Mesh hygiene on load. Checks (and throws softcut::Error naming `source` and
// the node or element): NaN/Inf coordinates, node ids out of range, repeated
// ids in a tet, degenerate tets. Flips negatively oriented tets, fills missing
// labels with 0. Reports the flip count and unreferenced nodes once each into
// `diag`. `source` is the file name (or generator) used in messages.
ValidateReport validate(TetMesh& m, const std::string& source, Diagnostics& diag);

// Per node: true if some tet references it. (nnode)
std::vector<char> referenced_nodes(const TetMesh& m);

// Total volume, m^3 (sum of signed tet volumes).
double total_volume(const TetMesh& m);

}  // namespace softcut::mesh
