#pragma once
// What the mesher meshes: a label at every point of a box. 0 is outside;
// each positive label is one tissue (liver 1, lesion 2, ...). Implicit organ
// shapes (organs.hpp) and segmented label images (volume_shape.hpp) are both
// given this way, so one CGAL Mesh_3 path meshes either (mesh_shape.hpp).
#include <Eigen/Geometry>
#include <functional>
#include <string>
#include <vector>

namespace softcut::mesh {

struct LabeledShape {
  std::string name;                                    // for messages: "generator liver", "volume a.nrrd"
  std::function<int(const Eigen::Vector3d&)> label;    // p in m -> 0 outside, else the tissue label
  Eigen::AlignedBox3d bounds;                          // m; every labelled point lies strictly inside
  std::vector<int> labels;                             // the labels the shape has, ascending
};

// Volume of each label, m^3, estimated on an n^3 grid of samples over `bounds`
// (midpoint rule). Index: label; index 0 is the outside.
std::vector<double> label_volumes(const LabeledShape& s, int n = 48);

}  // namespace softcut::mesh
