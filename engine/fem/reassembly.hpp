#pragma once
// Reassembly of a block stiffness after a small change of its tets (a cut):
// the node rows that no changed tet touches are taken from the last assembly
// (their columns renumbered), the others assembled afresh. The result is
// assemble_node_blocks' of the new tets, bit for bit: each row's blocks are
// sums over the row's tets in tet order either way.
//
//   AssemblyInputs in = assembly_inputs(m, mat, tets, position);   // with K
//   ... cut: m, mat, tets, position change ...
//   BlockStiffness K2 = reassemble_node_blocks(K, in, m, mat, tets2, position2, n2);
#include <array>
#include <vector>

#include "fem/assembly.hpp"

namespace softcut::fem {

// What an assembly read: each tet's id, corners, corner coordinates and
// material, and the mesh node of each position. A tet of the next assembly
// with the same id and the same bits in all of these has the same element
// matrix and adds it to the same rows.
struct AssemblyInputs {
  std::vector<int> tets;                       // ids, increasing, as assembled
  std::vector<std::array<int, 4>> corners;     // (tets) mesh node ids
  std::vector<std::array<double, 12>> coords;  // (tets) corner coordinates, m
  std::vector<Material> material;              // (tets)
  std::vector<int> node;                       // (positions) mesh node at each position, -1 for none
};

// The inputs of assemble_node_blocks(m, tet_material, tets, position,
// num_positions); `tets` increasing (empty when they are not: nothing can
// then be reused).
AssemblyInputs assembly_inputs(const mesh::TetMesh& m, const std::vector<Material>& tet_material,
                               const std::vector<int>& tets, const std::vector<int>& position, int num_positions);

struct ReassemblyReport {
  int rows = 0;            // node rows of the result
  int rows_assembled = 0;  // of which assembled afresh (the others copied)
  bool reused = false;     // false: the whole matrix was assembled (nothing to reuse)
};

// assemble_node_blocks(m, tet_material, tets, position, num_positions) from
// `before`, assembled (and so checked) from `inputs`. The whole matrix is
// assembled when `tets` or the inputs' tets are not increasing, or a mesh
// node of `inputs` is no longer in the mesh. The same errors as
// assemble_node_blocks for the tets that are new or changed. `next`
// (optional): the inputs of this assembly, for the one after it.
BlockStiffness reassemble_node_blocks(const BlockStiffness& before, const AssemblyInputs& inputs,
                                      const mesh::TetMesh& m, const std::vector<Material>& tet_material,
                                      const std::vector<int>& tets, const std::vector<int>& position,
                                      int num_positions, ReassemblyReport* report = nullptr,
                                      AssemblyInputs* next = nullptr);

}  // namespace softcut::fem
