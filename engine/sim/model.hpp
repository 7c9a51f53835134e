#pragma once
// Model (fixed after compile) and State (changes every frame), MuJoCo style:
// step(const Model&, State&) reads the one and writes the other.
#include <Eigen/Core>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "fem/material.hpp"
#include "hybrid/partition.hpp"
#include "mesh/surface.hpp"
#include "mesh/tet_mesh.hpp"
#include "sim/control.hpp"
#include "sim/cutting.hpp"
#include "sim/expectations.hpp"
#include "sim/scenario_spec.hpp"
#include "sim/validity.hpp"
#include "backend/solver.hpp"
#include "tools/springs.hpp"
#include "tools/tool.hpp"

namespace softcut::sim {

// A prescribed motion resolved against the mesh (ScenarioSpec::motions).
struct Motion {
  std::string name;
  std::vector<int> nodes;  // sorted ids (fixed in the partition)
  tools::Path path;        // displacement, m, over time
};

struct Model {
  ScenarioSpec spec;                                     // as compiled
  mesh::TetMesh mesh;                                    // rest mesh
  std::map<std::string, std::vector<int>> named_sets;    // e.g. "hole" from the generator
  mesh::Surface surface;                                 // whole-body boundary
  Eigen::MatrixX3d rest_normals;                         // (nnode x 3) unit outward, zero off-surface
  std::vector<fem::Material> tet_material;               // (ntet)
  // (ntet) the s:material call that set the tet's material, by its index in
  // spec.materials; spec.materials.size() for tets no call covers. Frames
  // colour and label tissue by it.
  std::vector<int> tet_group;
  hybrid::Partition partition;                           // node sets (fixed, 1, I, s, i), Table 2 counts
  std::vector<Motion> motions;                           // fixed nodes that move (prescribed displacement)
  std::vector<int> log_nodes;                            // sorted ids written to displacements.csv
  std::vector<std::vector<int>> expectation_nodes;       // (spec.expectations) node ids of bounds; empty for checks
  std::unique_ptr<const backend::Solver> solver;                  // solver->backend(): what runs and why
  std::vector<std::pair<std::string, double>> precompute_ms;  // Table 3 (+ mesh, selectors)
  std::vector<std::string> warnings;                     // from compile
  int num_frames = 1;                                    // see Timeline
  double dt = 0.0;                                       // 1 / fps, s

