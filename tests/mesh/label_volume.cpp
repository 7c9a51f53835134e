#include "mesh/volume/label_volume.hpp"

#include <doctest/doctest.h>

#include <map>
#include <string>

#include "core/error.hpp"
#include "generate_checks.hpp"
#include "mesh/quality.hpp"
#include "test_support.hpp"
#include "volume_samples.hpp"

using namespace softcut;
using namespace softcut::mesh;
namespace fs = std::filesystem;

namespace {

LabelVolume make_volume(Eigen::Vector3i size, const std::vector<int>& labels) {
  LabelVolume v;
  v.source = "vol";
  v.size = size;
  v.directions = Eigen::Vector3d(1e-3, 2e-3, 0.5e-3).asDiagonal();
  v.origin = Eigen::Vector3d(0.01, 0.02, 0.03);
  v.labels.assign(labels.begin(), labels.end());
  return v;
}

// Every tet face is shared by at most two tets, and a face shared by two has
// opposite orientations in them (conforming, consistently oriented).
int nonconforming_faces(const TetMesh& m) {
  std::map<std::array<int, 3>, std::vector<std::array<int, 3>>> faces;
  for (int t = 0; t < m.num_tets(); ++t)
    for (const auto& f : kTetFaces) {
      std::array<int, 3> v = {m.tets(t, f[0]), m.tets(t, f[1]), m.tets(t, f[2])}, key = v;
      std::sort(key.begin(), key.end());
      faces[key].push_back(v);
    }
  int bad = 0;
  for (const auto& [k, uses] : faces) {
    if (uses.size() > 2) ++bad;
    if (uses.size() == 2) {
      // Opposite orientation: some rotation of one equals the reverse of the other.
      const auto& a = uses[0];
      const auto& b = uses[1];
      bool opposite = false;
      for (int r = 0; r < 3; ++r) opposite |= a[0] == b[r] && a[1] == b[(r + 2) % 3] && a[2] == b[(r + 1) % 3];
      bad += !opposite;
    }
  }
  return bad;
}

}  // namespace

