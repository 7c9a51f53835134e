#include "mesh/tet_mesh.hpp"

#include <Eigen/Geometry>  // cross()
#include <cmath>

namespace softcut::mesh {

double signed_volume(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                     const Eigen::Vector3d& d) {
  return (b - a).cross(c - a).dot(d - a) / 6.0;
}

double signed_volume(const TetMesh& m, int t) {
  return signed_volume(m.node(m.tets(t, 0)), m.node(m.tets(t, 1)), m.node(m.tets(t, 2)),
                       m.node(m.tets(t, 3)));
}

static double longest_edge(const TetMesh& m, int t) {
  double l = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) l = std::max(l, (m.node(m.tets(t, i)) - m.node(m.tets(t, j))).norm());
  return l;
}

ValidateReport validate(TetMesh& m, const std::string& source, Diagnostics& diag) {
  ValidateReport report;
  const int nn = m.num_nodes(), nt = m.num_tets();
  for (int i = 0; i < nn; ++i)
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite(m.nodes(i, c)))
        fail(source, ": node ", i, " has a non-finite coordinate (", m.nodes(i, c),
             "); fix or remove that node");
  if (m.labels.size() == 0) m.labels = Eigen::VectorXi::Zero(nt);
  if (m.labels.size() != nt)
    fail(source, ": ", m.labels.size(), " labels for ", nt, " tetrahedra");
  for (int t = 0; t < nt; ++t) {
    for (int k = 0; k < 4; ++k) {
      const int v = m.tets(t, k);
      if (v < 0 || v >= nn)
        fail(source, ": tetrahedron ", t, " refers to node ", v, ", but the mesh has nodes 0..", nn - 1);
      for (int j = 0; j < k; ++j)
        if (m.tets(t, j) == v) fail(source, ": tetrahedron ", t, " uses node ", v, " twice");
    }
    const double vol = signed_volume(m, t);
    const double l = longest_edge(m, t);
    if (!(std::abs(vol) > kDegenerateVolume * l * l * l))
      fail(source, ": tetrahedron ", t, " (nodes ", m.tets(t, 0), " ", m.tets(t, 1), " ", m.tets(t, 2), " ",
           m.tets(t, 3), ") is degenerate: volume ", vol, " m^3 for longest edge ", l,
           " m; remove it or fix its nodes");
    if (vol < 0) {
      std::swap(m.tets(t, 2), m.tets(t, 3));
      ++report.reoriented;
    }
  }
  if (report.reoriented > 0)
    diag.warn(source, ": reoriented ", report.reoriented, " negatively oriented tetrahedra");
  const auto used = referenced_nodes(m);
  for (int i = 0; i < nn; ++i)
    if (!used[i]) report.unreferenced.push_back(i);
  if (!report.unreferenced.empty())
    diag.warn(source, ": ", report.unreferenced.size(), " node(s) are used by no tetrahedron (first: ",
              report.unreferenced.front(), "); they keep their ids and are left out of the system");
  return report;
}

std::vector<char> referenced_nodes(const TetMesh& m) {
  std::vector<char> used(size_t(m.num_nodes()), 0);
  for (int t = 0; t < m.num_tets(); ++t)
    for (int k = 0; k < 4; ++k) used[size_t(m.tets(t, k))] = 1;
  return used;
}

double total_volume(const TetMesh& m) {
  double v = 0;
  for (int t = 0; t < m.num_tets(); ++t) v += signed_volume(m, t);
  return v;
}

}  // namespace softcut::mesh