  double frame_time(int frame) const { return frame * dt; }
};

// Reads / generates the mesh, evaluates selectors, assigns materials,
// partitions, precomputes the solver (in resources.context for backend gpu;
// the context must outlive the Model). Throws softcut::Error naming the item.
Model compile(const ScenarioSpec& spec, const backend::RunResources& resources = {});

// Whether the application should create an EGL context for this spec:
// rendering is on, or the backend is gpu (auto runs on the CPU: it needs
// no context).
bool wants_gpu_context(const ScenarioSpec& spec);

// The prescribed displacement of every fixed node at time t (nnode x 3, m:
// the motions' paths, zero for the other fixed nodes), or an empty matrix
// when the scenario moves none. nnode: the current mesh's (cutting appends
// nodes, never fixed ones that move).
Eigen::MatrixX3d prescribed_displacements(const Model& m, double t, Eigen::Index nnode);

// A load resolved against the Model: the nodes and their unit directions.
struct ActiveLoad {
  LoadSpec spec;
  std::vector<int> nodes;       // (k) sorted ids
  Eigen::MatrixX3d directions;  // (k x 3) unit directions
  bool enabled = true;
  double scale = 1.0;           // multiplies the ramp (script knob)
};
// Throws naming the load when it selects no node, a fixed node, an interior
// nonoperational node (condensed away), or normal directions off the surface.
ActiveLoad resolve_load(const Model& m, const LoadSpec& spec);

// Per-frame stage timings, ms (the paper's Fig. 8 stages).
struct FrameTimings {
  double collision = 0, cutting = 0, poke_drag = 0, operational_solve = 0, nonoperational_update = 0;
  double total = 0;  // whole step
};

struct StageStat {
  double sum = 0, max = 0;
  void add(double v) { sum += v; max = v > max ? v : max; }
};

struct RunStatistics {
  int frames = 0;
  StageStat collision, cutting, poke_drag, operational_solve, nonoperational_update, total;  // ms
  StageStat springs;                 // implicit springs incl. compliance builds (part of poke_drag), ms
  int springs_frames = 0;            // frames in which implicit springs acted
  long long cg_iterations_total = 0;
  int cg_iterations_max = 0;
  double max_relative_residual = 0;
  // Nonlinear frames (a nonlinear law or a prescribed motion): Newton steps.
  int newton_frames = 0;
  long long newton_iterations_total = 0;
  int newton_iterations_max = 0;
  int projected_steps = 0;           // Newton steps that needed projected element tangents
  int floor_stops = 0;               // Newton frames that ended at the residual's rounding floor
  double nonlinear_rotation_max = 0; // rad, nonlinear-law tets
  double nonlinear_strain_max = 0;
  int inverted_max = 0;              // nonlinear-law tets inverted at a solution
  // What linear elasticity carried (sim/validity.hpp): the largest over the
  // run, with its frame, of each frame's largest and of its 99th percentile.
  double linear_rotation_max = 0, linear_strain_max = 0, condensed_rotation_max = 0;  // rad, -, rad
  int linear_rotation_frame = -1, linear_strain_frame = -1, condensed_rotation_frame = -1;
  double linear_rotation_p99_max = 0, linear_strain_p99_max = 0, condensed_rotation_p99_max = 0;  // rad, -, rad
  int linear_rotation_p99_frame = -1, linear_strain_p99_frame = -1, condensed_rotation_p99_frame = -1;
};

// What a frame changes in the world: the tissue (displacements, the cut
// mesh) and the instruments. Scene extraction, outputs and expectations read it.
struct PhysicsState {
  int frame = -1;                    // last completed frame, -1 before the first step
  double time = 0.0;                 // s, of `frame`
  Eigen::MatrixX3d displacement;     // (nnode x 3) m
  Eigen::MatrixX3d forces;           // (nnode x 3) N, external nodal forces of this frame
  std::vector<tools::ToolState> tools;  // (ntools) parallel to RunBookkeeping::tool_specs
  // Cutting (sim/cutting.hpp): the current mesh once a scalpel cut (null
  // before; then displacement/forces have its node count).
  std::unique_ptr<CutMesh> cut;
};

// The run's bookkeeping: what the script controls, the solver's per-run data
// and caches, statistics and logs.
struct RunBookkeeping {
  std::vector<ActiveLoad> loads;
  std::vector<tools::ToolSpec> tool_specs;  // copies; the script may change them between frames
  bool stop_requested = false;       // set by the script: finish after this frame
  backend::SolverRun solver_run;              // Solver::start_run: warm start, factors, column cache, device buffers
  tools::SpringCache springs;        // implicit spring compliance (per run, tools/springs.hpp)
  FrameTimings last;                 // of the last frame
  int last_cg_iterations = 0;
  int last_newton_iterations = 0;    // 0: the last frame was linear
  Validity last_validity;            // of the last frame (sim/validity.hpp)
  RunStatistics stats;
  std::vector<std::string> warnings;  // runtime, deduplicated by the writer
  std::vector<CutEvent> cut_events;   // every cut so far
  std::vector<ExpectationOutcome> expectations;  // (spec.expectations) sim/expectations.hpp
  std::vector<Metric> metrics;       // recorded by the script (sim/control.hpp), first-recorded order
};

// One run: move-only (it owns its cut mesh and solver data); copy_state()
// is the explicit copy.
struct State : PhysicsState, RunBookkeeping {
  State() = default;
  State(State&&) = default;
  State& operator=(State&&) = default;
  State(const State&) = delete;
  State& operator=(const State&) = delete;
};

// A new run at frame -1 (loads resolved, the solver's run data made and the
// columns of nodes the tool paths reach queued for prefetching).
State make_state(const Model& m);
// An independent run from where `s` is: the physics, controls, statistics and
// logs deep-copied; the solver's run data made afresh on the same (cut)
// system, so both continue to the same displacements (to the solver's
// tolerance: CG warm starts differ). The spring cache starts empty.
State copy_state(const Model& m, const State& s);


// Deformed positions rest + displacement of the current (possibly cut) mesh, (nnode x 3), m.
Eigen::MatrixX3d deformed_positions(const Model& m, const State& s);
// Nodes of a selector on the compiled model (e.g. for expectations).
std::vector<int> select_nodes(const Model& m, const NodeSelector& sel, const std::string& where);
// Throws naming `what` and the node when node n's displacement is not solved
// this frame: an interior nonoperational node while the solver does not
// recover them (hybrid backends unless logged or exported).
void check_solved(const Model& m, const State& s, int n, const std::string& what);
// Mean displacement (3) of a node set, m; throws on an empty set.
Eigen::Vector3d mean_displacement(const State& s, const std::vector<int>& nodes);

}  // namespace softcut::sim
