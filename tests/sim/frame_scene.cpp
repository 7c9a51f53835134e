#include "sim/frame_scene.hpp"

#include <doctest/doctest.h>

#include "fixtures.hpp"
#include "render/tool_geometry.hpp"
#include "sim/step.hpp"
#include "test_support.hpp"

using V = Eigen::Vector3d;
namespace sim = softcut::sim;
namespace tools = softcut::tools;

TEST_SUITE("sim/frame_scene") {
  TEST_CASE("scene inputs from a frame with a probe and a grasper are accepted by the scene extraction") {
    auto spec = softcut::test::cantilever_spec(softcut::test::scratch_dir("sim_frame_scene"), 0.2);
    tools::ToolSpec probe;
    probe.name = "probe";
    probe.path = tools::Path::fixed_at(V(0.1, 0.01, 0.02));
    probe.radius = 0.0051;
    probe.force = tools::Ramp::constant_value(0.001);
    tools::ToolSpec grasper = probe;
    grasper.name = "grasper";
    grasper.kind = tools::ToolSpec::Kind::grasper;
    grasper.path = tools::Path::fixed_at(V(0.06, 0.0, 0.02));
    spec.tools = {probe, grasper};
    spec.outputs.render.orbit_deg_per_s = 10.0;
    spec.outputs.render.width = 64;
    spec.outputs.render.height = 48;
    const sim::Model m = sim::compile(spec);
    sim::State s = sim::make_state(m);
    sim::step(m, s);
    sim::step(m, s);
    const softcut::render::SceneContent c = sim::scene_content(m, s);
    CHECK(c.operational == m.partition.operational_tet);
    // Markers are in every scene's content (a redraw may show them); the
    // settings draw them only when asked: interface nodes and the nodes tools
    // act on are a debugging view.
    CHECK(c.interface_nodes == m.partition.interface);
    {
      const softcut::render::Scene plain =
          softcut::render::extract_scene(m.mesh, sim::deformed_positions(m, s), c, sim::render_settings(m, s));
      CHECK(plain.interface_points.vertices() == 0);
      CHECK(plain.manipulated_points.vertices() == 0);
      auto shown = spec;
      shown.outputs.render.show_interface = true;
      shown.outputs.render.show_forces = true;
      const sim::Model m2 = sim::compile(shown);
      sim::State s2 = sim::make_state(m2);
      sim::step(m2, s2);
      const softcut::render::Scene debug = softcut::render::extract_scene(
          m2.mesh, sim::deformed_positions(m2, s2), sim::scene_content(m2, s2), sim::render_settings(m2, s2));
      CHECK(debug.interface_points.vertices() == int(m2.partition.interface.size()));
      CHECK(debug.manipulated_points.vertices() > 0);
    }
    CHECK(c.tools.size() == 2);
    CHECK(c.manipulated.size() == s.tools[0].nodes.size() + s.tools[1].nodes.size());
    REQUIRE(!c.manipulated.empty());
    CHECK((c.manipulated[0].line_end - V(0.1, 0.01, 0.02)).norm() == 0);
    const softcut::render::RenderSettings r = sim::render_settings(m, s);
    CHECK(r.camera.azimuth_deg == doctest::Approx(-60.0 + 10.0 * 0.1));
    CHECK(r.width == 64);
    const softcut::render::Scene scene = softcut::render::extract_scene(m.mesh, sim::deformed_positions(m, s), c, r);
    CHECK(scene.tissue_faces_operational > 0);
    CHECK(scene.tissue_faces_nonoperational > 0);
    CHECK(sim::frame_png_path("out", 12) == std::filesystem::path("out/frames/frame_000012.png"));
  }

  TEST_CASE("a scalpel is drawn until its stop time, not after") {
    auto spec = softcut::test::cantilever_spec(softcut::test::scratch_dir("sim_frame_scene_scalpel"), 0.3);
    tools::ToolSpec blade;
    blade.name = "blade";
    blade.kind = tools::ToolSpec::Kind::scalpel;
    blade.path = tools::Path::fixed_at(V(0.1, 0.01, 0.5));  // well above the bar: never touches it
    blade.force = tools::Ramp::constant_value(0.001);
    blade.stop = 0.15;
    spec.tools = {blade};
    const sim::Model m = sim::compile(spec);
    sim::State s = sim::make_state(m);
    sim::step(m, s);  // t = 0
    sim::step(m, s);  // t = 0.1
    CHECK(s.time <= 0.15);
    CHECK(sim::scene_content(m, s).tools.size() == 1);
    sim::step(m, s);  // t = 0.2
    CHECK(s.time > 0.15);
    CHECK(sim::scene_content(m, s).tools.empty());
  }

  TEST_CASE("a probe is drawn only while it acts - its shaft against its force direction") {
    auto spec = softcut::test::cantilever_spec(softcut::test::scratch_dir("sim_frame_scene_probe"), 0.4);
    tools::ToolSpec probe;
    probe.name = "probe";
    probe.path = tools::Path::fixed_at(V(0.1, 0.01, 0.5));
    probe.force = tools::Ramp::constant_value(0.001);
    probe.direction = V(1, 0, -1);
    probe.start = 0.15;
    probe.stop = 0.25;
    spec.tools = {probe};
    const sim::Model m = sim::compile(spec);
    sim::State s = sim::make_state(m);
    const size_t expect[] = {0, 0, 1, 0};  // t = 0, 0.1, 0.2, 0.3
    for (size_t k = 0; k < 4; ++k) {
      sim::step(m, s);
      CAPTURE(s.time);
      const auto c = sim::scene_content(m, s);
      REQUIRE(c.tools.size() == expect[k]);
      if (expect[k]) {
        const V axis = std::get<softcut::render::ProbeShape>(c.tools[0]).axis;
        CHECK((axis - V(-1, 0, 1).normalized()).norm() <= 1e-15);
      }
    }
  }

  TEST_CASE("a load arrow per load ends at its nodes' centroid along its total force, the largest a tenth of the model") {
    auto spec = softcut::test::cantilever_spec(softcut::test::scratch_dir("sim_frame_scene_loads"), 0.3);
    sim::LoadSpec side = spec.loads[0];  // a second load, half as strong, along +y on the same nodes
    side.name = "side";
    side.direction = V(0, 1, 0);
    side.magnitude = tools::Ramp::linear_ramp(0.0, 0.005, 0.0, 1.0);
    spec.loads.push_back(side);
    const sim::Model m0 = sim::compile(spec);
    sim::State s0 = sim::make_state(m0);
    sim::step(m0, s0);
    sim::step(m0, s0);
    // In the content always; drawn only with show_loads (style debug turns it on).
    CHECK(softcut::render::extract_scene(m0.mesh, sim::deformed_positions(m0, s0), sim::scene_content(m0, s0),
                                         sim::render_settings(m0, s0)).arrows.vertices() == 0);
    spec.outputs.render.show_loads = true;
    const sim::Model m = sim::compile(spec);
    sim::State s = sim::make_state(m);
    sim::step(m, s);
    CHECK(sim::scene_content(m, s).arrows.empty());  // t = 0: both ramps are still 0 N
    sim::step(m, s);
    const auto c = sim::scene_content(m, s);
    REQUIRE(c.arrows.size() == 2);
    const Eigen::MatrixX3d x = sim::deformed_positions(m, s);
    V centroid = V::Zero();
    for (int n : s.loads[0].nodes) centroid += x.row(n).transpose() / double(s.loads[0].nodes.size());
    const double diag = (m.mesh.nodes.colwise().maxCoeff() - m.mesh.nodes.colwise().minCoeff()).norm();
    CHECK((c.arrows[0].to - centroid).norm() <= 1e-15);
    CHECK((c.arrows[0].to - c.arrows[0].from - V(0, 0, -0.1 * diag)).norm() <= 1e-12 * diag);
    CHECK((c.arrows[1].to - c.arrows[1].from - V(0, 0.05 * diag, 0)).norm() <= 1e-12 * diag);
  }

  TEST_CASE("tissue groups follow s:material call order (a material's color first), whatever the tet order") {
    auto spec = softcut::test::cantilever_spec(softcut::test::scratch_dir("sim_frame_scene_style"), 0.1);
    sim::MaterialAssignment lesion;
    lesion.name = "lesion";
    lesion.young = 2e4;
    lesion.poisson = 0.45;
    lesion.tets.kind = sim::TetSelector::Kind::box;
    lesion.tets.min = V(0.07, -1, -1);
    lesion.tets.max = V(1, 1, 1);
    spec.materials.push_back(lesion);
    spec.prestress.push_back({"p", "", sim::TetSelector::of(sim::TetSelector::Kind::all), -0.01 * Eigen::Matrix3d::Identity()});
    spec.outputs.render.tissue_colors = {V(0.1, 0.2, 0.3), V(0.9, 0.8, 0.7)};
    // The lesion's call comes first: its tets are group 0 although tet 0 is
    // plain tissue (material colours used to follow the tets' order).
    std::swap(spec.materials[0], spec.materials[1]);
    spec.materials[1].tets = sim::TetSelector::of(sim::TetSelector::Kind::box);
    spec.materials[1].tets.min = V(-1, -1, -1);
    spec.materials[1].tets.max = V(0.07, 1, 1);
    const sim::Model m = sim::compile(spec);
    sim::State s = sim::make_state(m);
    sim::step(m, s);
    const auto c = sim::scene_content(m, s);
    REQUIRE(int(c.tet_group.size()) == m.mesh.num_tets());
    CHECK(m.tet_material[0].young != 2e4);
    for (int t = 0; t < m.mesh.num_tets(); ++t)  // the initial strain does not make a group of its own
      CHECK(c.tet_group[size_t(t)] == (m.tet_material[size_t(t)].young == 2e4 ? 0 : 1));
    const softcut::render::RenderSettings r = sim::render_settings(m, s);
    CHECK(r.style == softcut::render::Style::clinical);
    REQUIRE(r.palette.tissue.size() == 3);  // two calls and the default material
    CHECK(r.palette.tissue[0][0] == doctest::Approx(0.1f));
    CHECK(r.palette.tissue[1][0] == doctest::Approx(0.9f));
    // A material's own colour wins over render.tissue_colors.
    auto colored = spec;
    colored.materials[1].has_color = true;
    colored.materials[1].color = V(0.2, 0.6, 0.3);
    CHECK(sim::tissue_palette(colored)[1] == V(0.2, 0.6, 0.3));
    CHECK(sim::tissue_palette(colored)[0] == V(0.1, 0.2, 0.3));
    // The label ids: one per call, the cut surface, the tools; no default material (every tet has a call).
    const sim::LabelLegend legend = sim::label_legend(m);
    CHECK(legend.group == std::vector<std::uint32_t>{1, 2, 0});
    CHECK(legend.cut == 3);
    CHECK(legend.entries.size() == 3);
    CHECK(legend.entries[0].name == "lesion");
    auto paper = spec;
    paper.outputs.render.style = sim::RenderSettings::Style::paper;
    const sim::Model mp = sim::compile(paper);
    sim::State sp = sim::make_state(mp);
    sim::step(mp, sp);
    CHECK(sim::render_settings(mp, sp).style == softcut::render::Style::paper);
  }

  TEST_CASE("a grasper's jaws are drawn at the tissue they hold, not at its tip") {
    // An implicit grasper lifts the top of the cantilever; a soft spring
    // leaves the tissue well short of the tip, and the jaws stay with the tissue.
    auto spec = softcut::test::cantilever_spec(softcut::test::scratch_dir("sim_frame_scene_jaw"), 0.3);
    spec.loads.clear();
    spec.tools = {softcut::test::spring_grasper(0.2, 0.004, tools::Path::polyline({0.0, 0.2}, {V(0.07, 0.01, 0.02), V(0.07, 0.01, 0.03)}))};
    const sim::Model m = sim::compile(spec);
    sim::State s = sim::make_state(m);
    for (int k = 0; k < 3; ++k) sim::step(m, s);
    const tools::ToolState& ts = s.tools[0];
    REQUIRE(ts.engaged);
    const Eigen::MatrixX3d x = sim::deformed_positions(m, s);
    V held = V::Zero();
    for (const auto& p : ts.grip) held += p.at(x) / double(ts.grip.size());
    REQUIRE((held - ts.tip).norm() > 2e-3);  // the tissue lags the tip
    CHECK(held.z() > 0.02 + 1e-4);           // but it was lifted
    const auto c = sim::scene_content(m, s);
    REQUIRE(c.tools.size() == 1);
    const auto& jaw = std::get<softcut::render::GrasperShape>(c.tools[0]);
    CHECK((jaw.pivot + jaw.axis * jaw.jaw_length - held).norm() <= 1e-12);
  }

  TEST_CASE("a scalpel whose edge points along up (a stab) is drawn as a blade, not refused as a line") {
    auto spec = softcut::test::cantilever_spec(softcut::test::scratch_dir("sim_frame_scene_stab"), 0.2);
    tools::ToolSpec blade;
    blade.name = "stab";
    blade.kind = tools::ToolSpec::Kind::scalpel;
    blade.path = tools::Path::fixed_at(V(0.1, 0.01, 0.5));
    blade.force = tools::Ramp::constant_value(0.001);
    for (const V& axis : {V(0, 0, 1), V(0, 0, -2), V(0.01, 0, 1), V(0, 1, 0)}) {
      CAPTURE(axis.transpose());
      blade.blade_axis = axis;
      spec.tools = {blade};
      spec.outputs.render.up = V(0, 0, 1);
      const sim::Model m = sim::compile(spec);
      sim::State s = sim::make_state(m);
      sim::step(m, s);
      const softcut::render::SceneContent c = sim::scene_content(m, s);
      REQUIRE(c.tools.size() == 1);
      const auto& b = std::get<softcut::render::ScalpelShape>(c.tools[0]);
      const V e = b.edge_b - b.edge_a, back = b.spine - b.edge_b;
      CHECK(e.norm() == doctest::Approx(blade.blade_length));
      CHECK(std::abs(back.normalized().dot(e.normalized())) <= 1e-12);  // the blade stands normal to its edge
      softcut::render::Triangles tris;
      CHECK(softcut::render::add_tool(tris, c.tools[0], 8, {1, 1, 1, 1}) > 0);  // drawn, not refused
      // A sideways edge keeps its back toward up, as before.
      if (axis.z() == 0) CHECK(back.normalized().dot(V(0, 0, 1)) == doctest::Approx(1.0));
    }
  }

  TEST_CASE("a shaft follows shaft, else against the push, else back along the approach, else up") {
    tools::ToolSpec spec;
    spec.radius = 0.002;
    tools::ToolState ts;
    const V up(0, 0, 2);
    CHECK(sim::shaft_axis(spec, ts, up) == V(0, 0, 1));  // nothing known yet
    ts.has_start = true, ts.start_tip = V(0.01, 0, 0.01), ts.tip = V(0.01, 0, 0.0095);
    CHECK(sim::shaft_axis(spec, ts, up) == V(0, 0, 1));  // moved less than a radius
    ts.tip = V(0, 0, 0);  // on its way in: trails back to where it started
    CHECK((sim::shaft_axis(spec, ts, up) - V(1, 0, 1).normalized()).norm() < 1e-15);
    ts.touched = true, ts.approach = V(0, -1, 0);  // from the first contact on, the approach is kept
    CHECK(sim::shaft_axis(spec, ts, up) == V(0, -1, 0));
    spec.direction = V(0, 0, -3);  // a probe pushing down: the shaft is behind the push
    CHECK(sim::shaft_axis(spec, ts, up) == V(0, 0, 1));
    spec.kind = tools::ToolSpec::Kind::grasper;  // a grasper pulls along `direction`: not its shaft
    CHECK(sim::shaft_axis(spec, ts, up) == V(0, -1, 0));
    spec.shaft = V(3, 0, 4);  // given: it wins
    CHECK(sim::shaft_axis(spec, ts, up) == V(0.6, 0, 0.8));
    spec.shaft = V(std::nan(""), 0, 0);
    spec.path = tools::Path::fixed_at(V::Zero());
    spec.force = tools::Ramp::constant_value(0.1);
    CHECK_THROWS_WITH_AS(tools::check_tool(spec, "s.lua:3"), doctest::Contains("shaft must be finite"), softcut::Error);
  }

  TEST_CASE("a grasper coming in at an angle is drawn along its approach and keeps it while it drags") {
    auto spec = softcut::test::cantilever_spec(softcut::test::scratch_dir("sim_frame_scene_approach"), 0.6);
    spec.loads.clear();
    // In from the upper right at 45 degrees to the top face (z = 0.02), then dragged along y.
    const V start(0.09, 0.01, 0.042), touch(0.07, 0.01, 0.022);
    spec.tools = {softcut::test::spring_grasper(50, 0.003, tools::Path::polyline({0.0, 0.2, 0.3, 0.6}, {start, touch, touch, touch + V(0, 0.01, 0.002)}))};
    const sim::Model m = sim::compile(spec);
    sim::State s = sim::make_state(m);
    const V in = (start - touch).normalized();
    for (int k = 0; k < 7; ++k) {  // t = 0 .. 0.6 s: in, touch at 0.2 s, hold, drag
      sim::step(m, s);
      const auto c = sim::scene_content(m, s);
      REQUIRE(c.tools.size() == 1);
      const V shaft = -std::get<softcut::render::GrasperShape>(c.tools[0]).axis;  // the jaws point against it
      CAPTURE(s.time);
      CHECK(s.tools[0].engaged == (s.time > 0.15));
      if (k == 0) CHECK(shaft == V(0, 0, 1));  // not moved yet: the camera's up
      else CHECK((shaft - in).norm() < 1e-12);  // trailing on the way in, then the approach kept while dragging
    }
    REQUIRE(s.tools[0].engaged);
    CHECK(s.tools[0].touched);
  }

  TEST_CASE("a camera on a path, and one following a tool along its shaft like an endoscope") {
    auto spec = softcut::test::cantilever_spec(softcut::test::scratch_dir("sim_frame_scene_camera"), 0.3);
    spec.outputs.render.enabled = true;
    tools::ToolSpec probe;
    probe.name = "probe";
    probe.radius = 0.004;
    probe.force = tools::Ramp::constant_value(0.001);
    probe.shaft = V(0, 0, 2);  // drawn straight up
    probe.path = tools::Path::polyline({0.0, 0.3}, {V(0.05, 0.01, 0.025), V(0.08, 0.01, 0.025)});
    spec.tools = {probe};
    auto path = spec;
    path.outputs.camera.kind = sim::CameraSpec::Kind::path;
    path.outputs.camera.eye = tools::Path::polyline({0.0, 0.2}, {V(0.2, -0.2, 0.1), V(0.0, -0.2, 0.1)});
    path.outputs.camera.target = V(0.05, 0.01, 0.01);
    path.outputs.camera.fov_deg = 45;
    {
      const sim::Model m = sim::compile(path);
      sim::State s = sim::make_state(m);
      sim::step(m, s);
      sim::step(m, s);  // t = 0.1
      const auto c = sim::camera_settings(m, s);
      CHECK_FALSE(c.auto_frame);
      CHECK((c.eye - V(0.1, -0.2, 0.1)).norm() < 1e-12);
      CHECK(c.target == V(0.05, 0.01, 0.01));
      CHECK(c.fov_y_deg == 45);
    }
    auto follow = spec;
    follow.outputs.camera.kind = sim::CameraSpec::Kind::follow;
    follow.outputs.camera.follow = "probe";
    follow.outputs.camera.distance = 0.05;
    follow.outputs.camera.offset = 0.01;
    follow.outputs.camera.up = V(0, 1, 0);
    const sim::Model m = sim::compile(follow);
    sim::State s = sim::make_state(m);
    for (int f = 0; f < 3; ++f) {
      sim::step(m, s);
      const auto c = sim::camera_settings(m, s);
      const V tip = s.tools[0].tip;
      CAPTURE(f);
      // 5 cm up the shaft (+z) from the tip, 1 cm off it toward up (+y), looking at the tip.
      CHECK((c.eye - (tip + V(0, 0.01, 0.05))).norm() < 1e-12);
      CHECK((c.target - tip).norm() < 1e-12);
    }
    CHECK(s.tools[0].tip.x() > 0.05);  // the camera moved with the tool
    auto missing = follow;
    missing.outputs.camera.follow = "nobody";
    CHECK(softcut::test::contains(softcut::test::error_of([&] { sim::compile(missing); }), "follows tool 'nobody'"));
  }
}
