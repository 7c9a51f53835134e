#include "render/scene.hpp"

#include <doctest/doctest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "core/error.hpp"
#include "mesh/generate/box.hpp"
#include "mesh/surface.hpp"

using namespace softcut;
using render::RenderSettings;
using render::SceneContent;

namespace {

mesh::TetMesh box(int nx, int ny, int nz, Eigen::Vector3d hi = Eigen::Vector3d::Ones()) {
  mesh::BoxOptions o;
  o.nx = nx, o.ny = ny, o.nz = nz;
  o.max_corner = hi;
  return mesh::generate_box(o);
}

Eigen::Vector3d centroid(const render::Triangles& t, int i) {
  return ((t.positions[size_t(3 * i)] + t.positions[size_t(3 * i + 1)] + t.positions[size_t(3 * i + 2)]) / 3.0f)
      .cast<double>();
}

Eigen::Vector3d tet_centroid(const mesh::TetMesh& m, int t) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (int k = 0; k < 4; ++k) c += m.node(m.tets(t, k));
  return c / 4.0;
}

// Cut-face flags (4 ntet) marking every tet face that lies in the plane x = 0.
std::vector<char> faces_at_x0(const mesh::TetMesh& m) {
  std::vector<char> cut(size_t(4 * m.num_tets()), 0);
  for (int t = 0; t < m.num_tets(); ++t)
    for (int f = 0; f < 4; ++f) {
      bool on = true;
      for (int k = 0; k < 3; ++k) on &= m.node(m.tets(t, mesh::kTetFaces[f][k])).x() == 0.0;
      cut[size_t(4 * t + f)] = on;
    }
  return cut;
}

}  // namespace

