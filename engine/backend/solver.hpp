#pragma once
// The elastic solve of a run, and the ONE place where it is chosen:
// make_solver() returns the hybrid backend (hybrid::precompute once,
// hybrid::update per frame; backend/hybrid_solver) with the operational
// backend named by SolverSpec::backend (cpu CG, gpu compute-shader CG, direct
// CHOLMOD), or the whole-mesh CHOLMOD reference ("monolithic";
// backend/monolithic_solver). Nothing after this stage knows which.
#include <Eigen/Core>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "backend/spec.hpp"
#include "core/error.hpp"
#include "core/stop_flags.hpp"
#include "fem/grip_springs.hpp"
#include "fem/material.hpp"
#include "gpu/dense_product.hpp"
#include "hybrid/columns.hpp"
#include "hybrid/partition.hpp"
#include "hybrid/precompute_cache.hpp"
#include "mesh/tet_mesh.hpp"

namespace softcut::backend {

// What the application lends a run. The library never creates an OpenGL
// context: the CLI makes one (for rendering or the GPU backend) and passes it
// here; it must outlive the Model (the GPU solver keeps it) and be current on
// the stepping thread.
struct RunResources {
  gl::EglContext* context = nullptr;
  StopFlags stop;  // Ctrl-C and the watchdog, polled by the precompute (core/stop_flags.hpp)
};

// The operational backend actually used and why (written to summary.json).
struct BackendChoice {
  Backend requested;      // SolverSpec::backend as given
  Backend backend;        // chosen: cpu, gpu, direct or monolithic (never automatic)
  std::string reason;     // one sentence, e.g. "auto: llvmpipe (...) is a software rasteriser; CPU CG"
  std::string device;     // the context's GL renderer (+ ", software"), empty without a context
  bool gpu_fp64 = false;  // backend gpu: fp64 kernels (else fp32 + fp64 refinement)
  // Stage 5's dense product (K*^-1 P*) AI on the context's device when the
  // block has at least device_product_min_entries entries: backend gpu, and
  // auto on a hardware GPU (measured: docs/bench-gpu.md). From choose_backend
  // it says the device may be used; a Solver's backend() says whether it is
  // (then, like backend gpu, the run needs the context on its own thread).
  bool device_product = false;
  double device_product_min_entries = gpu::DeviceDenseProduct::kWorthwhileEntries;
};

// Resolves SolverSpec::backend against the context's description (null: no
// context): automatic -> direct (see the reason in solver.cpp), with stage 5
// on a hardware GPU's device; gpu -> the device even when it is software
// (llvmpipe), an Error when there is no context or no compute shaders.
BackendChoice choose_backend(const SolverSpec& spec, const gl::ContextInfo* context);

// Every solve is checked: a relative residual ||b - A x|| / ||b|| above
// kMaxRelativeResidual (or NaN) is an error naming `what`, never a result (a
// nearly singular system gives huge, wrong displacements from a factorization
// that "succeeded").
constexpr double kMaxRelativeResidual = 1e-8;
void check_solve_residual(double relative_residual, const char* what);

// Backend-owned per-run data (e.g. hybrid::State: warm start, running sums).
struct SolverRunState {
  virtual ~SolverRunState() = default;
};

// Per-run mutable solver data kept in State (Solver::start_run makes it):
// warm starts, running sums, the cut system, the column cache, device
// buffers. Owned by one run: a State is not copied implicitly.
struct SolverRun {
  std::unique_ptr<SolverRunState> backend;
};

struct SolveStats {
  int cg_iterations = 0;          // 0 for direct solves; a nonlinear frame's PCG iterations, all Newton steps
  double relative_residual = 0;   // of the operational system
  double loads_ms = 0;            // stage 2: checking and sorting the loads
  double operational_ms = 0;      // stage 4
  double nonoperational_ms = 0;   // stages 3 + 5
  // A nonlinear frame (a nonlinear law, or a prescribed motion): Newton's steps.
  bool newton = false;
  int newton_iterations = 0;
  int projected_steps = 0;        // steps that needed projected element tangents
  bool at_floor = false;          // Newton ended at its residual's rounding floor (solve/newton.hpp)
  double max_rotation = 0;        // rad, largest rotation of a nonlinear tet
  double max_strain = 0;          // largest |principal stretch - 1| of a nonlinear tet
  int inverted = 0;               // nonlinear tets inverted at the solution
};

// What a frame asks of the solve besides its nodal forces.
struct FrameInput {
  // (nnode x 3) m: the displacement of the fixed nodes (rows of other nodes
  // ignored); null: all zero.
  const Eigen::MatrixX3d* prescribed = nullptr;
  // A nonlinear model's grasper springs, solved inside the Newton iteration
  // (Solver::nonlinear()); null: none.
  const fem::GripSprings* springs = nullptr;
};

// The body a cut left, as a solver rebuilds its system from it: the fields of
// cut::CutMesh (a later stage). `carry` maps a nodal field of the body before
// the cut step (nodes_before rows) onto this body (the warm start); it is
// empty when a run starts on a cut body (State's explicit copy).
struct CutBody {
  const mesh::TetMesh& mesh;
  const std::vector<fem::Material>& tet_material;  // ntet
  const std::vector<char>& operational_tet;        // ntet: 1 in the operational region
  const std::vector<char>& node_fixed;             // nnode: 1 where the solve does not solve for the node
  int nodes_before = -1;
  std::function<Eigen::MatrixX3d(const Eigen::MatrixX3d&)> carry;
};

class Solver {
 public:
  virtual ~Solver() = default;
  virtual std::string name() const = 0;  // e.g. "hybrid (dense storage, operational cg)"
  // forces (nnode x 3), N -> u (nnode x 3), m. Fixed nodes get their
  // prescribed displacement (zero unless `in` gives one). Rows of
  // nonoperational interior nodes are valid only when interior_valid().
  virtual void solve(const Eigen::MatrixX3d& forces, Eigen::MatrixX3d& u, SolverRun& warm, SolveStats& stats,
                     const FrameInput& in = {}) const = 0;
  // Some solved tet has a nonlinear law: every frame is a Newton solve, and
  // implicit graspers go inside it (FrameInput::springs) instead of being
  // superposed on the unit responses afterwards.
  virtual bool nonlinear() const = 0;
  virtual bool interior_valid() const = 0;
  // Precompute timings, ms, by stage name (Table 3), in a stable order.
  virtual std::vector<std::pair<std::string, double>> precompute_ms() const = 0;
  virtual const BackendChoice& backend() const = 0;
  // A new run's solver data (on the device for backend gpu: its buffers,
  // sharing the kernels compiled with the Model). When `cut` is given the run
  // starts on that cut body's system (State's explicit copy).
  virtual void start_run(SolverRun& warm, const CutBody* cut) const = 0;
  // Hint: these nodes will be loaded (scripted tool paths); the hybrid
  // backends compute their columns on a worker thread (hybrid/columns.hpp).
  virtual void prefetch(const std::vector<int>& nodes, SolverRun& warm) const {
    (void)nodes, (void)warm;
  }
  // The run's column cache (hybrid backends in product or factor storage), else nullopt.
  virtual std::optional<hybrid::ColumnStats> column_stats(const SolverRun& warm) const {
    (void)warm;
    return std::nullopt;
  }
  // The precompute cache's report (hybrid backends with a cache folder), else null.
  virtual const hybrid::CacheReport* precompute_cache() const { return nullptr; }

