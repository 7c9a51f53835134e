#pragma once
// Precompute of the hybrid condensed model (paper Table 1 "new model",
// DESIGN.md §1): everything about the nonoperational region that stays fixed
// while the simulation runs, from ONE sparse Cholesky factor of K22 (rows and
// columns = the free nonoperational nodes 2 = s ∪ i, surface nodes first).
//
//   K'                = K2II - KI2 K22^-1 K2I          (3|I| x 3|I|)
//   (KI2 K22^-1)[:,s] = ((K22^-1 K2I)[s,:])^T          (3|I| x 3|s|)
//   K*^-1             = (K22^-1)_ss                   (3|s| x 3|s|)
//   K*^-1 P*          = -(K22^-1 K2I)[s,:]             (3|s| x 3|I|)
//   K*^-1 Ps0         = (K22^-1 [Ps0; Pi0])_s          (3|s|) (Pi0: interior
//                       loads of initial strains, DESIGN.md "Initial strain")
//
// Storage (all give the same displacements):
//   dense    the paper's scheme: every block above, O(|s|^2) memory; per
//            frame, selective multiplication and one dense product.
//   product  K' and K*^-1 P* (3|s| x 3|I|) only; the columns of K*^-1 and
//            (KI2 K22^-1) a loaded node needs come from the factor on first
//            touch (columns.hpp). The full surface is one bandwidth-bound
//            dense product per frame, precompute grows with |I| not |s|.
//   factor   K' only; the full surface is one K22 solve pair per frame.
// automatic picks product when K*^-1 P* fits the memory budget and reading it
// costs less than a solve with the factor (8 bytes per entry against about
// 24 bytes per factor nonzero), else factor. The K22 factor is kept in every
// mode (first touches, interior recovery).
//
// Usage (libigl/MuJoCo style):
//   Partition p = make_partition(mesh, tets_in_sphere(mesh, c, r), fixed_ids);
//   Model model = precompute(mesh, materials, p, {});
//   State state = make_state(model);                 // update.hpp
//   update(model, state, loads);                     // per frame
#include <Eigen/Core>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "core/stop_flags.hpp"
#include "fem/material.hpp"
#include "hybrid/operational_system.hpp"
#include "hybrid/partition.hpp"
#include "mesh/tet_mesh.hpp"
#include "solve/cholesky.hpp"

namespace softcut::hybrid {

enum class Storage { automatic, dense, product, factor };
const char* to_string(Storage s);
// The names users write (Lua's solver `mode`): "auto", "dense", "product",
// "factor". Throws softcut::Error naming the accepted values.
Storage parse_storage(std::string_view text);

struct PrecomputeOptions {
  Storage storage = Storage::automatic;
  double memory_budget_bytes = 512.0 * 1024 * 1024;  // automatic: dense if its blocks fit
  // The most the chosen mode's blocks may take, bytes (the sandbox's memory
  // budget); a mode that needs more, asked for or not, is an error before
  // anything large is allocated.
  double max_bytes = std::numeric_limits<double>::infinity();
  Eigen::MatrixX3d initial_loads;  // (nnode x 3) N, Ps0 and initial operational loads; empty = none
  int block_columns = 256;         // right-hand sides per CHOLMOD solve (bounds temporary memory)
  // Column blocks solved at once (two CHOLMOD solves side by side on
  // single-threaded BLAS): 1 or 2; 0: 2 when the thread policy has two idle
  // cores and a second block's temporary memory fits. The bits are the same either way.
  int block_threads = 0;
  // Polled between pieces of work (assembly, column blocks): a stop request
  // ends the precompute at once with its InterruptedError / TimeoutError.
  // Not part of the cache key.
  StopFlags stop;
};

// Table 3 rows, ms. Solves shared by two rows are booked where first needed.
struct PrecomputeTimings {
  double assemble_ms = 0;        // K^non over the nonoperational tets + block extraction
  double factor_ms = 0;          // CHOLMOD factor of K22
  double K_prime_ms = 0;         // solves K22^-1 K2I (column blocks) and K' = K2II - KI2 Y
  double KI2_K22inv_ms = 0;      // (KI2 K22^-1)[:, s] (transpose of the s rows of Y)
  double Kstar_inv_ms = 0;       // solves K22^-1 E_s, rows s
  double Kstar_inv_Pstar_ms = 0; // -(Y rows s), copied while K' is formed
  double Kstar_inv_Ps0_ms = 0;
  double operational_ms = 0;     // operational system assembly
  double total_ms = 0;
};

struct MemoryEstimate {
  double dense_bytes = 0;      // K*^-1, K*^-1 P*, (KI2 K22^-1)[:,s], K' and solve temporaries
  double product_bytes = 0;    // K*^-1 P*, K' and solve temporaries
  double factor_bytes = 0;     // K' and solve temporaries (the CHOLMOD factor itself not counted)
  double factor_nonzeros = 0;  // of the K22 factor (its solve reads them twice)
  double budget_bytes = 0;
};

struct Model {
  int num_nodes = 0;                         // nnode of the rest mesh
  Partition partition;
  std::vector<fem::Material> tet_material;   // (ntet)
  std::vector<char> node_fixed;              // (nnode)
  std::vector<char> node_nonoperational;     // (nnode) sets s and i
  std::vector<int> nonop_nodes;              // (|s| + |i|) surface ids then interior ids: K22 node order
  std::vector<int> surface_index;            // (nnode) position of a node in the surface set, -1 if none
  Storage storage = Storage::dense;          // resolved: dense, product or factor
  MemoryEstimate memory;

