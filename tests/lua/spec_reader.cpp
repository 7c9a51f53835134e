// What a script's s:camera, s:output and s:material fields become in the
// ScenarioSpec (lua/spec_reader.cpp), and the mistakes refused at their line.
#include <doctest/doctest.h>

#include "lua_test_support.hpp"

using softcut::test::kBoxHead;
using softcut::test::write_scenario;
namespace sim = softcut::sim;

namespace {

sim::ScenarioSpec spec_of(const std::string& name, const std::string& body) {
  softcut::app::RunRequest req;
  req.scenario = write_scenario(name, std::string(kBoxHead) + body + "\nreturn s\n");
  return softcut::app::load_scenario_spec(req);
}

std::string error_of(const std::string& name, const std::string& body) {
  return softcut::test::error_of([&] { spec_of(name, body); });
}

const char* kJaw =
    "s:grasper{ name = 'jaw', radius = 0.005, stiffness = 100, path = { 0.08, 0.02, 0.045 } }\n";

}  // namespace

TEST_SUITE("lua/spec_reader") {
  TEST_CASE("render's depth, labels, record and style, s:output's video and s:material's color reach the spec") {
    const auto s = spec_of("spec_render",
                           "s:material{ label = 1, young = 2e4, poisson = 0.4, color = { 0.2, 0.6, 0.3 } }\n"
                           "s:output{ video = true, render = { depth = true, labels = true, record = false, style = 'debug' } }");
    const sim::RenderSettings& r = s.outputs.render;
    CHECK(r.enabled);
    CHECK(r.video);
    CHECK(r.depth);
    CHECK(r.labels);
    CHECK(r.record == sim::RenderSettings::Record::off);
    CHECK(r.style == sim::RenderSettings::Style::debug);
    CHECK(r.show_forces);  // the debug style's markers
    CHECK(r.show_loads);
    REQUIRE(s.materials.size() == 2);
    CHECK_FALSE(s.materials[0].has_color);
    CHECK(s.materials[1].has_color);
    CHECK(s.materials[1].color == Eigen::Vector3d(0.2, 0.6, 0.3));
    // The clinical default: no markers.
    const auto plain = spec_of("spec_render_plain", "s:output{ render = { width = 64, height = 48 } }");
    CHECK_FALSE(plain.outputs.render.show_forces);
    CHECK_FALSE(plain.outputs.render.show_loads);
    CHECK(plain.outputs.render.record == sim::RenderSettings::Record::automatic);
    CHECK_FALSE(plain.outputs.render.video);
  }

  TEST_CASE("s:camera on a path or following a tool") {
    const auto p = spec_of("spec_camera_path",
                           "s:camera{ path = softcut.path.polyline{ times = { 0, 1 }, points = { { 0.2, 0, 0.1 }, { 0.1, -0.2, 0.1 } } },\n"
                           "          target = { 0.05, 0.02, 0.02 }, fov = 50, up = { 0, 1, 0 } }");
    const sim::CameraSpec& c = p.outputs.camera;
    CHECK(c.kind == sim::CameraSpec::Kind::path);
    CHECK(c.fov_deg == 50);
    CHECK(c.up == Eigen::Vector3d(0, 1, 0));
    CHECK(c.target_moves);  // a point is a fixed path
    CHECK(softcut::tools::evaluate(c.target_path, 0.7) == Eigen::Vector3d(0.05, 0.02, 0.02));
    CHECK((softcut::tools::evaluate(c.eye, 0.5) - Eigen::Vector3d(0.15, -0.1, 0.1)).norm() < 1e-12);
    CHECK(softcut::test::contains(c.where, "scenario.lua:"));
    const auto f = spec_of("spec_camera_follow", std::string(kJaw) + "s:camera{ follow = 'jaw', distance = 0.05, offset = 0.02, lead = 0.01 }");
    CHECK(f.outputs.camera.kind == sim::CameraSpec::Kind::follow);
    CHECK(f.outputs.camera.follow == "jaw");
    CHECK(f.outputs.camera.distance == 0.05);
    CHECK(f.outputs.camera.offset == 0.02);
    CHECK(f.outputs.camera.lead == 0.01);
  }

  TEST_CASE("camera mistakes are refused at their line, with a did-you-mean") {
    CHECK(softcut::test::contains(error_of("spec_camera_e1", std::string(kJaw) + "s:camera{ follow = 'jow' }"),
                                  "follows tool 'jow', which is not defined yet (did you mean 'jaw'?)"));
    CHECK(softcut::test::contains(error_of("spec_camera_e2", "s:camera{ path = { 0, 0, 1 } }"), "needs a target"));
    CHECK(softcut::test::contains(error_of("spec_camera_e3", std::string(kJaw) + "s:camera{ follow = 'jaw', target = { 0, 0, 0 } }"),
                                  "drop target"));
    CHECK(softcut::test::contains(error_of("spec_camera_e4", "s:camera{ path = { 0, 0, 1 }, target = { 0, 0, 0 } }\n"
                                                             "s:camera{ path = { 0, 0, 1 }, target = { 0, 0, 0 } }"),
                                  "already set at"));
    CHECK(softcut::test::contains(error_of("spec_camera_e5", "s:camera{ target = { 0, 0, 0 } }"), "scenario.lua:"));
  }
}