TEST_SUITE("mesh/volume/label_volume") {
  TEST_CASE("two labels from NRRD files (raw, gzip): 6 tets per voxel, labels kept, exact volume") {
    const fs::path dir = test::scratch_dir("label_volume_nrrd");
    for (bool gz : {false, true}) {
      std::string data = test::pack(test::sample_labels(), 2, true);
      if (gz) data = test::gzip_bytes(data);
      const fs::path p = dir / (gz ? "g.nrrd" : "r.nrrd");
      test::write_bytes(p, std::string("NRRD0004\ntype: int16\ndimension: 3\nsizes: 3 2 2\nencoding: ") +
                               (gz ? "gzip" : "raw") +
                               "\nendian: big\nspacings: 0.5 0.5 2\nspace units: \"mm\" \"mm\" \"mm\"\n\n" + data);
      Diagnostics d;
      const LabelVolume v = read_nrrd_labels(p, d);
      VoxelMeshOptions o;
      o.labels = {1, 2};
      const TetMesh m = mesh_label_volume(v, o, d);
      CHECK(d.warnings.empty());
      CHECK(m.num_tets() == 6 * 8);
      CHECK(m.num_nodes() == 3 * 3 * 3);  // the 2 x 2 x 2 voxel block's lattice
      CHECK((m.labels.array() == 1).count() == 24);
      CHECK((m.labels.array() == 2).count() == 24);
      CHECK(total_volume(m) == doctest::Approx(8 * 0.5e-3 * 0.5e-3 * 2e-3).epsilon(1e-12));
      test::check_solid(m, 2);
      CHECK(nonconforming_faces(m) == 0);
      CHECK(extract_surface(m).faces.rows() == 6 * 4 * 2);
      // Label 1 tets lie in the i = 0 column: x below the voxel boundary at origin + 0.5 spacing.
      for (int t = 0; t < m.num_tets(); ++t) {
        double cx = 0;
        for (int k = 0; k < 4; ++k) cx += m.nodes(m.tets(t, k), 0) / 4;
        CHECK((cx < 0.25e-3) == (m.labels(t) == 1));
      }
    }
  }

  TEST_CASE("all nonzero labels by default, lattice corners at origin - half a voxel") {
    const auto raw = test::sample_labels();
    const LabelVolume v = make_volume({3, 2, 2}, std::vector<int>(raw.begin(), raw.end()));
    Diagnostics d;
    const TetMesh m = mesh_label_volume(v, {}, d);
    CHECK(m.num_tets() == 6 * 9);
    CHECK((m.labels.array() == 5).count() == 6);
    const Eigen::Vector3d lo = m.nodes.colwise().minCoeff(), hi = m.nodes.colwise().maxCoeff();
    CHECK(lo.isApprox(v.origin - 0.5 * v.directions.diagonal()));
    CHECK(hi.isApprox(v.origin + 2.5 * v.directions.diagonal().cwiseProduct(Eigen::Vector3d(1, 0.6, 0.6))));
    test::check_solid(m, 2);
    CHECK(nonconforming_faces(m) == 0);
    CHECK(total_volume(m) == doctest::Approx(9 * v.directions.determinant()).epsilon(1e-12));
  }

  TEST_CASE("skewed, left-handed voxel axes still give positive tets and |det| volume per voxel") {
    std::vector<int> labels(4 * 3 * 2, 3);
    LabelVolume v = make_volume({4, 3, 2}, labels);
    v.directions << 1e-3, 0.3e-3, 0, 0, 1e-3, 0.2e-3, 0, 0, -1e-3;  // det < 0
    Diagnostics d;
    const TetMesh m = mesh_label_volume(v, {}, d);
    test::check_solid(m, 2);
    CHECK(total_volume(m) == doctest::Approx(24 * std::abs(v.directions.determinant())).epsilon(1e-12));
  }

  TEST_CASE("voxels touching along an edge: conforming, and a warning about the non-manifold surface") {
    // Voxels (0,0,0) and (1,1,0) share only an edge.
    const LabelVolume v = make_volume({2, 2, 1}, {1, 0, 0, 1});
    Diagnostics d;
    const TetMesh m = mesh_label_volume(v, {}, d);
    CHECK(m.num_tets() == 12);
    CHECK(nonconforming_faces(m) == 0);
    REQUIRE(d.warnings.size() == 1);
    CHECK(d.warnings[0].find("1 surface edge(s) are shared by more than two") != std::string::npos);
  }

  TEST_CASE("missing labels and empty selections are errors that list the labels present") {
    const LabelVolume v = make_volume({2, 1, 1}, {0, 4});
    Diagnostics d;
    VoxelMeshOptions o;
    o.labels = {7};
    CHECK_THROWS_WITH_AS(mesh_label_volume(v, o, d), "vol: label 7 does not occur; labels present: 0 (1 voxels), 4 (1 voxels)",
                         Error);
    const LabelVolume empty = make_volume({2, 1, 1}, {0, 0});
    CHECK_THROWS_WITH_AS(mesh_label_volume(empty, {}, d), doctest::Contains("no nonzero label to mesh"), Error);
  }

  TEST_CASE("smoothing a voxel ball keeps every tet positive and the surface closed") {
    const int n = 8;
    std::vector<int> labels;
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const Eigen::Vector3d c(i - 3.5, j - 3.5, k - 3.5);
          labels.push_back(c.norm() < 3.6 ? 1 : 0);
        }
    LabelVolume v = make_volume({n, n, n}, labels);
    v.directions = Eigen::Matrix3d::Identity() * 1e-3;
    Diagnostics d;
    const TetMesh stair = mesh_label_volume(v, {}, d);
    VoxelMeshOptions o;
    o.smooth_iterations = 5;
    const TetMesh smooth = mesh_label_volume(v, o, d);
    CHECK(smooth.tets == stair.tets);
    test::check_solid(smooth, 2);
    for (int t = 0; t < smooth.num_tets(); ++t)
      CHECK(signed_volume(smooth, t) >= o.min_volume_fraction * signed_volume(stair, t) * (1 - 1e-12));
    // Interior nodes stay put; the surface moved; the volume changed by a few percent only.
    const auto on_surface = surface_node_mask(stair, extract_surface(stair));
    double moved = 0;
    for (int i = 0; i < stair.num_nodes(); ++i) {
      const double dist = (smooth.node(i) - stair.node(i)).norm();
      if (!on_surface[size_t(i)]) CHECK(dist == 0);
      moved = std::max(moved, dist);
    }
    CHECK(moved > 0.1e-3);
    CHECK(std::abs(total_volume(smooth) / total_volume(stair) - 1) < 0.1);
    // Smoother: the mean aspect ratio of the surface does not matter here, the
    // surface area does: the staircase has more area than the smoothed ball.
    auto area = [](const TetMesh& m) {
      const Surface s = extract_surface(m);
      double a = 0;
      for (Eigen::Index f = 0; f < s.faces.rows(); ++f)
        a += 0.5 * (m.node(s.faces(f, 1)) - m.node(s.faces(f, 0))).cross(m.node(s.faces(f, 2)) - m.node(s.faces(f, 0))).norm();
      return a;
    };
    CHECK(area(smooth) < 0.95 * area(stair));
  }
}

TEST_SUITE("mesh/volume/label_volume") {
  TEST_CASE("the sample data: detached gzip and attached raw agree, documented counts") {
    Diagnostics d;
    const LabelVolume g = read_nrrd_labels(test::data_dir() / "volume" / "organ.nhdr", d);
    const LabelVolume r = read_nrrd_labels(test::data_dir() / "volume" / "organ_raw.nrrd", d);
    CHECK(d.warnings.empty());
    CHECK(g.labels == r.labels);
    CHECK(g.origin.isApprox(Eigen::Vector3d(-0.011, -0.009, -0.00875)));
    const TetMesh m = mesh_label_volume(g, {}, d);
    CHECK((m.labels.array() == 1).count() == 6 * 316);
    CHECK((m.labels.array() == 2).count() == 6 * 36);
    CHECK(total_volume(m) == doctest::Approx(352 * 2e-3 * 2e-3 * 2.5e-3).epsilon(1e-12));
    test::check_solid(m, 2);
  }
}
