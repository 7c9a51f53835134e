#pragma once
// The cutting stage of a frame (DESIGN.md §2, docs/outputs.md "Cutting"):
// scalpel tools whose contact pressure reaches their threshold sweep their
// blade between the last and the current pose; the swept surface, mapped
// into the rest configuration, is cut from the operational tets (cutter),
// the run's nodal fields are mapped onto the new nodes, pieces cut free are
// held, and the solver is asked to rebuild its system.
#include <Eigen/Core>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "cut/cut_mesh.hpp"
#include "tools/tool.hpp"

namespace softcut::cut {

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

// One frame of a run, as the cutting stage sees it: what it reads and what it
// changes. `cut` is null until the first cut makes it from the rest body.
struct StageFrame {
  int frame = 0;                  // the frame being made
  double t = 0, t_prev = 0, dt = 0;  // its time, the previous frame's, the step, s
  CutOptions options;
  std::unique_ptr<CutMesh>& cut;
  const std::vector<tools::ToolSpec>& specs;
  std::vector<tools::ToolState>& tools;   // (specs.size())
  Eigen::MatrixX3d& displacement;         // (nnode x 3) m, last frame's; mapped onto new nodes
  Eigen::MatrixX3d& forces;               // (nnode x 3) N; grows with zero rows for new nodes
  std::vector<std::string>& warnings;     // the run's, "frame F (t = T s), scalpel 'S': ..."
  int cg_iterations_before = 0;           // for the events' log
  // The solver rebuilds its system for the cut mesh and maps its warm start.
  std::function<void(const CutMesh&, const CutRecord&)> rebuild;
};

// For every active scalpel that cuts this frame (pressure >= cut_pressure,
// or still inside the cut it is making): cuts the swept blade surface,
// rebuilds, and maps the frame's nodal fields; the blade then applies no
// force. Returns the events of blades that changed the mesh. Throws
// softcut::Error on a non-finite blade and on a blade inside the tissue that
// is not cutting (it would never cut, and say nothing).
std::vector<CutEvent> cut_stage(const RestBody& rest, StageFrame& f);

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

// `current`: the rest mesh before the first cut, else cm->mesh.
CuttingSummary cutting_summary(const mesh::TetMesh& current, const CutMesh* cm, const std::vector<CutEvent>& events);

}  // namespace softcut::cut