  solve::Cholesky K22;                       // factor of K22 ((3|2|)^2), both modes
  SparseMatrix K2I;                          // (3|2| x 3|I|) N/m
  SparseMatrix KI2;                          // (3|I| x 3|2|) = K2I^T
  std::shared_ptr<const Eigen::MatrixXd> K_prime;  // (3|I| x 3|I|) N/m

  // Dense mode only (empty otherwise):
  Eigen::MatrixXd Kstar_inv;        // (3|s| x 3|s|) m/N
  Eigen::MatrixXd KI2_K22inv_s;     // (3|I| x 3|s|) dimensionless
  // Dense and product modes (empty in factor mode):
  Eigen::MatrixXd Kstar_inv_Pstar;  // (3|s| x 3|I|) dimensionless
  Eigen::VectorXd Kstar_inv_Ps0;    // (3|s|) m

  // Initial loads: the given ones plus the initial strains' forces of the
  // nonoperational tets (on s, i and I; the operational tets' are the
  // operational system's `prestress`).
  Eigen::MatrixX3d initial_loads;   // (nnode x 3) N
  Eigen::VectorXd Ps0;              // (3|s|) N, initial surface loads
  Eigen::VectorXd Pi0;              // (3|i|) N, initial interior loads (initial strains only)
  Eigen::VectorXd P_prime0;         // (3|I|) N, KI2 K22^-1 P2 for the initial loads

  std::shared_ptr<const OperationalSystem> operational;  // from the rest mesh
  PrecomputeTimings timings;

  int ns() const { return int(partition.surface.size()); }
  bool has_Kstar_inv_Pstar() const { return storage == Storage::dense || storage == Storage::product; }
  int ni() const { return int(partition.interface.size()); }
};

// Precomputes the model. `tet_material` has one entry per tet. Throws
// softcut::Error on a singular K22 or bad sizes.
Model precompute(const mesh::TetMesh& m, const std::vector<fem::Material>& tet_material, const Partition& p,
                 const PrecomputeOptions& opt = {});

// The cheap parts of precompute() that a cached model shares
// (precompute_cache.hpp): the checks, node sets and initial loads; and the
// operational system from the mesh and M.K_prime.
Model setup_model(const mesh::TetMesh& m, const std::vector<fem::Material>& tet_material, const Partition& p,
                  const PrecomputeOptions& opt);
void build_operational(const mesh::TetMesh& m, Model& M);

// Rebuilds the operational system of a changed operational mesh (cutting): `m`
// is the rest mesh with changed operational tets and nodes appended after the
// original ones; `tet_material` (m.num_tets()); `operational_tets` the
// operational tets of `m`; `new_fixed` (optional, m.num_nodes()) marks fixed
// nodes, default: the model's fixed nodes, appended nodes free. Nonoperational
// data of the model are reused unchanged. `before` (optional): the system
// being replaced, whose unchanged rows of K are reused (build_operational_system).
std::shared_ptr<const OperationalSystem> rebuild_operational_system(
    const Model& model, const mesh::TetMesh& m, const std::vector<fem::Material>& tet_material,
    const std::vector<int>& operational_tets, const std::vector<char>& new_fixed = {},
    const OperationalSystem* before = nullptr, fem::ReassemblyReport* report = nullptr);

// One line: storage mode, why, memory estimate and per-item times.
std::string describe(const Model& model);

}  // namespace softcut::hybrid
