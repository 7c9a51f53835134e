#include "mesh/mesher/organs.hpp"

#include <doctest/doctest.h>

#include <set>

#include "generate_checks.hpp"
#include "test_support.hpp"
#include "mesh/io/mesh_io.hpp"
#include "mesh/quality.hpp"
#include "mesh/surface.hpp"

using namespace softcut;
using namespace softcut::mesh;

namespace {

// The quality every shipped organ mesh keeps (the mesher reports its own).
constexpr double kMinDihedralDeg = 8;

std::set<int> labels_of(const TetMesh& m) { return {m.labels.data(), m.labels.data() + m.labels.size()}; }

double label_volume(const TetMesh& m, int label) {
  double v = 0;
  for (int t = 0; t < m.num_tets(); ++t)
    if (m.labels(t) == label) v += signed_volume(m, t);
  return v;
}

}  // namespace

TEST_SUITE("mesh/mesher/organs") {
  TEST_CASE("every organ at the paper's 2k tets and at 5k: a closed labelled solid above the quality bound") {
    for (const std::string& kind : organ_kinds())
      for (int target : {2000, 5000}) {
        CAPTURE(kind);
        CAPTURE(target);
        OrganOptions o;
        o.target_tets = target;
        MesherReport rep;
        const TetMesh m = generate_organ(kind, o, 1e9, &rep);
        test::check_solid(m, 2);
        CHECK(std::abs(m.num_tets() - target) <= 0.2 * target);
        CHECK(rep.min_dihedral_deg >= kMinDihedralDeg);
        const LabeledShape s = organ_shape(kind, o);
        CHECK(labels_of(m) == std::set<int>(s.labels.begin(), s.labels.end()));
        // The mesh fills the shape: its volume per label against the
        // shape's sampled volume.
        const auto want = label_volumes(s, 96);
        for (int l : s.labels) CHECK(label_volume(m, l) / want[size_t(l)] == doctest::Approx(1).epsilon(0.1));
      }
  }

  TEST_CASE("the liver's lesion is inside it, and the kidney's medulla inside its cortex") {
    for (const std::string kind : {"liver", "kidney"}) {
      CAPTURE(kind);
      OrganOptions o;
      o.target_tets = 4000;
      const TetMesh m = generate_organ(kind, o, 1e9);
      const Surface s = extract_surface(m);
      std::set<int> outer(s.nodes.begin(), s.nodes.end());
      int on_surface = 0, inner = 0;
      for (int t = 0; t < m.num_tets(); ++t)
        if (m.labels(t) == 2) {
          ++inner;
          for (int v = 0; v < 4; ++v) on_surface += outer.count(m.tets(t, v)) > 0;
        }
      CHECK(inner > 0);
      CHECK(on_surface == 0);
    }
  }

  TEST_CASE("grading puts the fine tets around the fine centre") {
    OrganOptions o;
    o.target_tets = 4000;
    o.fine_center = Eigen::Vector3d(0.03, 0, 0.045);  // top of the right lobe
    o.fine_radius = 0.025;
    o.fine_ratio = 0.35;
    const TetMesh m = generate_organ("liver", o, 1e9);
    test::check_solid(m, 2);
    int near = 0;
    for (int t = 0; t < m.num_tets(); ++t) {
      Eigen::Vector3d c = Eigen::Vector3d::Zero();
      for (int v = 0; v < 4; ++v) c += m.node(m.tets(t, v)) / 4;
      near += (c - o.fine_center).norm() < o.fine_radius;
    }
    // The fine ball holds ~4 % of the liver's volume and, graded, a third of its tets.
    CHECK(near > m.num_tets() / 5);
  }

  TEST_CASE("organ meshes round-trip through VTU bit for bit") {
    OrganOptions o;
    o.target_tets = 2000;
    const TetMesh m = generate_organ("liver", o, 1e9);
    const auto path = test::scratch_dir("mesher_organs") / "liver.vtu";
    write_mesh(path, m);
    Diagnostics d;
    const TetMesh back = read_mesh(path, d);
    CHECK(back.nodes == m.nodes);
    CHECK(back.tets == m.tets);
    CHECK(back.labels == m.labels);
    CHECK(d.warnings.empty());
  }

  TEST_CASE("scale scales the organ") {
    OrganOptions o;
    o.target_tets = 2000;
    const TetMesh a = generate_organ("kidney", o, 1e9);
    o.scale = 0.5;
    const TetMesh b = generate_organ("kidney", o, 1e9);
    CHECK(total_volume(b) / total_volume(a) == doctest::Approx(0.125).epsilon(0.05));
  }

  TEST_CASE("a request over the tet limit is refused before meshing, and bad options are named") {
    OrganOptions o;
    o.target_tets = 1000000000;
    CHECK_THROWS_WITH_AS(generate_organ("liver", o, 2e5), doctest::Contains("over this run's limit of 200000"), Error);
    o.target_tets = 0;
    o.cell_size = 1e-6;
    CHECK_THROWS_WITH_AS(generate_organ("liver", o, 2e5), doctest::Contains("generator liver: about"), Error);
    o.cell_size = 0.01;
    o.target_tets = 100;
    CHECK_THROWS_WITH_AS(generate_organ("liver", o, 2e5), doctest::Contains("give target_tets or cell_size, not both"), Error);
    o = {};
    o.scale = -1;
    CHECK_THROWS_WITH_AS(generate_organ("kidney", o, 2e5), doctest::Contains("generator kidney: scale must be in"), Error);
    o = {};
    o.fine_radius = 0.01, o.fine_ratio = 0;
    CHECK_THROWS_WITH_AS(generate_organ("liver", o, 2e5), doctest::Contains("fine_ratio must be in"), Error);
    o = {};
    o.lesion_center = Eigen::Vector3d(0.025, 0, 0.04);  // 5 mm under the dome's top: the 12 mm lesion breaks out
    CHECK_THROWS_WITH_AS(generate_organ("liver", o, 2e5), doctest::Contains("the lesion (lesion_center, lesion_radius) must lie inside"), Error);
    CHECK_THROWS_WITH_AS(generate_organ("spleen", {}, 2e5), doctest::Contains("generator spleen: unknown organ"), Error);
  }
}
