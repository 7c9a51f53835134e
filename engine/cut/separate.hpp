#pragma once
// Internal to the cutter: which faces lie on the cut, and separating the mesh
// along them by duplicating nodes (DESIGN.md §2, docs/cutting.md).
#include <vector>

#include "cut/cutter.hpp"
#include "cut/topology.hpp"

namespace softcut::cut::detail {

// Node v is on the cut surface of the current stroke.
inline bool on_stroke(const CutState& st, int v) { return st.cut_stroke[size_t(v)] == st.stroke; }

// Faces of `face_tets` (and the still-pending faces of `st`) to separate: all
// three nodes on the current stroke's cut, the centre on its swept surface
// (up to how far its nodes were snapped), the two tets on opposite sides, no
// locked node (`blocked` gets how many were held back by one), no tet left
// floating. Pending pairs with a tet in `split_tets` (sorted) are dropped.
// Sorted by key.
std::vector<CutFace> find_cut_faces(const mesh::TetMesh& m, const Adjacency& adj, const CutState& st,
                                    const std::vector<int>& face_tets, const std::vector<int>& split_tets,
                                    double snap_fraction, int& blocked);

// Duplicate nodes so that the tets on the two sides of every cut face no
// longer share it where the cut is complete around a node; the copies are
// appended to `m` and recorded in `rec` (new_nodes, faces_separated,
// faces_pending); faces still joined become `st.pending`. Returns the tets
// whose node lists changed. `adj` must be current for `m`.
std::vector<int> separate(mesh::TetMesh& m, const Adjacency& adj, CutState& st, const std::vector<CutFace>& cut_faces,
                          CutRecord& rec);

}  // namespace softcut::cut::detail
