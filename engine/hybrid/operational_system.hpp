#pragma once
// The operational system of the hybrid model (paper Eq. 12, DESIGN.md §1):
//
//   [ K11   K1I       ] [A1]   [ P1        ]
//   [ KI1   K1II + K' ] [AI] = [ PI_ext - P' ]
//
// plus, on the right, the initial strains' forces of the operational tets
// (`prestress`, rebuilt with the system when a cut splits them).
//
// K (K11, K1I, KI1, K1II) is assembled from the operational tets only; K' is
// the dense Schur complement of the nonoperational region on the interface
// DOFs (precomputed once, never changes). Cutting changes only operational
// tets and appends nodes, so this system is rebuilt from the cut mesh while K'
// and every other precomputed block stay valid.
//
// DOF ordering (shared with the GPU solver):
//   unknown node k, 0 <= k < size_nodes(), is mesh node nodes[k]; its DOFs are
//   3k + axis (axis 0,1,2 = x,y,z).
//   nodes[0 .. num_operational)     set-1 nodes (free, touched only by
//                                   operational tets, including nodes appended
//                                   by cutting), increasing node id;
//   nodes[num_operational .. end)   the interface nodes, in the model's
//                                   interface order (increasing node id).
//   So the interface DOFs are the LAST 3*num_interface DOFs, contiguous,
//   starting at interface_offset() = 3*num_operational, and K' row/column j is
//   system DOF interface_offset() + j.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <string>
#include <vector>

#include "fem/assembly.hpp"
#include "fem/material.hpp"
#include "fem/nonlinear_tets.hpp"
#include "fem/reassembly.hpp"
#include "hybrid/node_blocks.hpp"
#include "mesh/tet_mesh.hpp"

namespace softcut::hybrid {

struct OperationalSystem {
  std::vector<int> nodes;       // (num_operational + num_interface) mesh node id of each unknown node
  std::vector<int> node_index;  // (nnode of the operational mesh) position in `nodes`, -1 if none
  int num_operational = 0;      // |1|
  int num_interface = 0;        // |I|
  SparseMatrix K;               // (3n x 3n) N/m, operational tets only, both triangles stored
  std::shared_ptr<const Eigen::MatrixXd> K_prime;  // (3|I| x 3|I|) N/m, dense, on the last 3|I| DOFs
  long generation = 0;          // unique per build; solvers cache per-system data by it
  // (size()) N: f0 = sum V B^T D eps0 of the operational tets on the unknowns;
  // empty when none of them has an initial strain.
  Eigen::VectorXd prestress;
  // K again in 3x3 node blocks, row by row (block CSR; K is symmetric), made by
  // build_operational_system: apply() runs on it, 3x faster than the scalar
  // sparse product. Empty for a hand-made system: apply() uses K then.
  fem::BlockStiffness block;
  // What `block` was assembled from, so that the system of a cut mesh
  // reassembles only the rows the cut changed (fem/reassembly.hpp).
  std::shared_ptr<const fem::AssemblyInputs> assembly;
  // The operational tets a nonlinear frame (nonlinear_solve.hpp) evaluates
  // itself: those of a nonlinear law and those with a fixed corner (a
  // prescribed motion's load). Null when there are none.
  std::shared_ptr<const fem::NonlinearTets> nonlinear;
  // Some operational tet has a nonlinear law: every frame is a Newton solve
  // (else only frames with a prescribed motion are).
  bool nonlinear_law = false;

  int size() const { return int(3 * nodes.size()); }
  int interface_offset() const { return 3 * num_operational; }

  // y = (K + K') x, x and y of size(); y is resized.
  void apply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const;
  // K with K' added into its interface block (sparse with a dense corner), for
  // direct solvers and checks.
  SparseMatrix assembled() const;
  // b = [P1; PI - P'] + prestress from per-node forces (nnode x 3, N; rows of other nodes
  // are ignored) and P' (3|I|, N).
  Eigen::VectorXd rhs(const Eigen::MatrixX3d& forces, const Eigen::VectorXd& P_prime) const;
};

// Builds the system from the operational tets of a mesh. `interface_nodes`
// are the model's interface node ids (kept last, in this order, even if no
// operational tet touches one any more); `node_fixed` (nnode) marks fixed
// nodes. K_prime must be (3|I| x 3|I|). Throws when an operational tet uses a
// nonoperational node that is not an interface node (the precomputed data
// would no longer describe the nonoperational region). `before` (optional):
// the system this one replaces (a cut); the rows of K that no changed tet
// touches are taken from it, with the same result bit for bit; `report`
// (optional) says how many rows were assembled.
OperationalSystem build_operational_system(const mesh::TetMesh& m, const std::vector<fem::Material>& tet_material,
                                           const std::vector<int>& operational_tets,
                                           const std::vector<int>& interface_nodes,
                                           const std::vector<char>& node_fixed,
                                           const std::vector<char>& node_nonoperational,
                                           std::shared_ptr<const Eigen::MatrixXd> K_prime,
                                           const OperationalSystem* before = nullptr,
                                           fem::ReassemblyReport* report = nullptr);

}  // namespace softcut::hybrid
