#include "cut/rest_map.hpp"

#include <Eigen/LU>
#include <limits>

#include "core/error.hpp"

namespace softcut::cut {

namespace {

void check_sizes(const mesh::TetMesh& m, const Eigen::MatrixX3d& u, const std::vector<char>& mask) {
  if (u.rows() != m.num_nodes())
    fail("cut: displacement has ", u.rows(), " rows but the mesh has ", m.num_nodes(), " nodes");
  if (!mask.empty() && mask.size() != size_t(m.num_tets()))
    fail("cut: tet mask has ", mask.size(), " entries for ", m.num_tets(), " tets");
}

// Corners of tet t in the deformed configuration (rest + displacement), m.
void deformed_corners(const mesh::TetMesh& m, const Eigen::MatrixX3d& u, int t, Eigen::Vector3d (&p)[4]) {
  for (int k = 0; k < 4; ++k) p[k] = (m.nodes.row(m.tets(t, k)) + u.row(m.tets(t, k))).transpose();
}

// Barycentric coordinates of x in the tet with corners p; false when the
// tet is collapsed.
bool barycentric(const Eigen::Vector3d (&p)[4], const Eigen::Vector3d& x, Eigen::Vector4d& bary) {
  Eigen::Matrix3d e;
  e << p[1] - p[0], p[2] - p[0], p[3] - p[0];
  Eigen::FullPivLU<Eigen::Matrix3d> lu(e);
  if (!lu.isInvertible()) return false;
  const Eigen::Vector3d l = lu.solve(x - p[0]);
  bary = Eigen::Vector4d(1 - l.sum(), l(0), l(1), l(2));
  return true;
}

}  // namespace

Eigen::Vector3d deformed_to_rest(const mesh::TetMesh& m, const Eigen::MatrixX3d& u, const Eigen::Vector3d& x,
                                 const std::vector<char>& mask) {
  check_sizes(m, u, mask);
  if (!x.allFinite()) fail("cut: point to map has a non-finite coordinate");
  // A point inside the mesh maps through the first tet (in index order)
  // that holds it: deformed_tet_at finds it with a bounding-box test per tet.
  // Only a point outside every tet needs the barycentric coordinates of all.
  int best = deformed_tet_at(m, u, x, mask);
  double best_min = -std::numeric_limits<double>::infinity();
  Eigen::Vector4d best_bary;
  if (best >= 0) {
    Eigen::Vector3d p[4];
    deformed_corners(m, u, best, p);
    barycentric(p, x, best_bary);
    best_min = best_bary.minCoeff();
  }
  for (int t = 0; t < m.num_tets() && best_min < 0; ++t) {
    if (!mask.empty() && !mask[size_t(t)]) continue;
    Eigen::Vector3d p[4];
    deformed_corners(m, u, t, p);
    Eigen::Vector4d bary;
    if (!barycentric(p, x, bary)) continue;  // collapsed in the deformed state
    if (bary.minCoeff() > best_min) {
      best_min = bary.minCoeff();
      best = t;
      best_bary = bary;
      if (best_min >= 0) break;  // inside
    }
  }
  if (best < 0) fail("cut: no usable tet to map a blade point to the rest configuration");
  Eigen::Vector3d r = Eigen::Vector3d::Zero();
  for (int k = 0; k < 4; ++k) r += best_bary(k) * m.node(m.tets(best, k));
  return r;
}

int deformed_tet_at(const mesh::TetMesh& m, const Eigen::MatrixX3d& u, const Eigen::Vector3d& x,
                    const std::vector<char>& mask) {
  check_sizes(m, u, mask);
  for (int t = 0; t < m.num_tets(); ++t) {
    if (!mask.empty() && !mask[size_t(t)]) continue;
    Eigen::Vector3d p[4];
    deformed_corners(m, u, t, p);
    // The box is padded by a hair, so that a point the barycentric solve
    // puts on a face is not dropped for lying outside the box by rounding.
    Eigen::Vector3d lo = p[0].cwiseMin(p[1]).cwiseMin(p[2]).cwiseMin(p[3]);
    Eigen::Vector3d hi = p[0].cwiseMax(p[1]).cwiseMax(p[2]).cwiseMax(p[3]);
    const double pad = 1e-9 * (hi - lo).maxCoeff();
    lo.array() -= pad;
    hi.array() += pad;
    if ((x.array() < lo.array()).any() || (x.array() > hi.array()).any()) continue;
    Eigen::Vector4d bary;
    if (barycentric(p, x, bary) && bary.minCoeff() >= 0) return t;
  }
  return -1;
}

SweptSurface deformed_to_rest(const mesh::TetMesh& m, const Eigen::MatrixX3d& u, const SweptSurface& s,
                              const std::vector<char>& mask) {
  SweptSurface out = s;
  for (auto& tri : out.triangles)
    for (int k = 0; k < 3; ++k) tri.col(k) = deformed_to_rest(m, u, tri.col(k), mask);
  return out;
}

}  // namespace softcut::cut
