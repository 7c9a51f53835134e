#pragma once
// Progressive cutting of the operational region of a tet mesh by a moving
// blade (DESIGN.md §2, docs/cutting.md). One call = one blade step: the swept
// surface is intersected with the cuttable tets, crossed edges are split (or
// the crossing snapped to a nearby node), and faces lying on the accumulated
// cut surface are separated by duplicating their nodes. Everything happens in
// the rest configuration. Existing nodes keep their ids and positions; new
// nodes and tets are appended. Non-cuttable tets and locked nodes never change.
#include <array>
#include <string>
#include <vector>

#include "cut/blade.hpp"
#include "mesh/tet_mesh.hpp"

namespace softcut::cut {

struct CutOptions {
  // A crossing closer than snap_fraction * (edge length) to an end of the
  // edge snaps to that node instead of splitting the edge. In (0, 0.5).
  double snap_fraction = 0.15;
  // No tet created by a step has a smaller dihedral angle (unless the tet it
  // came from was already worse: then not worse than that). Splits that would
  // break this are snapped instead. Degrees, in [0, 60).
  double min_dihedral_deg = 10.0;
};

// What cutting keeps between steps. Grows with the mesh; callers set the masks
// through make_cut_state and otherwise leave it to cut_step.
struct CutState {
  std::vector<char> cuttable;      // (ntet) 1: operational tet, may be split and separated
  std::vector<char> locked;        // (nnode) 1: interface node, never duplicated, never on a separated face
  int stroke = 0;                  // current stroke (see begin_stroke)
  std::vector<int> cut_stroke;     // (nnode) last stroke the node joined the cut surface in; -1: never
  std::vector<double> cut_offset;  // (nnode) farthest it lay from a blade that put it on the cut in that stroke, m
  SweptSurface swept;              // every blade step of the current stroke (rest configuration)
  std::vector<double> quality;     // (ntet) min dihedral angle of each cuttable tet, deg (180 elsewhere)
  std::vector<std::array<int, 2>> pending;  // tet pairs whose shared face is on the cut but still joined
};

// A stroke is one continuous blade motion; its steps build one cut surface.
// Call begin_stroke when the blade re-enters the tissue (after it was lifted
// out), so that a new cut crossing an old one is told apart from it.
void begin_stroke(CutState& state);

// Start state: `cuttable` (ntet) and `locked` (nnode) as given; nodes of
// non-cuttable tets are locked in addition. Throws softcut::Error on size
// mismatch.
CutState make_cut_state(const mesh::TetMesh& m, std::vector<char> cuttable, std::vector<char> locked);

// A node created by a step. Its displacement (or any nodal field) maps from
// the pre-step field as f[id] = weight[0] f[parent[0]] + weight[1] f[parent[1]];
// parents are always pre-step nodes (parent[1] = -1, weight[1] = 0 for a copy of a
// pre-step node).
struct NewNode {
  int id = -1;
  std::array<int, 2> parent = {-1, -1};
  std::array<double, 2> weight = {0, 0};
  bool duplicate = false;  // a copy made to separate the two sides (else an edge split point)
};

// Change record of one step, for rebuilding the touched part of the
// operational system and mapping the CG warm start.
struct CutRecord {
  int nodes_before = 0, tets_before = 0;
  std::vector<NewNode> new_nodes;  // ids nodes_before, nodes_before+1, ... in order
  std::vector<int> tet_parent;     // (ntet after) pre-step tet each tet came from (itself if untouched)
  std::vector<int> changed_tets;   // sorted ids (after) whose node list changed: split children, relabelled
  std::vector<int> split_tets;     // sorted pre-step ids of tets that were subdivided
  int edges_split = 0;             // edges bisected at a blade crossing
  int nodes_snapped = 0;           // existing nodes newly put on the cut by snapping
  int splits_vetoed = 0;           // splits replaced by a snap to keep quality
  int locked_snapped = 0;          // locked nodes (never cut) a crossing or the blade snapped onto
  double locked_snap_reach = 0;    // m, the largest snap distance among those
  int faces_separated = 0;         // faces that became two boundary faces this step
  int faces_pending = 0;           // faces on the cut still joined (the cut front)
  int uncuttable_tets_crossed = 0; // tets the blade crosses that may not be cut (nonoperational)
  double worst_new_dihedral_deg = 180;  // over tets created this step (180 when none)
  double worst_dihedral_deg = 180;      // over all cuttable tets after the step
  std::vector<std::string> warnings;
};

// One blade step. `m`, `state` are updated in place. Throws softcut::Error on
// bad options or a state that does not match the mesh.
CutRecord cut_step(mesh::TetMesh& m, CutState& state, const SweptSurface& blade, const CutOptions& opt = {});

// Map a nodal field (pre-step rows, nnode_before x 3) to the post-step mesh
// with the record's parent weights: the CG warm start after a cut.
Eigen::MatrixX3d map_node_field(const CutRecord& rec, const Eigen::MatrixX3d& before);

}  // namespace softcut::cut
