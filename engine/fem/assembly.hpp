#pragma once
// One assembler for every stiffness matrix: the whole mesh, the operational
// tets (K^op) or the nonoperational tets (K^non). DOF numbering is global:
// dof = 3 * node + axis over all nodes of the mesh; nodes outside the tet set
// get empty rows and columns.
#include <Eigen/SparseCore>
#include <array>
#include <vector>

#include "core/stop_flags.hpp"
#include "fem/element_stiffness.hpp"
#include "fem/material.hpp"

namespace softcut::fem {

using SparseMatrix = Eigen::SparseMatrix<double>;  // column-major, int indices

// K (3 nnode x 3 nnode), N/m, symmetric, both triangles stored, from the tets
// listed in `tets` (all tets when empty). `tet_material` has one entry per tet
// of the mesh. The sparsity pattern is built per 3x3 node block, then element
// matrices are scattered straight into it (no triplet list). `threads` > 1
// splits the columns into node ranges, each thread computing the elements that
// touch its range ("owner computes": no atomics, no shared writes); 0 picks
// the hardware concurrency for large sets and 1 thread below ~20k tets. The
// result does not depend on the thread count (same additions, same order per
// entry). Throws softcut::Error naming the tet for ids out of range, a
// degenerate or inverted tet (run mesh::validate first), or a bad material.
// `stop` (optional) is polled every few thousand tets: a stop request ends
// the assembly with its InterruptedError / TimeoutError (core/stop_flags.hpp).
SparseMatrix assemble_stiffness(const mesh::TetMesh& m, const std::vector<Material>& tet_material,
                                const std::vector<int>& tets = {}, int threads = 0, const StopFlags* stop = nullptr);

// K of the tets restricted to a subset of nodes and renumbered, in 3x3 node
// blocks (block CSR; K is symmetric, so node row j is node column j):
// K(3 row + a, 3 col + b) = blocks[k](a, b) for the blocks k of node row
// `row`, their column nodes in increasing order. Each entry receives the same
// additions in the same order as assemble_stiffness's, so to_sparse() equals
// that matrix's rows and columns of the subset bit for bit (pairs with a node
// outside the subset dropped, structural zeros kept).
// Throws, naming the tet, on everything that would make an element matrix
// wrong: a tet id or node out of range, a bad material, an inverted or
// degenerate tet; `who` starts the message. The assemblers call it before any
// (possibly threaded) work starts.
void check_tets(const mesh::TetMesh& m, const std::vector<Material>& tet_material, const std::vector<int>& tets,
                const char* who);

struct BlockStiffness {
  std::vector<int> row_start;            // (nodes + 1) first block of each node row
  std::vector<int> col;                  // node column of each block
  std::vector<Eigen::Matrix3d> blocks;   // N/m

  int nodes() const { return int(row_start.size()) - 1; }
  // (3 nodes x 3 nodes), both triangles stored.
  SparseMatrix to_sparse() const;
};

// Adds an element matrix (tet corners' positions `pos`, -1: not in the
// subset) into block row pos[b] of K, whose pattern holds the row's
// neighbours: the one addition every block assembler makes, so that they all
// sum the same terms the same way (bit for bit).
void add_element_row(BlockStiffness& K, const Mat12& Ke, const std::array<int, 4>& pos, int b);

// `position` (nnode) numbers the subset's nodes 0..num_positions-1 (-1: not
// in it). Same checks as assemble_stiffness. Used after every cut: it skips
// the whole-mesh pattern and the extraction of the subset (8k tets: 10 -> 5 ms).
// `threads` (at most 2) splits the node rows in two ranges, owner computes
// as above; 0: two from 2,000 tets when the thread policy has two.
BlockStiffness assemble_node_blocks(const mesh::TetMesh& m, const std::vector<Material>& tet_material,
                                    const std::vector<int>& tets, const std::vector<int>& position,
                                    int num_positions, int threads = 0);

// The same matrix through Eigen's setFromTriplets (144 triplets per tet): the
// baseline `softcut bench assembly` compares against, and a reference in tests.
SparseMatrix assemble_stiffness_triplets(const mesh::TetMesh& m, const std::vector<Material>& tet_material,
                                         const std::vector<int>& tets = {});

// The tets' constant loads, (nnode x 3) N: the equivalent nodal forces of
// their initial strains (Material::initial_strain), f0 = V B^T D eps0 per
// tet, and their body forces (Material::body_force), V b / 4 on each
// corner; summed over the tets listed in `tets` (all when empty); nodes
// outside the set get zero. They enter K u = f + f0, so the stress
// D (B u - eps0) of a free body with a uniform eps0 vanishes at u = the
// matching uniform strain. Same checks as assemble_stiffness.
Eigen::MatrixX3d element_loads(const mesh::TetMesh& m, const std::vector<Material>& tet_material,
                               const std::vector<int>& tets = {});
// True when some tet's material has an initial strain or a body force.
bool any_element_load(const std::vector<Material>& tet_material);

// Elastic strain energy 1/2 u^T K u of a displacement field (nnode x 3), J,
// summed element by element (independent of the assembler; used in tests).
double strain_energy(const mesh::TetMesh& m, const std::vector<Material>& tet_material,
                     const Eigen::MatrixX3d& u);

}  // namespace softcut::fem
