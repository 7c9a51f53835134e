#include "mesh/mesher/volume_shape.hpp"

#include <doctest/doctest.h>

#include <set>

#include "generate_checks.hpp"
#include "mesh/mesher/mesh_shape.hpp"
#include "mesh/quality.hpp"
#include "mesh/surface.hpp"

using namespace softcut;
using namespace softcut::mesh;

namespace {

// 24^3 voxels of 1 mm: a ball of radius 9 mm (label 1) around a ball of
// radius 4 mm (label 2), and a separate corner block of label 3.
LabelVolume two_balls() {
  LabelVolume v;
  v.source = "balls.nrrd";
  v.size = Eigen::Vector3i(24, 24, 24);
  v.directions = 1e-3 * Eigen::Matrix3d::Identity();
  v.origin = Eigen::Vector3d(0.001, 0.002, 0.003);
  v.labels.assign(size_t(v.num_voxels()), 0);
  for (int k = 0; k < 24; ++k)
    for (int j = 0; j < 24; ++j)
      for (int i = 0; i < 24; ++i) {
        const double r = Eigen::Vector3d(i - 11.5, j - 11.5, k - 11.5).norm();
        auto& l = v.labels[size_t(v.index(i, j, k))];
        l = r < 4 ? 2 : r < 9 ? 1 : 0;
        if (i < 2 && j < 2 && k < 2) l = 3;
      }
  return v;
}

}  // namespace

TEST_SUITE("mesh/mesher/volume_shape") {
  TEST_CASE("a label image becomes a smooth labelled solid: nodes on the sphere, not on the voxel staircase") {
    const LabelVolume v = two_balls();
    const LabeledShape s = volume_shape(v, {1, 2});
    CHECK(s.labels == std::vector<int>{1, 2});
    const Eigen::Vector3d centre = v.origin + Eigen::Vector3d::Constant(11.5e-3);
    CHECK(s.label(centre) == 2);
    CHECK(s.label(centre + Eigen::Vector3d(6e-3, 0, 0)) == 1);
    CHECK(s.label(v.origin) == 0);  // label 3 is not kept
    MesherOptions o;
    o.cell_size = 2e-3;
    MesherReport rep;
    const TetMesh m = mesh_shape(s, o, &rep);
    test::check_solid(m, 2);
    CHECK(std::set<int>(m.labels.data(), m.labels.data() + m.labels.size()) == std::set<int>{1, 2});
    CHECK(rep.min_dihedral_deg > 8);
    // The interpolated indicator puts the boundary on the sphere between
    // the last voxel in and the first out: every surface node within half a
    // voxel of radius 9 mm (the staircase is up to a voxel off).
    double worst = 0;
    for (int i : extract_surface(m).nodes) worst = std::max(worst, std::abs((m.node(i) - centre).norm() - 9e-3));
    CHECK(worst < 0.5e-3);
  }

  TEST_CASE("every nonzero label by default, and a missing label is an error naming the file") {
    const LabelVolume v = two_balls();
    CHECK(volume_shape(v, {}).labels == std::vector<int>{1, 2, 3});
    CHECK_THROWS_WITH_AS(volume_shape(v, {7}), doctest::Contains("balls.nrrd: label 7 does not occur"), Error);
    LabelVolume empty = v;
    std::fill(empty.labels.begin(), empty.labels.end(), 0);
    CHECK_THROWS_WITH_AS(volume_shape(empty, {}), doctest::Contains("balls.nrrd: the image has no nonzero label"), Error);
  }
}