  // Displacement fields of unit loads: column 3j + a of `out` (3 nnode x 3m,
  // m/N, rows 3 node + axis) is u for 1 N on nodes[j] along axis a and no
  // other load, through the same solve as solve() (for the hybrid model one
  // update per column on a scratch state: the paper's selective columns).
  // nodes: free (not fixed), not interior-nonoperational. Leaves `warm`'s
  // frame state unchanged (it may keep scratch data there).
  virtual void unit_responses(const std::vector<int>& nodes, SolverRun& warm, Eigen::MatrixXd& out) const = 0;
  // Identifies the system solve() uses now (changes when cutting rebuilds
  // the operational system); caches of unit_responses() are keyed by it.
  virtual long system_generation(const SolverRun& warm) const = 0;
  // After a cut step changed the body to `cut`: rebuilds the run's system
  // (hybrid: only the operational one, K' and the rest stay), carries the
  // warm start onto the new nodes, bumps system_generation().
  virtual void apply_cut(const CutBody& cut, SolverRun& warm) const = 0;
};

// tet_material (ntet). need_interior: interior nonoperational rows of u are
// wanted every frame (logged or exported), at one extra factor solve a frame.
// Notes go to diag. The GPU backend compiles its kernels here, in
// resources.context (see choose_backend for which backend is used).
std::unique_ptr<Solver> make_solver(const mesh::TetMesh& m, const std::vector<fem::Material>& tet_material,
                                    const hybrid::Partition& partition, const SolverSpec& spec, bool need_interior,
                                    const RunResources& resources, Diagnostics& diag);

}  // namespace softcut::backend
