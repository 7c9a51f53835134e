#pragma once
// Per-frame update of the hybrid model (paper §4 stages 2-5, DESIGN.md §1):
//   2. take this frame's interactive loads;
//   3. selective multiplication: for surface nodes whose load changed, add
//      (change) x (the 3 columns of K*^-1 and of (KI2 K22^-1)[:, s]) to the
//      running sums K*^-1 (Ps0 + Ps_interact) and P' (paper Fig. 3); the
//      columns are the dense blocks' (dense storage) or the run's column
//      cache's (columns.hpp: first touch one 3-column solve, then a lookup);
//   4. solve the operational system for A1, AI (pluggable backend, warm start);
//   5. As = (running sum) + (K*^-1 P*) AI: for every surface node (a rendered
//      frame; one dense product, or a K22 solve pair in factor storage), or
//      only for the nodes the frame needs (physics frames: loaded nodes and
//      the ones asked for, 3 rows each).
// Loads on operational and interface nodes go straight into the operational
// right-hand side.
#include <Eigen/Core>
#include <memory>
#include <span>
#include <vector>

#include "core/helper_thread.hpp"
#include "hybrid/columns.hpp"
#include "hybrid/loads.hpp"
#include "hybrid/nonlinear_solve.hpp"
#include "hybrid/nonoperational_product.hpp"
#include "hybrid/operational_solvers.hpp"
#include "hybrid/precompute.hpp"

namespace softcut::hybrid {

struct FrameReport {
  double loads_ms = 0;            // stage 2: check and sort loads
  double selective_ms = 0;        // stage 3: running sums / P'
  double operational_ms = 0;      // stage 4
  double nonoperational_ms = 0;   // stage 5 (+ interior recovery when asked)
  double total_ms = 0;
  SolveReport solve;
  bool newton = false;            // stage 4 was a nonlinear solve (nonlinear_solve.hpp)
  NonlinearReport nonlinear;      // its report
  int loaded_surface_nodes = 0;   // surface nodes whose load changed this frame
  int loaded_operational_nodes = 0;
  int surface_nodes_updated = 0;  // surface rows of u written in stage 5
  bool surface_complete = false;  // every surface row of u is this frame's
  bool interior_recovered = false;
};

struct UpdateOptions {
  bool recover_interior = false;  // also compute the interior nonoperational nodes (one factor solve)
  // false: a physics frame, stage 5 only for the loaded surface nodes and
  // `surface_nodes` (mesh node ids; other ids are ignored); the other
  // surface rows of u keep the values of the frame that last wrote them.
  bool full_surface = true;
  std::span<const int> surface_nodes;
  // The frame's prescribed motions and grasper springs, for a nonlinear
  // stage 4 (nonlinear_solve.hpp); null: none (a linear system then takes
  // the linear solve).
  const NonlinearFrame* nonlinear = nullptr;
};

struct StateOptions {
  double column_cache_bytes = 256.0 * 1024 * 1024;  // bound of the column cache (product and factor storage)
  // Threads for the frame's dense products (stage 5's (K*^-1 P*) AI, a small
  // operational system's kept inverse), a first touch's backward solve
  // (columns.hpp) and a nonlinear frame's element loops: 1, or 2 (a
  // HelperThread); 0: 2 when
  // the thread policy has two idle cores and the products are large enough
  // to pay for it (kHelperMinEntries). The bits are the same either way.
  int product_threads = 0;
};

// Dense entries read per frame (K*^-1 P*, plus a small operational system's
// inverse, plus the K22 factor where first touches read it) from which a second thread pays: the upper leg's (128k + 103k)
// frame goes from 27 to 17-19 us; far below, the hand-over costs more than the half saves.
constexpr double kHelperMinEntries = 65536;
// A tet of a nonlinear law in that count: its element pass (force and
// tangent, about 0.7 us) costs what reading ~300 entries does.
constexpr double kEntriesPerNonlinearTet = 300;

struct State {
  Eigen::MatrixX3d u;  // (nnode x 3) m: sets 1, I, s each frame; fixed rows 0; interior rows as last recovered
  std::shared_ptr<const OperationalSystem> operational;  // rest or cut operational system
  std::unique_ptr<OperationalSolver> solver;             // backend used by update() without one

  Eigen::VectorXd Ps_interact;       // (3|s|) N, interactive surface loads now applied
  std::vector<int> loaded_surface;   // surface positions with nonzero Ps_interact
  Eigen::VectorXd As_loads;          // (3|s|) m, K*^-1 (Ps0 + Ps_interact)
  Eigen::VectorXd P_prime;           // (3|I|) N, KI2 K22^-1 P2
  Eigen::VectorXd x_operational;     // (operational->size()) m, last solution (warm start)
  solve::SecantStart secant;         // a nonlinear frame's predicted Newton start
  long x_generation = -1;            // system the warm starts belong to
  long frames = 0;
  FrameReport last;
  std::unique_ptr<ColumnCache> columns;  // product and factor storage: columns of loaded nodes
  // Splits stage 5's product (and the solver's dense product) in two halves,
  // and first touches' backward solves by subtrees (core/helper_thread.hpp);
  // null: all of it on the calling thread.
  std::shared_ptr<HelperThread> helper;
  // Dense storage only: computes (K*^-1 P*) AI in stage 5 instead of the CPU
  // product (e.g. gpu::DeviceDenseProduct for large blocks). Null: CPU.
  std::shared_ptr<NonoperationalProduct> nonoperational_product;
  // CHOLMOD's workspace for this run's solves with the Model's K22 factor
  // (factor storage's stage 5, interior recovery): the factor is shared,
  // the workspace is not.
  std::unique_ptr<solve::SolveWorkspace> ws = std::make_unique<solve::SolveWorkspace>();
  fem::NonlinearWork nonlinear;      // element tangents of a nonlinear stage 4

  // Scratch (no allocation per frame).
  Eigen::MatrixX3d forces;           // (nnode x 3) N, operational forces of this frame
  std::vector<int> slot;             // (|s|) index into `pending` or -1
  std::vector<std::pair<int, Eigen::Vector3d>> pending;  // surface position, force
  std::vector<int> loaded_operational;
  std::vector<int> touched;          // surface positions whose columns stage 3 reads
};

// Fresh state (zero displacement, initial loads applied at the first update).
// `solver` defaults to CgSolver with tolerance 1e-10. `model` must outlive
// the state (its column cache reads the K22 factor).
State make_state(const Model& model, std::unique_ptr<OperationalSolver> solver = nullptr,
                 const StateOptions& opt = {});

// Queues the columns of these mesh nodes (surface nodes; others are ignored)
// for the state's worker thread, so their first load costs a lookup. No-op in
// dense storage.
void prefetch_columns(const Model& model, State& state, std::span<const int> nodes);

// One frame. `loads` is the complete set of interactive loads of this frame
// (forces add to the model's initial loads; a node absent from the list has
// none; repeated nodes add up). Throws softcut::Error on a bad load before
// changing the state.
const FrameReport& update(const Model& model, State& state, std::span<const Load> loads, OperationalSolver& solver,
                          const UpdateOptions& opt = {});
const FrameReport& update(const Model& model, State& state, std::span<const Load> loads,
                          const UpdateOptions& opt = {});

// Switches the state to a rebuilt operational system (cutting); the next
// update warm-starts from the current displacements.
void set_operational_system(State& state, std::shared_ptr<const OperationalSystem> sys);

// Interior nonoperational displacements for the state's current loads and AI,
// written into state.u (one solve with the K22 factor).
void recover_interior(const Model& model, State& state);

}  // namespace softcut::hybrid
