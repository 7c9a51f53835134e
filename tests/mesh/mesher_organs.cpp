#include "mesh/mesher/organs.hpp"

#include <doctest/doctest.h>

#include <algorithm>
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
        if (kind == "knee_ligament") {  // its insertions: the end faces' nodes, nothing between
          const auto sets = organ_landmarks(kind, m, o);
          const double z0 = m.nodes.col(2).minCoeff(), z1 = m.nodes.col(2).maxCoeff();
          int ends = 0;
          for (int n = 0; n < m.num_nodes(); ++n) ends += m.node(n).z() <= z0 + 1e-9 || m.node(n).z() >= z1 - 1e-9;
          CHECK(ends > 0);
          CHECK(int(sets.at("tibial").size() + sets.at("femoral").size()) >= ends);
          for (int n : sets.at("tibial")) CHECK(m.node(n).z() <= z0 + 5e-4 + 1e-12);
          for (int n : sets.at("femoral")) CHECK(m.node(n).z() >= z1 - 5e-4 - 1e-12);
        }
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

      // Landmarks (organ_landmarks): where the organ's shape puts them,
      // read from the mesh's own nodes.
      const auto sets = organ_landmarks(kind, m, o);
      auto mean = [&](const std::string& name) {
        REQUIRE(sets.count(name));
        const std::vector<int>& ids = sets.at(name);
        REQUIRE(!ids.empty());
        Eigen::Vector3d c = Eigen::Vector3d::Zero();
        for (int n : ids) c += m.node(n);
        return Eigen::Vector3d(c / double(ids.size()));
      };
      const double zmin = m.nodes.col(2).minCoeff();
      if (kind == "liver") {
        std::vector<int> lobes = sets.at("right_lobe");
        lobes.insert(lobes.end(), sets.at("left_lobe").begin(), sets.at("left_lobe").end());
        std::sort(lobes.begin(), lobes.end());
        CHECK(int(std::unique(lobes.begin(), lobes.end()) - lobes.begin()) == m.num_nodes());  // a partition
        CHECK(int(lobes.size()) == m.num_nodes());
        CHECK(mean("right_lobe").x() > 0);
        CHECK(mean("left_lobe").x() < -0.03);
        for (int n : sets.at("underside")) CHECK(m.node(n).z() <= zmin + 1e-3);
        CHECK(mean("dome").z() > 0.035);
        for (int n : sets.at("lesion")) CHECK((m.node(n) - o.lesion_center).norm() <= o.lesion_radius + 0.006);
        int lesion_tet_nodes = 0;
        std::set<int> lesion(sets.at("lesion").begin(), sets.at("lesion").end());
        for (int t = 0; t < m.num_tets(); ++t)
          if (m.labels(t) == 2)
            for (int v = 0; v < 4; ++v) lesion_tet_nodes += lesion.count(m.tets(t, v)) > 0 ? 0 : 1;
        CHECK(lesion_tet_nodes == 0);
      } else {
        CHECK(mean("hilum").y() > 0.01);
        CHECK(mean("convex").y() < -0.02);
        CHECK(mean("upper_pole").x() > 0.04);
        CHECK(mean("lower_pole").x() < -0.04);
        CHECK(mean("underside").z() < -0.016);
        CHECK(mean("top").z() > 0.016);
        for (const auto& [name, ids] : sets)
          for (int n : ids) CHECK(outer.count(n) == 1);  // surface landmarks
      }
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
