#include "hybrid/partition.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <numeric>

#include "core/error.hpp"
#include "fem/anchoring.hpp"
#include "mesh/surface.hpp"

namespace softcut::hybrid {

const char* to_string(NodeSet s) {
  switch (s) {
    case NodeSet::unused: return "unused";
    case NodeSet::fixed: return "fixed";
    case NodeSet::operational: return "operational (1)";
    case NodeSet::interface: return "interface (I)";
    case NodeSet::surface: return "nonoperational surface (s)";
    case NodeSet::interior: return "nonoperational interior (i)";
  }
  return "?";
}

namespace {

Eigen::Vector3d centroid(const mesh::TetMesh& m, int t) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (int k = 0; k < 4; ++k) c += m.node(m.tets(t, k));
  return c / 4.0;
}

template <class Pred>
std::vector<char> tets_where(const mesh::TetMesh& m, Pred pred) {
  std::vector<char> mask(size_t(m.num_tets()), 0);
  for (int t = 0; t < m.num_tets(); ++t) mask[size_t(t)] = pred(centroid(m, t)) ? 1 : 0;
  return mask;
}

// Every rigid part of the body (tets joined through faces, fem::anchor_parts)
// needs pinned nodes that stop all six rigid motions: three not on one line,
// fixed or shared with an anchored part. A part hanging by one node or one
// edge can turn about it and makes the stiffness matrix singular.
void check_parts_are_fixed(const mesh::TetMesh& m, const std::vector<char>& op_tet,
                           const std::vector<char>& is_fixed) {
  const fem::Anchoring A = fem::anchor_parts(m, {}, is_fixed);
  for (size_t p = 0; p < A.parts.size(); ++p) {
    const fem::Anchoring::Part& P = A.parts[p];
    if (P.anchored) continue;
    int op = 0;
    for (int t = 0; t < m.num_tets(); ++t) op += A.tet_part[size_t(t)] == int(p) && op_tet[size_t(t)];
    const int non = P.tets - op;
    const char* region = op == 0 ? "nonoperational region" : non == 0 ? "operational region"
                                                                     : "operational and nonoperational regions";
    const std::string where =
        cat("the connected part of the body containing node ", P.first_node, " (", P.tets, " tets: ", op,
            " operational, ", non, " nonoperational; in the ", region, "; bounding box [", P.lo.x(), ", ", P.lo.y(),
            ", ", P.lo.z(), "] .. [", P.hi.x(), ", ", P.hi.y(), ", ", P.hi.z(), "] m)");
    if (P.pin == fem::Anchoring::Pin::none)
      fail("hybrid partition: ", where, " has no fixed node, so its stiffness matrix is singular; "
           "fix at least three non-collinear nodes of that part");
    if (P.through_shared) fail("hybrid partition: ", where, " ", A.why_loose(int(p)));
    fail("hybrid partition: ", where, " has ", P.fixed, " fixed node(s), all on one line, so it "
         "can still rotate (singular stiffness matrix); fix at least three non-collinear nodes of that part");
  }
}

}  // namespace

std::vector<char> tets_with_label(const mesh::TetMesh& m, int label) {
  std::vector<char> mask(size_t(m.num_tets()), 0);
  for (int t = 0; t < m.num_tets(); ++t) mask[size_t(t)] = t < m.labels.size() && m.labels(t) == label;
  return mask;
}

std::vector<char> tets_in_sphere(const mesh::TetMesh& m, const Eigen::Vector3d& center, double radius) {
  return tets_where(m, [&](const Eigen::Vector3d& c) { return (c - center).norm() <= radius; });
}

std::vector<char> tets_in_box(const mesh::TetMesh& m, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  return tets_where(m, [&](const Eigen::Vector3d& c) {
    return (c.array() >= lo.array()).all() && (c.array() <= hi.array()).all();
  });
}

std::vector<char> tets_in_half_space(const mesh::TetMesh& m, const Eigen::Vector3d& point,
                                     const Eigen::Vector3d& normal) {
  return tets_where(m, [&](const Eigen::Vector3d& c) { return (c - point).dot(normal) >= 0; });
}

