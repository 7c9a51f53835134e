#pragma once
// Cutting in a scenario (DESIGN.md §2, docs/outputs.md "Cutting"): scalpel
// tools whose contact pressure reaches their threshold sweep their blade
// between the last and the current pose; the swept surface, mapped into the
// rest configuration, is cut from the operational tets (engine/cut). The
// current (cut) mesh lives in the State (the Model keeps the rest mesh); the
// solver rebuilds the operational system and maps its warm start.
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "cut/cutter.hpp"
#include "fem/material.hpp"
#include "hybrid/partition.hpp"
#include "mesh/surface.hpp"
#include "mesh/tet_mesh.hpp"

namespace softcut::sim {

struct Model;
struct State;

// The mesh after the first cut. Original nodes keep their ids; nodes made by
// cutting are appended (ids >= the rest mesh's node count), as are new tets.
struct CutMesh {
  mesh::TetMesh mesh;                      // current rest mesh
  mesh::Surface surface;                   // its boundary, including the cut faces
  std::vector<fem::Material> tet_material; // (ntet)
  std::vector<char> operational_tet;       // (ntet) 1: operational (children of operational tets)
  // Nodes the elastic solve does not solve for (what Solver::apply_cut
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
  cut::CutState cut;                       // masks and stroke data of the cutter
};

// One frame's cut by one scalpel, as logged in summary.json "cutting.events".
struct CutEvent {
  int frame = 0;
  double time = 0.0;               // s
  std::string tool;
  int tets_split = 0, nodes_added = 0, edges_split = 0, nodes_snapped = 0;
  int faces_separated = 0, faces_pending = 0;
  int nodes_after = 0, tets_after = 0;
  double worst_new_dihedral_deg = 180, worst_dihedral_deg = 180;  // element quality after the step
  double cut_ms = 0, rebuild_ms = 0;  // cut_step (+ rest mapping), system rebuild + field mapping
  int cg_iterations_before = 0;    // operational CG iterations of the previous frame
  int cg_iterations_after = 0;     // of this frame (first solve on the cut system)
  int pieces_freed = 0, tets_freed = 0, nodes_freed = 0;  // pieces this step cut free (see CutMesh::node_held)
  std::vector<std::string> warnings;
};

// Current mesh and boundary: the cut ones once a cut happened, else the Model's.
const mesh::TetMesh& current_mesh(const Model& m, const State& s);
const mesh::Surface& current_surface(const Model& m, const State& s);
// Node n takes no load and is not solved for: fixed (also nodes made by
// cutting from fixed nodes) or held in a piece cut free.
bool is_fixed_node(const Model& m, const State& s, int n);
// Node n belongs to a piece cut free (held at its displacement at separation).
bool is_held_node(const State& s, int n);
// Node set of n; nodes made by cutting are operational (or fixed, also when held).
hybrid::NodeSet node_set(const Model& m, const State& s, int n);

// The cutting stage of a frame: for every active scalpel that cuts this frame
// (pressure >= cut_pressure, or still inside the cut it is making), cuts the
// swept blade surface, rebuilds the solver's system and maps the state's
// nodal fields; the blade then applies no force. Returns the events (also
// appended to s.cut_events). Throws softcut::Error on a non-finite blade.
std::vector<CutEvent> cut_stage(const Model& m, State& s, int frame, double t);

// Loads and tool forces on pieces cut free: zeroes their rows of s.forces
// and warns once per load or tool (summary.json "warnings"). Call after the
// forces of the frame are summed, before the solve.
void drop_loads_on_held(State& s, int frame, double t);
// Writes the held displacement into the rows of held nodes of s.displacement
// (the solve leaves them unknown: zero, or whatever the decoupled block gave).
void hold_detached(State& s);

// For summary.json "cutting": pieces cut free during the run, and the tets /
// nodes of the current mesh that lie in detached pieces.
struct DetachedCounts {
  int pieces = 0, tets = 0, nodes = 0;
};
DetachedCounts detached_counts(const State& s);

// What cutting did so far, for scripts (Frame:cutting) and checks: enough to
// tell a cut through from a refinement or a cut front still joined.
struct CuttingSummary {
  int events = 0;            // frames in which a blade changed the mesh
  int nodes_added = 0;       // by cutting, all events
  int nodes = 0, tets = 0;   // of the current mesh
  int faces_separated = 0;   // faces that became two boundary faces, all events
  int faces_pending = 0;     // faces on the cut still joined now (the cut front)
  int components = 0;        // pieces joined through shared nodes (count_components)
  int pieces = 0;            // rigid pieces: tets joined through shared faces (a hinge splits them)
  int detached = 0;          // pieces cut free so far (held where they separated)
};
// Visits every tet of the current mesh (pieces and components).
CuttingSummary cutting_summary(const Model& m, const State& s);

// Connected pieces of a tet mesh (tets joined through shared nodes); unused
// nodes do not count.
int count_components(const mesh::TetMesh& mesh);

}  // namespace softcut::sim
