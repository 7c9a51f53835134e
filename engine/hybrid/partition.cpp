#include "hybrid/partition.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <numeric>

#include "core/error.hpp"
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

// Union-find over node ids.
struct Components {
  std::vector<int> parent;
  explicit Components(int n) : parent(size_t(n)) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int a) {
    while (parent[size_t(a)] != a) a = parent[size_t(a)] = parent[size_t(parent[size_t(a)])];
    return a;
  }
  void unite(int a, int b) {
    a = find(a), b = find(b);
    if (a != b) parent[size_t(std::max(a, b))] = std::min(a, b);
  }
};

// Every connected part of the body needs fixed nodes that pin all six rigid
// motions: at least three not on one line. (Parts joined through a single node
// or edge can still be singular; the Cholesky factorisation reports those.)
void check_parts_are_fixed(const mesh::TetMesh& m, const std::vector<char>& op_tet,
                           const std::vector<char>& is_fixed, const std::vector<char>& used) {
  const int nn = m.num_nodes();
  Components comp(nn);
  for (int t = 0; t < m.num_tets(); ++t)
    for (int k = 1; k < 4; ++k) comp.unite(m.tets(t, 0), m.tets(t, k));
  struct Part {
    int tets_op = 0, tets_non = 0;
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = Eigen::Vector3d::Constant(-1e300);
    std::vector<int> fixed;
  };
  std::vector<Part> parts(static_cast<size_t>(nn));
  for (int t = 0; t < m.num_tets(); ++t) {
    Part& p = parts[size_t(comp.find(m.tets(t, 0)))];
    (op_tet[size_t(t)] ? p.tets_op : p.tets_non)++;
  }
  for (int v = 0; v < nn; ++v) {
    if (!used[size_t(v)]) continue;
    Part& p = parts[size_t(comp.find(v))];
    p.lo = p.lo.cwiseMin(m.node(v));
    p.hi = p.hi.cwiseMax(m.node(v));
    if (is_fixed[size_t(v)]) p.fixed.push_back(v);
  }
  for (int root = 0; root < nn; ++root) {
    const Part& p = parts[size_t(root)];
    if (!used[size_t(root)] || comp.find(root) != root) continue;
    const char* region = p.tets_op == 0 ? "nonoperational region"
                         : p.tets_non == 0 ? "operational region" : "operational and nonoperational regions";
    auto where = [&] {
      return cat("the connected part of the body containing node ", root, " (", p.tets_op + p.tets_non,
                 " tets: ", p.tets_op, " operational, ", p.tets_non, " nonoperational; in the ", region,
                 "; bounding box [", p.lo.x(), ", ", p.lo.y(), ", ", p.lo.z(), "] .. [", p.hi.x(), ", ",
                 p.hi.y(), ", ", p.hi.z(), "] m)");
    };
    if (p.fixed.empty())
      fail("hybrid partition: ", where(), " has no fixed node, so its stiffness matrix is singular; "
           "fix at least three non-collinear nodes of that part");
    // Largest distance of a fixed node from the line through two far-apart ones.
    const Eigen::Vector3d a = m.node(p.fixed.front());
    int far = p.fixed.front();
    for (int v : p.fixed)
      if ((m.node(v) - a).squaredNorm() > (m.node(far) - a).squaredNorm()) far = v;
    const Eigen::Vector3d d = m.node(far) - a;
    double off = 0;
    if (d.norm() > 0)
      for (int v : p.fixed) off = std::max(off, (m.node(v) - a).cross(d).norm() / d.norm());
    const double size = (p.hi - p.lo).norm();
    if (!(off > 1e-9 * size))
      fail("hybrid partition: ", where(), " has ", p.fixed.size(), " fixed node(s), all on one line, so it "
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
  check_parts_are_fixed(m, p.operational_tet, is_fixed, used);

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