std::vector<char> tets_from_list(const mesh::TetMesh& m, const std::vector<int>& ids) {
  std::vector<char> mask(size_t(m.num_tets()), 0);
  for (int t : ids) {
    if (t < 0 || t >= m.num_tets())
      fail("hybrid partition: operational tet id ", t, " is out of range (the mesh has ", m.num_tets(),
           " tets, ids 0..", m.num_tets() - 1, ")");
    mask[size_t(t)] = 1;
  }
  return mask;
}

Partition make_partition(const mesh::TetMesh& m, const std::vector<char>& op_tet_in,
                         const std::vector<int>& fixed_nodes) {
  const int nn = m.num_nodes(), nt = m.num_tets();
  if (!op_tet_in.empty() && int(op_tet_in.size()) != nt)
    fail("hybrid partition: the operational tet mask has ", op_tet_in.size(), " entries for ", nt, " tets");
  Partition p;
  p.operational_tet = op_tet_in.empty() ? std::vector<char>(size_t(nt), 0) : op_tet_in;
  for (auto& c : p.operational_tet) c = c ? 1 : 0;

  std::vector<char> is_fixed(size_t(nn), 0), touch_op(size_t(nn), 0), touch_non(size_t(nn), 0);
  for (int v : fixed_nodes) {
    if (v < 0 || v >= nn)
      fail("hybrid partition: fixed node id ", v, " is out of range (the mesh has ", nn, " nodes, ids 0..",
           nn - 1, ")");
    is_fixed[size_t(v)] = 1;
  }
  for (int t = 0; t < nt; ++t) {
    const bool op = p.operational_tet[size_t(t)];
    (op ? p.operational_tets : p.nonoperational_tets).push_back(t);
    for (int k = 0; k < 4; ++k) (op ? touch_op : touch_non)[size_t(m.tets(t, k))] = 1;
  }
  std::vector<char> used(static_cast<size_t>(nn));
  for (int v = 0; v < nn; ++v) used[size_t(v)] = touch_op[size_t(v)] || touch_non[size_t(v)];
  check_parts_are_fixed(m, p.operational_tet, is_fixed);

  const std::vector<char> on_surface = mesh::surface_node_mask(m, mesh::extract_surface(m));
  p.node_set.assign(size_t(nn), NodeSet::unused);
  PartitionCounts& c = p.counts;
  for (int v = 0; v < nn; ++v) {
    const size_t i = size_t(v);
    NodeSet s = NodeSet::unused;
    if (!used[i]) s = NodeSet::unused;
    else if (is_fixed[i]) s = NodeSet::fixed;
    else if (touch_op[i] && touch_non[i]) s = NodeSet::interface;
    else if (touch_op[i]) s = NodeSet::operational;
    else s = on_surface[i] ? NodeSet::surface : NodeSet::interior;
    p.node_set[i] = s;
    switch (s) {
      case NodeSet::unused: ++c.unused; break;
      case NodeSet::fixed: p.fixed.push_back(v); break;
      case NodeSet::operational: p.operational.push_back(v); break;
      case NodeSet::interface: p.interface.push_back(v); break;
      case NodeSet::surface: p.surface.push_back(v); break;
      case NodeSet::interior: p.interior.push_back(v); break;
    }
    c.operational_region_nodes += touch_op[i];
    c.nonoperational_region_nodes += touch_non[i];
    c.nonoperational_surface_nodes += touch_non[i] && on_surface[i];
  }
  c.operational_tets = int(p.operational_tets.size());
  c.nonoperational_tets = int(p.nonoperational_tets.size());
  c.fixed = int(p.fixed.size());
  c.operational = int(p.operational.size());
  c.interface = int(p.interface.size());
  c.surface = int(p.surface.size());
  c.interior = int(p.interior.size());
  return p;
}

std::string describe(const PartitionCounts& c) {
  return cat("operational ", c.operational_region_nodes, " nodes / ", c.operational_tets,
             " tets; nonoperational ", c.nonoperational_region_nodes, " nodes / ",
             c.nonoperational_surface_nodes, " surface nodes / ", c.nonoperational_tets, " tets; sets: fixed ",
             c.fixed, ", 1 ", c.operational, ", I ", c.interface, ", s ", c.surface, ", i ", c.interior,
             ", unused ", c.unused);
}

}  // namespace softcut::hybrid
