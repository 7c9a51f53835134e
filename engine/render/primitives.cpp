#include "render/primitives.hpp"

#include <Eigen/Geometry>

namespace softcut::render {

void Triangles::reserve(int ntri) {
  positions.reserve(size_t(3 * ntri));
  normals.reserve(size_t(3 * ntri));
  colors.reserve(size_t(3 * ntri));
  labels.reserve(size_t(3 * ntri));
}

void Triangles::add(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                    const Eigen::Vector3d& na, const Eigen::Vector3d& nb, const Eigen::Vector3d& nc,
                    const Rgba& color) {
  positions.insert(positions.end(), {a.cast<float>(), b.cast<float>(), c.cast<float>()});
  normals.insert(normals.end(), {na.cast<float>(), nb.cast<float>(), nc.cast<float>()});
  colors.insert(colors.end(), {color, color, color});
  labels.insert(labels.end(), {label, label, label});
}

void Triangles::add(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                    const Eigen::Vector3d& na, const Eigen::Vector3d& nb, const Eigen::Vector3d& nc, const Rgba& ca,
                    const Rgba& cb, const Rgba& cc) {
  add(a, b, c, na, nb, nc, ca);
  colors[colors.size() - 2] = cb;
  colors[colors.size() - 1] = cc;
}

void Triangles::add_flat(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                         const Rgba& color) {
  Eigen::Vector3d n = (b - a).cross(c - a);
  const double len = n.norm();
  n = len > 0 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::UnitZ();
  add(a, b, c, n, n, n, color);
}

void Primitives::add(const Eigen::Vector3d& p, const Rgba& color) {
  positions.push_back(p.cast<float>());
  colors.push_back(color);
}

}  // namespace softcut::render
