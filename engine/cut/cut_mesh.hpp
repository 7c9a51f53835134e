#pragma once
// The run's mesh once a scalpel has cut it (DESIGN.md §2, docs/cutting.md):
// the cut mesh with its per-tet and per-node masks, kept in the run's state
// (the Model keeps the rest mesh), and the bookkeeping after each cut step:
// masks grown onto new tets and nodes, cut faces flagged, pieces cut free
// found and held.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "cut/cutter.hpp"
#include "cut/detached.hpp"
#include "fem/material.hpp"
#include "mesh/surface.hpp"
#include "mesh/tet_mesh.hpp"

namespace softcut::cut {

// What cutting reads of the compiled model: the rest body and its partition.
struct RestBody {
  const mesh::TetMesh& mesh;
  const mesh::Surface& surface;
  const std::vector<fem::Material>& tet_material;  // (ntet)
  const std::vector<char>& operational_tet;        // (ntet) 1: may be cut
  const std::vector<int>& fixed;                   // fixed node ids
  const std::vector<int>& interface;               // node ids shared with nonoperational tets (never split)
};

// The mesh after the first cut. Original nodes keep their ids; nodes made by
// cutting are appended (ids >= the rest mesh's node count), as are new tets.
struct CutMesh {
  mesh::TetMesh mesh;                      // current rest mesh
  mesh::Surface surface;                   // its boundary, including the cut faces
  std::vector<fem::Material> tet_material; // (ntet)
  std::vector<char> operational_tet;       // (ntet) 1: operational (children of operational tets)
  // Nodes the elastic solve does not solve for (what backend::Solver::apply_cut
  // eliminates): node_clamped or node_held.
  std::vector<char> node_fixed;            // (nnode)
  std::vector<char> node_clamped;          // (nnode) zero displacement: fixed nodes, copies/splits of fixed nodes only
  // Pieces cut free (docs/cutting.md "Pieces cut free"): a connected part
  // without clamped nodes that pin its rigid motions is held where it was
  // when it separated; loads and tool forces on it are ignored.
  std::vector<char> node_held;             // (nnode) unclamped node of a detached piece
  Eigen::MatrixX3d held_displacement;      // (nnode x 3) m, displacement of held nodes at separation, else 0
  std::vector<char> tet_detached;          // (ntet) tet of a detached piece
  int detached_pieces = 0;                 // pieces cut free so far, each counted once, when it separated
  std::vector<std::string> ignored_on_held;  // loads / tools already warned about acting on a held piece
  std::vector<char> cut_face;              // (4 ntet) face f of tet t is a boundary face made by cutting
  std::vector<int> origin_tet;             // (ntet) rest-mesh tet each tet comes from
  CutState cut;                       // masks and stroke data of the cutter
  // Where each stroke (CutState::stroke, from 1) began: its scalpel and time,
  // s; for messages that name the strokes a piece was cut free by.
  std::vector<std::pair<std::string, double>> stroke_begun;
};

// The first cut: the rest body's mesh and masks become the run's.
CutMesh initial_cut_mesh(const RestBody& rest);

// Grows the per-tet / per-node masks after a cut step and refreshes the
// boundary; faces of the new boundary that lie on no rest boundary face are
// flagged as cut faces.
void update_after_cut(const RestBody& rest, CutMesh& cm, const CutRecord& rec);

// After a step (u: displacements already mapped onto the new nodes): finds
// the parts that nothing anchors, holds their unclamped nodes (at their held
// value if they were held before, else at u: where they were when they
// separated) and refreshes node_fixed. Returns the pieces this step cut free.
std::vector<DetachedPiece> update_detached(CutMesh& cm, const CutRecord& rec, const Eigen::MatrixX3d& u);

// Node n belongs to a piece cut free (held at its displacement at separation).
bool is_held(const CutMesh& cm, int n);
// Writes the held displacement into the rows of held nodes of u (nnode x 3,
// m; the solve leaves them unknown).
void hold_detached(const CutMesh& cm, Eigen::MatrixX3d& u);

// For summary.json "cutting": pieces cut free during the run, and the tets /
// nodes of the current mesh that lie in detached pieces.
struct DetachedCounts {
  int pieces = 0, tets = 0, nodes = 0;
};
DetachedCounts detached_counts(const CutMesh& cm);

// Connected pieces of a tet mesh (tets joined through shared nodes); unused
// nodes do not count.
int count_components(const mesh::TetMesh& mesh);

}  // namespace softcut::cut