TEST_SUITE("render/scene") {
  TEST_CASE("two triangles per square of the sides of a box facing out and coloured by region") {
    std::mt19937 rng(7);
    for (int trial = 0; trial < 6; ++trial) {
      const int nx = 1 + int(rng() % 4), ny = 1 + int(rng() % 4), nz = 1 + int(rng() % 4);
      const mesh::TetMesh m = box(nx, ny, nz, {1.0, 2.0, 0.5});
      SceneContent c;
      c.operational.resize(size_t(m.num_tets()));
      for (int t = 0; t < m.num_tets(); ++t) c.operational[size_t(t)] = tet_centroid(m, t).x() < 0.5;
      RenderSettings s;
      s.crease_angle_deg = 40;
      const render::Scene sc = render::extract_scene(m, m.nodes, c, s);
      CAPTURE(nx);
      CAPTURE(ny);
      CAPTURE(nz);
      REQUIRE(sc.tissue.count() == 4 * (nx * ny + ny * nz + nz * nx));
      CHECK(sc.tissue_faces_operational + sc.tissue_faces_nonoperational == sc.tissue.count());
      CHECK(sc.tissue_faces_cut == 0);
      const Eigen::Vector3d mid(0.5, 1.0, 0.25);
      int op = 0;
      for (int i = 0; i < sc.tissue.count(); ++i) {
        const Eigen::Vector3d g = centroid(sc.tissue, i);
        // A face's tet lies in the same cell as the face, so the face centroid
        // tells the region (cells split at x = 0.5 only when nx is even).
        const auto& col = sc.tissue.colors[size_t(3 * i)];
        const bool grey = col == s.palette.operational, blue = col == s.palette.nonoperational;
        REQUIRE((grey || blue));
        op += grey;
        if (nx % 2 == 0) CHECK(grey == (g.x() < 0.5));
        // Box sides are 90 degree creases: every corner normal is the face's axis normal.
        const Eigen::Vector3d a = sc.tissue.positions[size_t(3 * i)].cast<double>();
        const Eigen::Vector3d b = sc.tissue.positions[size_t(3 * i + 1)].cast<double>();
        const Eigen::Vector3d cc = sc.tissue.positions[size_t(3 * i + 2)].cast<double>();
        const Eigen::Vector3d n = (b - a).cross(cc - a).normalized();
        CHECK(n.dot(g - mid) > 0);  // outward for a convex body
        for (int k = 0; k < 3; ++k)
          CHECK((sc.tissue.normals[size_t(3 * i + k)].cast<double>() - n).norm() < 1e-6);
      }
      CHECK(op == sc.tissue_faces_operational);
    }
  }

  TEST_CASE("normals are smoothed across flat creases only") {
    const mesh::TetMesh m = box(2, 2, 2);
    RenderSettings s;
    s.crease_angle_deg = 100;  // now the 90 degree box edges are smoothed too
    const render::Scene sc = render::extract_scene(m, m.nodes, {}, s);
    int tilted = 0;
    for (const auto& n : sc.tissue.normals) {
      CHECK(std::abs(n.norm() - 1.0f) < 1e-5f);
      tilted += n.cwiseAbs().maxCoeff() < 0.999f;
    }
    CHECK(tilted > 0);
  }

  TEST_CASE("normals are never smoothed across an incision's rim however flat the bend") {
    const mesh::TetMesh m = box(2, 2, 2);
    RenderSettings s;
    s.crease_angle_deg = 100;  // would smooth the 90 degree edges, the rim of the x = 0 face among them
    SceneContent c;
    auto x0_corner_normals = [&](const render::Scene& sc, bool cut_faces) {
      double worst = 0;  // largest |n.x| at an x = 0 corner of an uncut face
      for (int i = 0; i < sc.tissue.count(); ++i) {
        const bool on_x0 = centroid(sc.tissue, i).x() == doctest::Approx(0.0);
        for (int k = 0; k < 3; ++k) {
          const Eigen::Vector3f n = sc.tissue.normals[size_t(3 * i + k)];
          if (on_x0 && cut_faces) CHECK((n - Eigen::Vector3f(-1, 0, 0)).norm() < 1e-6f);
          if (!on_x0 && sc.tissue.positions[size_t(3 * i + k)].x() == 0.0f)
            worst = std::max(worst, double(std::abs(n.x())));
        }
      }
      return worst;
    };
    CHECK(x0_corner_normals(render::extract_scene(m, m.nodes, c, s), false) > 0.3);  // smoothed over the edge
    c.cut_faces = faces_at_x0(m);  // the x = 0 side is now a cut face
    CHECK(x0_corner_normals(render::extract_scene(m, m.nodes, c, s), true) < 1e-6);
  }

  TEST_CASE("cut faces take the cut colour") {
    const mesh::TetMesh m = box(3, 2, 2);
    SceneContent c;
    c.cut_faces = faces_at_x0(m);  // every tet face in the plane x = 0 (the boundary there), marked cut
    const render::Scene sc = render::extract_scene(m, m.nodes, c, {});
    CHECK(sc.tissue_faces_cut == 2 * 2 * 2);
    int red = 0;
    for (int i = 0; i < sc.tissue.count(); ++i)
      if (sc.tissue.colors[size_t(3 * i)] == RenderSettings().palette.cut) {
        ++red;
        CHECK(centroid(sc.tissue, i).x() == doctest::Approx(0.0));
      }
    CHECK(red == 8);
  }

  TEST_CASE("clinical style colours tissue by group, cycling the palette, cut faces a wet wound, paper by region") {
    const mesh::TetMesh m = box(4, 2, 2);
    SceneContent c;
    c.operational.resize(size_t(m.num_tets()));
    c.tet_group.resize(size_t(m.num_tets()));
    for (int t = 0; t < m.num_tets(); ++t) {
      c.operational[size_t(t)] = tet_centroid(m, t).x() < 0.5;
      c.tet_group[size_t(t)] = tet_centroid(m, t).y() < 0.5 ? 0 : 6;  // 6 cycles to palette entry 1 of 5
    }
    c.cut_faces = faces_at_x0(m);  // every tet face in the plane x = 0 (the boundary there), marked cut
    RenderSettings s;
    s.style = render::Style::clinical;
    const auto& pal = s.palette;
    REQUIRE(pal.tissue.size() == 5);
    const render::Scene sc = render::extract_scene(m, m.nodes, c, s);
    const render::Scene paper = render::extract_scene(m, m.nodes, c, {});
    // Clinical: the cut faces are the wound, apart; the paper style keeps them with the tissue.
    CHECK(sc.wound.count() == sc.tissue_faces_cut);
    CHECK(sc.tissue.count() + sc.wound.count() == paper.tissue.count());
    CHECK(paper.wound.count() == 0);
    for (int i = 0; i < sc.wound.count(); ++i) {
      const Eigen::Vector3d p = centroid(sc.wound, i);
      CHECK(p.x() == doctest::Approx(0.0));
      // Its group's colour cut_tint of the way to the cut colour, darkened.
      const render::Rgba tissue = p.y() < 0.5 ? pal.tissue[0] : pal.tissue[1];
      render::Rgba want = pal.wound_shade * ((1 - pal.cut_tint) * tissue + pal.cut_tint * pal.cut);
      want[3] = 1;
      CHECK((sc.wound.colors[size_t(3 * i)] - want).norm() < 1e-6f);
    }
    for (int i = 0; i < paper.tissue.count(); ++i)
      if (centroid(paper.tissue, i).x() == doctest::Approx(0.0)) CHECK(paper.tissue.colors[size_t(3 * i)] == pal.cut);
    for (int i = 0; i < sc.tissue.count(); ++i) {
      const Eigen::Vector3d p = centroid(sc.tissue, i);
      const render::Rgba want = p.y() < 0.5 ? pal.tissue[0] : pal.tissue[1];
      if (p.y() < 0.49 || p.y() > 0.51) {  // faces of one group (not on y = 0.5)
        // Corners at the incision's edge (x = 0) go margin_tint toward the wound; others are the tissue's.
        for (int k = 0; k < 3; ++k) {
          const bool at_cut = sc.tissue.positions[size_t(3 * i + k)].x() == 0.0f;
          const render::Rgba got = sc.tissue.colors[size_t(3 * i + k)];
          if (!at_cut) CHECK(got == want);
          else CHECK(got != want);
        }
      }
    }
    c.tet_group[3] = -1;
    CHECK_THROWS_WITH_AS(render::extract_scene(m, m.nodes, c, s), doctest::Contains("tet 3 has tissue group -1"), Error);
    c.tet_group.resize(5);
    CHECK_THROWS_WITH_AS(render::extract_scene(m, m.nodes, c, s), doctest::Contains("tissue groups have 5 entries"), Error);
  }

  TEST_CASE("inclusions: each inner boundary face between tissue groups once, wound out of the inclusion") {
    const mesh::TetMesh m = box(4, 4, 4);
    RenderSettings s;
    s.style = render::Style::clinical;
    SceneContent c;
    const Eigen::Vector3d mid(0.5, 0.5, 0.5);
    for (const int inside : {1, 0}) {  // the core is the rarer group whichever its number
      CAPTURE(inside);
      c.tet_group.resize(size_t(m.num_tets()));
      for (int t = 0; t < m.num_tets(); ++t)
        c.tet_group[size_t(t)] = (tet_centroid(m, t) - mid).cwiseAbs().maxCoeff() < 0.25 ? inside : 1 - inside;
      const render::Scene sc = render::extract_scene(m, m.nodes, c, s);
      REQUIRE(sc.inclusions.count() == 6 * 4 * 2);  // the 2 x 2 x 2 core's sides, 2 triangles per square
      for (int i = 0; i < sc.inclusions.count(); ++i) {
        const Eigen::Vector3d g = centroid(sc.inclusions, i);
        CHECK((g - mid).cwiseAbs().maxCoeff() == doctest::Approx(0.25));
        const Eigen::Vector3d a = sc.inclusions.positions[size_t(3 * i)].cast<double>();
        const Eigen::Vector3d n = (sc.inclusions.positions[size_t(3 * i + 1)].cast<double>() - a)
                                      .cross(sc.inclusions.positions[size_t(3 * i + 2)].cast<double>() - a);
        CHECK(n.dot(g - mid) > 0);  // outward from the core
        // 40 % of the way toward the tissue around it; fainter with depth, never below 30 %.
        const render::Rgba want = 0.6f * s.palette.tissue[size_t(inside)] + 0.4f * s.palette.tissue[size_t(1 - inside)];
        const render::Rgba got = sc.inclusions.colors[size_t(3 * i)];
        CHECK((got.head<3>() - want.head<3>()).norm() < 1e-6f);
        CHECK(got[3] <= s.palette.inclusion_alpha);
        CHECK(got[3] >= 0.3f * s.palette.inclusion_alpha);
      }
    }
    RenderSettings off = s;
    off.show_inclusions = false;
    CHECK(render::extract_scene(m, m.nodes, c, off).inclusions.count() == 0);
    CHECK(render::extract_scene(m, m.nodes, c, {}).inclusions.count() == 0);  // the paper style has none
    for (int& g : c.tet_group) g = g == 1 ? 1 << 30 : g;  // any group ids: a huge one costs nothing
    CHECK(render::extract_scene(m, m.nodes, c, s).inclusions.count() == 6 * 4 * 2);
    c.tet_group.assign(size_t(m.num_tets()), 2);
    CHECK(render::extract_scene(m, m.nodes, c, s).inclusions.count() == 0);  // one group: nothing inside
    s.palette.inclusion_alpha = 0;
    CHECK_THROWS_WITH_AS(render::extract_scene(m, m.nodes, c, s), doctest::Contains("inclusion_alpha"), Error);
  }

  TEST_CASE("load arrows: a shaft ending at the node and a two-stroke head pointing back along it") {
    const mesh::TetMesh m = box(1, 1, 1);
    SceneContent c;
    c.arrows = {{Eigen::Vector3d(0, 0, 2), Eigen::Vector3d(0, 0, 1)}, {Eigen::Vector3d(1, 1, 1), Eigen::Vector3d(1, 1, 1)}};
    const render::Scene sc = render::extract_scene(m, m.nodes, c, {});
    REQUIRE(sc.arrows.vertices() == 6);  // the zero-length arrow is skipped
    CHECK(sc.arrows.on_top);
    CHECK((sc.arrows.positions[1] - Eigen::Vector3f(0, 0, 1)).norm() == 0);
    for (int k : {3, 5}) {  // head strokes: from the tip back up, 25 degrees off the shaft, 0.25 long
      const Eigen::Vector3f d = sc.arrows.positions[size_t(k)] - Eigen::Vector3f(0, 0, 1);
      CHECK(d.norm() == doctest::Approx(0.25).epsilon(1e-6));
      CHECK(d.z() == doctest::Approx(0.25 * std::cos(0.436)).epsilon(1e-6));
    }
    c.arrows[0].from.x() = std::nan("");
    CHECK_THROWS_WITH_AS(render::extract_scene(m, m.nodes, c, {}), doctest::Contains("arrow 0 has a non-finite end"), Error);
  }

  TEST_CASE("the incision is outlined where cut faces meet the outer surface, even when closed") {
    const mesh::TetMesh m = box(3, 2, 2);
    SceneContent c;
    CHECK(render::extract_scene(m, m.nodes, c, {}).outline.vertices() == 0);  // nothing cut
    c.cut_faces = faces_at_x0(m);  // every tet face in the plane x = 0 (the boundary there), marked cut
    const render::Scene sc = render::extract_scene(m, m.nodes, c, {});
    // The rim is the square's perimeter: 4 sides of 2 segments, 2 vertices each.
    REQUIRE(sc.outline.vertices() == 16);
    for (const Eigen::Vector3f& p : sc.outline.positions) {
      CHECK(p.x() == 0.0f);
      CHECK((p.y() == 0.0f || p.y() == 1.0f || p.z() == 0.0f || p.z() == 1.0f));
    }
    CHECK(!sc.outline.on_top);  // hidden behind tissue like the surface it lies on
    RenderSettings off;
    off.incision_outline = false;
    CHECK(render::extract_scene(m, m.nodes, c, off).outline.vertices() == 0);
  }

  TEST_CASE("deformed positions are drawn but framing follows the rest shape") {
    const mesh::TetMesh m = box(2, 2, 2);
    Eigen::MatrixX3d x = m.nodes;
    x.col(2).array() += 0.25;
    const render::Scene rest = render::extract_scene(m, m.nodes, {}, {});
    const render::Scene moved = render::extract_scene(m, x, {}, {});
    CHECK((moved.camera.eye - rest.camera.eye).norm() == doctest::Approx(0.0));
    for (size_t i = 0; i < rest.tissue.positions.size(); ++i)
      CHECK((moved.tissue.positions[i] - rest.tissue.positions[i] - Eigen::Vector3f(0, 0, 0.25f)).norm() < 1e-6f);
  }

  TEST_CASE("wireframe draws each surface edge once") {
    const mesh::TetMesh m = box(3, 2, 1);
    RenderSettings s;
    const render::Scene off = render::extract_scene(m, m.nodes, {}, s);
    CHECK(off.wire.vertices() == 0);
    s.wireframe = true;
    const render::Scene on = render::extract_scene(m, m.nodes, {}, s);
    // Closed triangulated surface: E = 3F/2, two vertices per edge.
    CHECK(on.wire.vertices() == 3 * on.tissue.count());
  }

  TEST_CASE("a scene extractor keeps the topology until a cut changes it and matches extract_scene") {
    auto same = [](const render::Scene& a, const render::Scene& b) {
      CHECK(a.tissue.positions == b.tissue.positions);
      CHECK(a.tissue.normals == b.tissue.normals);
      CHECK(a.tissue.colors == b.tissue.colors);
      CHECK(a.wire.positions == b.wire.positions);
      CHECK(a.wire.colors == b.wire.colors);
      CHECK(a.tissue_faces_operational == b.tissue_faces_operational);
      CHECK(a.tissue_faces_nonoperational == b.tissue_faces_nonoperational);
      CHECK(a.tissue_faces_cut == b.tissue_faces_cut);
      CHECK((a.camera.view - b.camera.view).norm() == 0.0);
    };
    mesh::TetMesh m = box(3, 2, 2);
    RenderSettings s;
    s.wireframe = true;
    SceneContent c;
    c.operational.assign(size_t(m.num_tets()), 0);
    for (int t = 0; t < m.num_tets(); t += 2) c.operational[size_t(t)] = 1;
    render::SceneExtractor ex;
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> jitter(-0.05, 0.05);
    auto deformed = [&] { return Eigen::MatrixX3d(m.nodes.unaryExpr([&](double v) { return v + jitter(rng); })); };
    for (int frame = 0; frame < 4; ++frame) {
      const Eigen::MatrixX3d x = deformed();
      same(ex.extract(m, x, c, s), render::extract_scene(m, x, c, s));
    }
    CHECK(ex.topology_builds() == 1);
    // A new region split, then cut faces, then new tets: each rebuilds once.
    c.operational.assign(size_t(m.num_tets()), 1);
    Eigen::MatrixX3d x = deformed();
    same(ex.extract(m, x, c, s), render::extract_scene(m, x, c, s));
    CHECK(ex.topology_builds() == 2);
    c.cut_faces.assign(size_t(4 * m.num_tets()), 0);
    c.cut_faces[5] = c.cut_faces[18] = 1;
    same(ex.extract(m, x, c, s), render::extract_scene(m, x, c, s));
    CHECK(ex.topology_builds() == 3);
    m.tets.row(0).swap(m.tets.row(1));
    same(ex.extract(m, x, c, s), render::extract_scene(m, x, c, s));
    same(ex.extract(m, x, c, s), render::extract_scene(m, x, c, s));
    CHECK(ex.topology_builds() == 4);
  }

  TEST_CASE("interface nodes as points and manipulated nodes with their lines") {
    const mesh::TetMesh m = box(2, 2, 2);
    Eigen::MatrixX3d x = m.nodes * 1.5;
    SceneContent c;
    c.interface_nodes = {13, 4, 22};  // 13 is the centre node, inside the box
    c.manipulated = {{26, Eigen::Vector3d(2, 2, 3)}};
    RenderSettings s;
    render::Scene sc = render::extract_scene(m, x, c, s);
    REQUIRE(sc.interface_points.vertices() == 3);
    for (int i = 0; i < 3; ++i) {
      CHECK((sc.interface_points.positions[size_t(i)].cast<double>() -
             x.row(c.interface_nodes[size_t(i)]).transpose()).norm() < 1e-6);
      CHECK(sc.interface_points.colors[size_t(i)] == s.palette.interface_nodes);
    }
    CHECK(sc.interface_points.on_top);
    REQUIRE(sc.manipulated_points.vertices() == 1);
    REQUIRE(sc.force_lines.vertices() == 2);
    CHECK((sc.force_lines.positions[0].cast<double>() - x.row(26).transpose()).norm() < 1e-6);
    CHECK((sc.force_lines.positions[1].cast<double>() - Eigen::Vector3d(2, 2, 3)).norm() < 1e-6);
    CHECK(sc.force_lines.colors[0] == s.palette.manipulated);
    // The line end lies beyond the box: near/far must still contain it.
    const Eigen::Vector3d ndc = sc.camera.to_ndc({2, 2, 3});
    CHECK(std::abs(ndc.z()) <= 1.0);
    s.show_interface = false;
    sc = render::extract_scene(m, x, c, s);
    CHECK(sc.interface_points.vertices() == 0);
  }

  TEST_CASE("tools become triangles") {
    const mesh::TetMesh m = box(1, 1, 1);
    SceneContent c;
    c.tools = {render::ProbeShape{}, render::GrasperShape{}, render::ScalpelShape{}};
    RenderSettings s;
    s.tool_segments = 16;
    const render::Scene sc = render::extract_scene(m, m.nodes, c, s);
    const int S = 16;
    CHECK(sc.tools.count() == (2 * S * (S / 2 - 1) + 4 * S) + (24 + 8 * S) + (4 + 12));
    for (const auto& col : sc.tools.colors) CHECK((col == s.palette.tool || col == s.palette.tool_dark));
  }

  TEST_CASE("bad input is refused naming the item") {
    const mesh::TetMesh m = box(1, 1, 1);
    Eigen::MatrixX3d x = m.nodes;
    CHECK_THROWS_WITH_AS(render::extract_scene(m, Eigen::MatrixX3d(x.topRows(3)), {}, {}),
                         doctest::Contains("positions have 3 rows but the mesh has 8 nodes"), Error);
    SceneContent c;
    c.interface_nodes = {8};
    CHECK_THROWS_WITH_AS(render::extract_scene(m, x, c, {}), doctest::Contains("interface node 0 has id 8"), Error);
    c = {};
    c.operational = {1, 0};
    CHECK_THROWS_WITH_AS(render::extract_scene(m, x, c, {}), doctest::Contains("operational flags have 2"), Error);
    c = {};
    c.manipulated = {{-1, {}}};
    CHECK_THROWS_WITH_AS(render::extract_scene(m, x, c, {}), doctest::Contains("manipulated node 0 has id -1"),
                         Error);
    c = {};
    x(5, 1) = std::nan("");
    CHECK_THROWS_WITH_AS(render::extract_scene(m, x, c, {}), doctest::Contains("node 5 is not finite"), Error);
    x = m.nodes;
    c.tools = {render::ProbeShape{}, render::ProbeShape{{0, 0, 0}, {0, 0, 1}, -1.0, 0.1}};
    CHECK_THROWS_WITH_AS(render::extract_scene(m, x, c, {}), doctest::Contains("tool 1: probe radius"), Error);
    RenderSettings s;
    s.width = 0;
    CHECK_THROWS_WITH_AS(render::extract_scene(m, x, {}, s), doctest::Contains("image size 0 x 480"), Error);
  }
}
