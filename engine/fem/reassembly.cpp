#include "fem/reassembly.hpp"

#include <algorithm>
#include <cstring>
#include <numeric>

namespace softcut::fem {

namespace {

// Bitwise comparison below needs Material without padding.
static_assert(sizeof(Material) == 12 * sizeof(double));

bool increasing(const std::vector<int>& v) {
  for (size_t k = 1; k < v.size(); ++k)
    if (v[k] <= v[k - 1]) return false;
  return true;
}

std::array<double, 12> corner_coords(const mesh::TetMesh& m, int t) {
  std::array<double, 12> x{};
  for (int k = 0; k < 4; ++k)
    for (int d = 0; d < 3; ++d) x[size_t(3 * k + d)] = m.nodes(m.tets(t, k), d);
  return x;
}

// `in` sized for the tets (increasing) of an assembly, their entries to record.
void size_for(AssemblyInputs& in, const std::vector<int>& tets) {
  in.tets = tets;
  in.corners.resize(tets.size());
  in.coords.resize(tets.size());
  in.material.resize(tets.size());
}

// Entry i of `in`: tet t's corners, their coordinates and its material (its
// nodes in range). One function for both, so that what a reassembly compares
// is what an assembly recorded.
void record(AssemblyInputs& in, size_t i, const mesh::TetMesh& m, const std::vector<Material>& tet_material, int t) {
  for (int k = 0; k < 4; ++k) in.corners[i][size_t(k)] = m.tets(t, k);
  in.coords[i] = corner_coords(m, t);
  in.material[i] = tet_material[size_t(t)];
}

}  // namespace

AssemblyInputs assembly_inputs(const mesh::TetMesh& m, const std::vector<Material>& tet_material,
                               const std::vector<int>& tets, const std::vector<int>& position, int num_positions) {
  AssemblyInputs in;
  in.node.assign(size_t(std::max(0, num_positions)), -1);
  for (int v = 0; v < int(position.size()); ++v)
    if (position[size_t(v)] >= 0 && position[size_t(v)] < num_positions) in.node[size_t(position[size_t(v)])] = v;
  if (!increasing(tets)) return in;
  size_for(in, tets);
  for (size_t i = 0; i < tets.size(); ++i) record(in, i, m, tet_material, tets[i]);
  return in;
}

BlockStiffness reassemble_node_blocks(const BlockStiffness& before, const AssemblyInputs& in, const mesh::TetMesh& m,
                                      const std::vector<Material>& tet_material, const std::vector<int>& tets_in,
                                      const std::vector<int>& position, int num_positions, ReassemblyReport* report,
                                      AssemblyInputs* next) {
  const int nn = m.num_nodes();
  ReassemblyReport rep;
  rep.rows = num_positions;
  auto whole = [&] {
    rep.rows_assembled = num_positions;
    BlockStiffness K = assemble_node_blocks(m, tet_material, tets_in, position, num_positions);
    if (next) *next = assembly_inputs(m, tet_material, tets_in, position, num_positions);
    if (report) *report = rep;
    return K;
  };
  std::vector<int> tets = tets_in;  // as assemble_node_blocks: empty = every tet
  if (tets.empty()) {
    tets.resize(size_t(m.num_tets()));
    std::iota(tets.begin(), tets.end(), 0);
  }
  const size_t nold = in.tets.size();
  if (int(position.size()) != nn || int(tet_material.size()) != m.num_tets() || !increasing(tets) ||
      !increasing(in.tets) || in.corners.size() != nold || in.coords.size() != nold || in.material.size() != nold ||
      before.nodes() != int(in.node.size()))
    return whole();  // (which names a bad position or material array)
  for (int p : position)
    if (p < -1 || p >= num_positions) return whole();
  for (int t : tets)  // before any node of a tet is read
    if (t < 0 || t >= m.num_tets()) return whole();

  // Mesh node of each new position, old position of each mesh node.
  std::vector<int> node_of(size_t(num_positions), -1), old_pos(size_t(nn), -1);
  for (int v = 0; v < nn; ++v) {
    const int p = position[size_t(v)];
    if (p < 0) continue;
    if (node_of[size_t(p)] >= 0) return whole();  // two nodes at one position: their rows merge
    node_of[size_t(p)] = v;
  }
  for (size_t q = 0; q < in.node.size(); ++q) {
    const int v = in.node[q];
    if (v >= nn) return whole();
    if (v >= 0) old_pos[size_t(v)] = int(q);
  }

  // Dirty nodes: the corners of tets that are new, changed or gone, and of
  // tets with a corner that joined or left the positions. Every other node's
  // row has the same tets, in the same order, adding the same matrices to
  // the same neighbours.
  std::vector<char> dirty(size_t(nn), 0);
  auto mark_old = [&](size_t k) {
    for (int v : in.corners[k])
      if (v >= 0 && v < nn) dirty[size_t(v)] = 1;
  };
  auto mark_new = [&](int t) {
    for (int c = 0; c < 4; ++c) dirty[size_t(m.tets(t, c))] = 1;
  };
  // The new tets' inputs (for the next reassembly) are gathered on the way,
  // and the tets that are not the same are checked as assemble_node_blocks
  // checks them (the others were when `inputs` were assembled).
  AssemblyInputs out;
  size_for(out, tets);
  std::vector<int> changed;
  size_t k = 0;
  for (size_t i = 0; i < tets.size(); ++i) {
    const int t = tets[i];
    for (int c = 0; c < 4; ++c)
      if (m.tets(t, c) < 0 || m.tets(t, c) >= nn) return whole();  // (which names the tet)
    record(out, i, m, tet_material, t);
    while (k < nold && in.tets[k] < t) mark_old(k++);  // gone
    bool same = k < nold && in.tets[k] == t;
    if (same) {
      same = out.corners[i] == in.corners[k] &&
             std::memcmp(out.coords[i].data(), in.coords[k].data(), sizeof(double) * 12) == 0 &&
             std::memcmp(&out.material[i], &in.material[k], sizeof(Material)) == 0;
      if (!same) mark_old(k);
      ++k;
    }
    if (!same) {
      mark_new(t);
      changed.push_back(t);
    }
  }
  while (k < nold) mark_old(k++);
  check_tets(m, tet_material, changed, "assemble_node_blocks");
  std::vector<char> moved(size_t(nn), 0);  // joined or left the positions
  bool any_moved = false;
  for (int v = 0; v < nn; ++v)
    if ((old_pos[size_t(v)] >= 0) != (position[size_t(v)] >= 0)) moved[size_t(v)] = 1, any_moved = true;
  for (int t : tets)
    for (int c = 0; any_moved && c < 4; ++c)
      if (moved[size_t(m.tets(t, c))]) {
        mark_new(t);
        break;
      }

  // Rows assembled afresh: dirty nodes', and those of nodes new to the positions.
  auto pos = [&](int t, int c) { return position[size_t(m.tets(t, c))]; };
  std::vector<char> fresh(size_t(num_positions), 1);
  for (int p = 0; p < num_positions; ++p) {
    const int v = node_of[size_t(p)];
    fresh[size_t(p)] = v < 0 || dirty[size_t(v)] || old_pos[size_t(v)] < 0;
  }
  // The tets with a corner in a fresh row, in order, and those rows' sorted
  // neighbour lists, as assemble_node_blocks builds them.
  std::vector<int> touching;
  for (int t : tets)
    for (int b = 0; b < 4; ++b)
      if (pos(t, b) >= 0 && fresh[size_t(pos(t, b))]) {
        touching.push_back(t);
        break;
      }
  std::vector<int> count(size_t(num_positions) + 1, 0);
  for (int t : touching)
    for (int b = 0; b < 4; ++b)
      if (pos(t, b) >= 0 && fresh[size_t(pos(t, b))]) count[size_t(pos(t, b)) + 1] += 4;
  std::partial_sum(count.begin(), count.end(), count.begin());
  std::vector<int> nbr(size_t(count.back())), end(count.begin(), count.end() - 1);
  for (int t : touching)
    for (int b = 0; b < 4; ++b)
      if (pos(t, b) >= 0 && fresh[size_t(pos(t, b))])
        for (int a = 0; a < 4; ++a)
          if (pos(t, a) >= 0) nbr[size_t(end[size_t(pos(t, b))]++)] = pos(t, a);

  BlockStiffness K;
  K.row_start.reserve(size_t(num_positions) + 1);
  K.row_start.push_back(0);
  K.col.reserve(before.col.size() + nbr.size() / 4);
  for (int p = 0; p < num_positions; ++p) {
    if (fresh[size_t(p)]) {
      ++rep.rows_assembled;
      auto b = nbr.begin() + count[size_t(p)], e = nbr.begin() + end[size_t(p)];
      std::sort(b, e);
      K.col.insert(K.col.end(), b, std::unique(b, e));
    } else {  // the old row's neighbours at their new positions (their order is kept)
      const int q = old_pos[size_t(node_of[size_t(p)])];
      for (int e = before.row_start[size_t(q)]; e < before.row_start[size_t(q) + 1]; ++e) {
        const int oc = before.col[size_t(e)];
        const int v = oc >= 0 && oc < int(in.node.size()) ? in.node[size_t(oc)] : -1;
        const int c = v >= 0 ? position[size_t(v)] : -1;
        if (c < 0 || (e > before.row_start[size_t(q)] && c <= K.col.back())) return whole();  // not expected
        K.col.push_back(c);
      }
    }
    K.row_start.push_back(int(K.col.size()));
  }
  K.blocks.resize(K.col.size());
  for (int p = 0; p < num_positions; ++p) {
    auto out = K.blocks.begin() + K.row_start[size_t(p)];
    if (fresh[size_t(p)]) {
      std::fill(out, K.blocks.begin() + K.row_start[size_t(p) + 1], Eigen::Matrix3d::Zero());
    } else {
      const int q = old_pos[size_t(node_of[size_t(p)])];
      std::copy(before.blocks.begin() + before.row_start[size_t(q)],
                before.blocks.begin() + before.row_start[size_t(q) + 1], out);
    }
  }
  // The fresh rows' sums, tet by tet in order, as the whole assembly adds them.
  for (int t : touching) {
    const std::array<int, 4> p{pos(t, 0), pos(t, 1), pos(t, 2), pos(t, 3)};
    const Mat12 Ke = element_stiffness(tet_corners(m, t), tet_material[size_t(t)]);
    for (int b = 0; b < 4; ++b)
      if (p[size_t(b)] >= 0 && fresh[size_t(p[size_t(b)])]) add_element_row(K, Ke, p, b);
  }
  rep.reused = true;
  if (report) *report = rep;
  if (next) {
    out.node = std::move(node_of);
    *next = std::move(out);
  }
  return K;
}

}  // namespace softcut::fem
