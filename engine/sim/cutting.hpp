#pragma once
// Cutting in a run: the cutting stage itself lives in engine/cut (cut/stage:
// the scalpels' sweep, the cut, the fields mapped onto new nodes, pieces cut
// free; cut/cut_mesh: the cut mesh and its masks). Here: the run's view of it
// (the current mesh, which nodes are fixed or held), the stage called with
// the Model and State, and what loads on pieces cut free become.
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "backend/solver.hpp"
#include "cut/cut_mesh.hpp"
#include "cut/stage.hpp"
#include "hybrid/partition.hpp"
#include "mesh/surface.hpp"
#include "mesh/tet_mesh.hpp"

namespace softcut::sim {

struct Model;
struct State;

using cut::CutEvent;
using cut::CutMesh;
using cut::CuttingSummary;
using cut::DetachedCounts;

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

// The cut body as the solver rebuilds from it; with `rec` (the step that made
// it; must outlive the result) the warm start is carried onto its nodes.
backend::CutBody cut_body(const CutMesh& cm, const cut::CutRecord* rec = nullptr);

// The cutting stage of frame `frame` at time t (cut::cut_stage on the
// Model's rest body and the State; the solver rebuilds through apply_cut).
// Returns the events (also appended to s.cut_events).
std::vector<CutEvent> cut_stage(const Model& m, State& s, int frame, double t);

// Loads and tool forces on pieces cut free: zeroes their rows of s.forces
// and warns once per load or tool (summary.json "warnings"). Call after the
// forces of the frame are summed, before the solve.
void drop_loads_on_held(State& s, int frame, double t);
// Writes the held displacement into the rows of held nodes of s.displacement
// (the solve leaves them unknown: zero, or whatever the decoupled block gave).
void hold_detached(State& s);

DetachedCounts detached_counts(const State& s);
// Visits every tet of the current mesh (pieces and components).
CuttingSummary cutting_summary(const Model& m, const State& s);

}  // namespace softcut::sim
