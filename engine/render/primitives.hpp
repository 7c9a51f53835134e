#pragma once
// Coloured triangles, lines and points in world space: the drawable content of
// a scene, laid out so the renderer uploads each array as one GL buffer.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace softcut::render {

using Rgba = Eigen::Vector4f;  // red, green, blue, alpha in [0, 1], written to the PNG as is

struct Triangles {
  std::vector<Eigen::Vector3f> positions;  // (3 ntri) corners, m (contiguous xyz: GL-ready)
  std::vector<Eigen::Vector3f> normals;    // (3 ntri) unit shading normals
  std::vector<Rgba> colors;                // (3 ntri)
  std::vector<std::uint32_t> labels;       // (3 ntri) id of each corner's triangle in the label image
  std::uint32_t label = 0;                 // the id add() gives the triangles it appends

  int count() const { return int(positions.size() / 3); }
  void reserve(int ntri);
  // Appends one triangle with one colour; normals per corner.
  void add(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
           const Eigen::Vector3d& na, const Eigen::Vector3d& nb, const Eigen::Vector3d& nc, const Rgba& color);
  // With a colour per corner (blended across the triangle).
  void add(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
           const Eigen::Vector3d& na, const Eigen::Vector3d& nb, const Eigen::Vector3d& nc, const Rgba& ca,
           const Rgba& cb, const Rgba& cc);
  // Flat: the geometric normal of (a, b, c) at all corners.
  void add_flat(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, const Rgba& color);
};

// Lines (2 vertices per segment) or points (1 per point) of one style.
struct Primitives {
  std::vector<Eigen::Vector3f> positions;  // (nvert) m
  std::vector<Rgba> colors;                // (nvert)
  float size_px = 1.0f;  // line width or point diameter
  bool on_top = false;   // drawn without depth test

  int vertices() const { return int(positions.size()); }
  void add(const Eigen::Vector3d& p, const Rgba& color);
};

}  // namespace softcut::render
