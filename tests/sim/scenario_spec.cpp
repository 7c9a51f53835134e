// engine/sim/scenario_spec.cpp: check_spec refuses every out-of-range
// setting with a message naming the setting and the accepted range, and
// accepts the defaults and the edges of each range.
#include "sim/scenario_spec.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <functional>
#include <limits>

#include "core/error.hpp"

using namespace softcut;
using namespace softcut::sim;

namespace {

struct Case {
  const char* what;                       // the setting, for the report
  std::function<void(ScenarioSpec&)> set; // makes the default spec bad
  const char* message;                    // part of the expected message
};

const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();

}  // namespace

TEST_SUITE("sim/scenario_spec") {
  TEST_CASE("parse_X: every name users write, and a misspelt one named with a did-you-mean") {
    CHECK(sim::parse_load_direction("world") == sim::LoadSpec::Direction::world);
    CHECK(sim::parse_load_direction("normal") == sim::LoadSpec::Direction::normal);
    CHECK(sim::parse_render_style("clinical") == sim::RenderSettings::Style::clinical);
    CHECK(sim::parse_render_style("paper") == sim::RenderSettings::Style::paper);
    CHECK(sim::parse_render_style("debug") == sim::RenderSettings::Style::debug);
    CHECK(sim::parse_camera_kind("path") == sim::CameraSpec::Kind::path);
    CHECK(sim::parse_camera_kind("follow") == sim::CameraSpec::Kind::follow);
    CHECK_THROWS_WITH(sim::parse_load_direction("normals"), doctest::Contains("unknown direction kind 'normals' (did you mean 'normal'?)"));
    CHECK_THROWS_WITH(sim::parse_render_style("clincal"), doctest::Contains("(did you mean 'clinical'?)"));
    CHECK_THROWS_WITH(sim::parse_camera_kind("none"), doctest::Contains("camera: unknown kind 'none'"));
  }

  TEST_CASE("the default spec and the edges of each range are accepted") {
    ScenarioSpec s;
    CHECK_NOTHROW(check_spec(s));
    s.timeline.duration = 0;  // a single frame at t = 0
    s.outputs.render.width = s.outputs.render.height = 16384;
    s.outputs.render.msaa_samples = 0;
    s.cutting.min_dihedral_deg = 0;
    s.solver.cg_max_iterations = 0;
    s.outputs.render.background = Eigen::Vector3d(0, 1, 0);
    CHECK_NOTHROW(check_spec(s));
    s.timeline.fps = 100;
    s.timeline.duration = 1e5;  // exactly the frame limit
    CHECK_NOTHROW(check_spec(s));
    s.timeline.duration = 1;
    for (double fps : {Timeline::kMinFps, Timeline::kMaxFps}) {
      s.timeline.fps = fps;
      CHECK_NOTHROW(check_spec(s));
    }
  }

  TEST_CASE("each out-of-range setting is an error naming it") {
    const std::vector<Case> cases = {
        {"empty name", [](ScenarioSpec& s) { s.name = ""; }, "name must not be empty"},
        {"path in name", [](ScenarioSpec& s) { s.name = "../x"; }, "name must not contain path separators"},
        {"negative duration", [](ScenarioSpec& s) { s.timeline.duration = -1; }, "duration must be a finite number >= 0 s"},
        {"infinite duration", [](ScenarioSpec& s) { s.timeline.duration = kInf; }, "duration must be a finite number"},
        {"zero frame rate", [](ScenarioSpec& s) { s.timeline.fps = 0; }, "fps must be > 0 Hz, got 0"},
        {"NaN frame rate", [](ScenarioSpec& s) { s.timeline.fps = kNaN; }, "fps must be > 0 Hz"},
        {"too many frames", [](ScenarioSpec& s) { s.timeline.duration = 1e6; }, "the limit is 10000000"},
        {"vtu_every", [](ScenarioSpec& s) { s.outputs.vtu_every = 0; }, "outputs: vtu_every must be >= 1, got 0"},
        {"render width", [](ScenarioSpec& s) { s.outputs.render.width = 0; }, "outputs.render: size must be 1..16384"},
        {"render height", [](ScenarioSpec& s) { s.outputs.render.height = 16385; }, "size must be 1..16384 pixels"},
        {"fov", [](ScenarioSpec& s) { s.outputs.render.fov_deg = 180; }, "fov_deg must lie in (0, 180), got 180"},
        {"render every", [](ScenarioSpec& s) { s.outputs.render.every = 0; }, "outputs.render: every must be >= 1"},
        {"eye", [](ScenarioSpec& s) { s.outputs.render.eye.x() = kNaN; }, "eye and target must be finite"},
        {"target", [](ScenarioSpec& s) { s.outputs.render.target.z() = kInf; }, "eye and target must be finite"},
        {"up", [](ScenarioSpec& s) { s.outputs.render.up.setZero(); }, "up nonzero"},
        {"elevation", [](ScenarioSpec& s) { s.outputs.render.elevation_deg = 90; }, "output: render: elevation must lie in (-90, 90) degrees, got 90"},
        {"elevation where", [](ScenarioSpec& s) { s.outputs.where = "x.lua:9", s.outputs.render.elevation_deg = -90; }, "x.lua:9: output: render: elevation"},
        {"denormal frame rate", [](ScenarioSpec& s) { s.timeline.fps = 5e-324; }, "fps = 4.94065645841e-324 Hz is out of range: it must lie in [0.001, 10000]"},
        {"huge frame rate", [](ScenarioSpec& s) { s.timeline.fps = 2e4; s.timeline.duration = 0; }, "fps = 20000 Hz is out of range"},
        {"timeline where", [](ScenarioSpec& s) { s.timeline.where = "x.lua:1", s.timeline.fps = 1e-4; }, "x.lua:1: timeline: fps"},
        {"azimuth", [](ScenarioSpec& s) { s.outputs.render.azimuth_deg = kNaN; }, "azimuth_deg and orbit_deg_per_s must be finite"},
        {"orbit", [](ScenarioSpec& s) { s.outputs.render.orbit_deg_per_s = kInf; }, "orbit_deg_per_s must be finite"},
        {"background", [](ScenarioSpec& s) { s.outputs.render.background.y() = 1.5; }, "background components must lie in [0, 1]"},
        {"background NaN", [](ScenarioSpec& s) { s.outputs.render.background.x() = kNaN; }, "background components"},
        {"tissue colour", [](ScenarioSpec& s) { s.outputs.render.tissue_colors = {Eigen::Vector3d(0.5, 0.5, 0.5), Eigen::Vector3d(0, kNaN, 0)}; }, "tissue colour 2 has components outside [0, 1]"},
        {"tissue colours", [](ScenarioSpec& s) { s.outputs.render.tissue_colors.assign(257, Eigen::Vector3d(0.5, 0.5, 0.5)); }, "at most 256 tissue colours, got 257"},
        {"prestress", [](ScenarioSpec& s) { s.prestress.push_back({"p", "x.lua:3", {}, 0.6 * Eigen::Matrix3d::Identity()}); }, "x.lua:3: prestress 'p': initial strain component eps_xx must be a finite number within +-0.5"},
        {"prestress shear", [](ScenarioSpec& s) { Eigen::Matrix3d e = Eigen::Matrix3d::Zero(); e(0, 1) = e(1, 0) = 0.6; s.prestress.push_back({"q", "", {}, e}); }, "eps_xy must be a finite number within +-0.5 (a small-strain model), got 0.6"},
        {"prestress asymmetric", [](ScenarioSpec& s) { Eigen::Matrix3d e = Eigen::Matrix3d::Zero(); e(0, 1) = 0.1; s.prestress.push_back({"r", "", {}, e}); }, "the strain must be a finite symmetric tensor"},
        {"msaa", [](ScenarioSpec& s) { s.outputs.render.msaa_samples = 17; }, "msaa_samples must be 0..16"},
        {"cg tolerance", [](ScenarioSpec& s) { s.solver.cg_tolerance = 1; }, "cg_tolerance must lie in (0, 1), got 1"},
        {"cg iterations", [](ScenarioSpec& s) { s.solver.cg_max_iterations = -1; }, "cg_max_iterations must be >= 0"},
        {"snap", [](ScenarioSpec& s) { s.cutting.snap_fraction = 0.5; }, "snap_fraction must lie in (0, 0.5), got 0.5"},
        {"snap zero", [](ScenarioSpec& s) { s.cutting.snap_fraction = 0; }, "snap_fraction must lie in (0, 0.5)"},
        {"dihedral", [](ScenarioSpec& s) { s.cutting.min_dihedral_deg = 60; }, "min_dihedral_deg must lie in [0, 60), got 60"},
        {"dihedral NaN", [](ScenarioSpec& s) { s.cutting.min_dihedral_deg = kNaN; }, "min_dihedral_deg must lie in [0, 60)"},
    };
    for (const Case& c : cases) {
      CAPTURE(c.what);
      ScenarioSpec s;
      c.set(s);
      CHECK_THROWS_WITH_AS(check_spec(s), doctest::Contains(c.message), Error);
    }
  }

  TEST_CASE("the frame limit names the scenario file") {
    ScenarioSpec s;
    s.source = "/some/where/long_run.lua";
    s.timeline.duration = 1e6;
    CHECK_THROWS_WITH_AS(check_spec(s), doctest::Contains("long_run.lua: timeline: 30000000 frames"), Error);
  }

  TEST_CASE("materials and loads are checked by name") {
    {
      ScenarioSpec s;
      MaterialAssignment m;
      m.name = "fat";
      m.young = -5;
      s.materials.push_back(m);
      CHECK_THROWS_WITH_AS(check_spec(s), doctest::Contains("fat"), Error);
      s.materials[0].preset = "liver";  // a preset may be scaled by a positive young only
      CHECK_THROWS_WITH_AS(check_spec(s), doctest::Contains("material 'fat': young must be > 0 Pa, got -5"), Error);
      s.materials[0].young = 0;  // 0: the preset's own value
      CHECK_NOTHROW(check_spec(s));
    }
    {
      ScenarioSpec s;
      LoadSpec l;
      l.name = "push";
      l.direction = Eigen::Vector3d::Zero();
      s.loads.push_back(l);
      CHECK_THROWS_WITH_AS(check_spec(s), doctest::Contains("load 'push': direction must be a nonzero finite vector"),
                           Error);
      s.loads[0].direction = Eigen::Vector3d::UnitZ();
      CHECK_NOTHROW(check_spec(s));
      s.loads.push_back(s.loads[0]);
      CHECK_THROWS_WITH_AS(check_spec(s), doctest::Contains("load 'push': another load has the same name"), Error);
    }
    {
      ScenarioSpec s;
      s.timeline.duration = 0.5;
      ExpectationSpec e;
      e.name = "late";
      e.where = "scenario.lua:7";
      e.at = 0.5;  // the last frame: due
      s.expectations.push_back(e);
      CHECK_NOTHROW(check_spec(s));
      s.expectations[0].at = 3;
      CHECK_THROWS_WITH_AS(check_spec(s),
                           doctest::Contains("scenario.lua:7: expectation 'late': at = 3 s is after the end of the "
                                             "timeline (duration = 0.5 s)"),
                           Error);
    }
  }
}
