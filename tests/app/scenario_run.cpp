#include "app/scenario_run.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <fstream>
#include <sstream>

#include "core/warning.hpp"
#include "lua/lua_test_support.hpp"
#include "sim/fixtures.hpp"
#include "sim/model.hpp"

namespace fs = std::filesystem;
using softcut::test::contains;
using softcut::test::kBoxHead;
using softcut::test::scenario_error;
using softcut::test::write_scenario;

using softcut::test::slurp;

namespace {

const char* kPull = R"(
s:load{ name = "pull", nodes = tip, force = {0, 0, -P.force}, ramp = softcut.ramp.linear{ t1 = 0.5 } }
s:expect{ name = "down", at = 0.5, nodes = tip, component = "z", max = 0 }
s:expect{ name = "tiny", at = 0.3, nodes = tip, measure = "max", max = 1e-9 }
s:expect{ name = "fn", at = 0.2, check = function(f) return f.time > 0.1, "never" end }
return s
)";

// A script written in C++: the cantilever (sim/fixtures.hpp) with a bounds
// expectation and a check function at 0.1 s; it records what the run asked of
// it and stops the run after `stop_after` frames.
struct CppScript final : softcut::sim::ScenarioScript {
  struct Log {
    fs::path confined;
    int starts = 0, frames = 0, checks = 0;
    int frame_at_start = -2;
  };
  Log* log;
  fs::path dir;
  int stop_after;
  CppScript(Log* l, fs::path d, int stop) : log(l), dir(std::move(d)), stop_after(stop) {}

  softcut::sim::ScenarioSpec spec() override {
    namespace sim = softcut::sim;
    sim::ScenarioSpec s = softcut::test::cantilever_spec(dir, 1.0);
    s.description = "a bar sags";
    sim::ExpectationSpec sags;
    sags.name = "sags";
    sags.where = "cpp:1";
    sags.at = 0.1;
    sags.bounds = true;
    sags.nodes = sim::NodeSelector::box(Eigen::Vector3d(0.1, -1, -1), Eigen::Vector3d(0.1, 1, 1));
    sags.component = sim::ExpectationSpec::Component::z;
    sags.max = 0.0;
    sim::ExpectationSpec asked;
    asked.name = "asked";
    asked.where = "cpp:2";
    asked.at = 0.1;
    s.expectations = {sags, asked};
    return s;
  }
  void confine_writes(const fs::path& d) override { log->confined = d; }
  void start() override { ++log->starts; }
  bool on_frame(const softcut::sim::Model&, softcut::sim::State& st) override {
    if (log->frame_at_start == -2) log->frame_at_start = st.frame;
    return ++log->frames < stop_after;
  }
  std::pair<bool, std::string> check(int index, const softcut::sim::Model&, softcut::sim::State& st) override {
    ++log->checks;
    return {false, "expectation " + std::to_string(index) + " asked at t = " + std::to_string(st.time)};
  }
};

std::string params_scenario(const std::string& name) {
  return write_scenario(name, "local P = softcut.params{ force = 0.05, label = 'x', fast = false }\n" + std::string(kBoxHead) + kPull)
      .string();
}

}  // namespace

TEST_SUITE("app/scenario_run") {
  TEST_CASE("a run writes the outputs and reports each expectation with its line") {
    softcut::app::RunOutcome out;
    const fs::path f = params_scenario("runner_basic");
    REQUIRE(scenario_error(f, &out) == "");
    CHECK(out.name == "scenario");
    CHECK(out.num_frames == 6);
    CHECK(out.result.frames == 6);
    CHECK(fs::exists(out.out_dir / "displacements.csv"));
    CHECK(contains(slurp(out.out_dir / "summary.json"), "\"exit_reason\": \"completed\""));
    REQUIRE(out.expectations.size() == 3);
    // Evaluated in time order: fn (0.2), tiny (0.3), down (0.5).
    CHECK(out.expectations[0].name == "fn");
    CHECK(out.expectations[0].ok);
    CHECK(out.expectations[1].name == "tiny");
    CHECK_FALSE(out.expectations[1].ok);
    CHECK(out.expectations[1].where == f.string() + ":11");
    CHECK(contains(out.expectations[1].message, "max |u| of 9 nodes at t = 0.3 s is "));
    CHECK(contains(out.expectations[1].message, "outside [-inf, 1e-09] m"));
    CHECK(out.expectations[2].ok);
  }

  TEST_CASE("--set overrides params by the defaults' types - unknown keys are suggested") {
    softcut::app::RunRequest req;
    req.overrides = {{"force", "0.1"}};
    const fs::path f = params_scenario("runner_set");
    REQUIRE(scenario_error(f, nullptr, req) == "");
    req.overrides = {{"forse", "1"}};
    CHECK(contains(scenario_error(f, nullptr, req), "scenario.lua:1: params: --set forse: the scenario has no parameter 'forse' (did you mean 'force'?)"));
    req.overrides = {{"force", "abc"}};
    CHECK(contains(scenario_error(f, nullptr, req), "--set force=abc: 'abc' is not a number"));
    req.overrides = {{"fast", "maybe"}};
    CHECK(contains(scenario_error(f, nullptr, req), "--set fast=maybe: expected true or false"));
    const fs::path g = write_scenario("runner_noparams", std::string(kBoxHead) + "return s\n");
    req.overrides = {{"force", "1"}};
    CHECK(contains(scenario_error(g, nullptr, req), "--set force=...: the scenario declares no parameters"));
  }

  TEST_CASE("twice the force gives twice the displacement") {
    const fs::path f = params_scenario("runner_linear");
    softcut::app::RunRequest r1, r2;
    r1.out_dir = f.parent_path() / "a";
    r2.out_dir = f.parent_path() / "b";
    r2.overrides = {{"force", "0.1"}};
    softcut::app::RunOutcome a, b;
    REQUIRE(scenario_error(f, &a, r1) == "");
    REQUIRE(scenario_error(f, &b, r2) == "");
    std::istringstream sa(slurp(a.out_dir / "displacements.csv")), sb(slurp(b.out_dir / "displacements.csv"));
    std::string la, lb;
    int rows = 0;
    std::getline(sa, la), std::getline(sb, lb);
    while (std::getline(sa, la) && std::getline(sb, lb)) {
      const double ua = std::stod(la.substr(la.rfind(',') + 1)), ub = std::stod(lb.substr(lb.rfind(',') + 1));
      CHECK(ub == doctest::Approx(2 * ua).epsilon(1e-9));
      ++rows;
    }
    CHECK(rows > 0);
  }

  TEST_CASE("same scenario, same build: byte-identical logs") {
    const fs::path f = params_scenario("runner_determinism");
    softcut::app::RunRequest r1, r2;
    r1.out_dir = f.parent_path() / "a";
    r2.out_dir = f.parent_path() / "b";
    REQUIRE(scenario_error(f, nullptr, r1) == "");
    REQUIRE(scenario_error(f, nullptr, r2) == "");
    CHECK(slurp(r1.out_dir / "displacements.csv") == slurp(r2.out_dir / "displacements.csv"));
  }

  TEST_CASE("interruption: the frame finishes, outputs are valid and marked interrupted") {
    const fs::path f = params_scenario("runner_interrupt");
    std::atomic<bool> flag{false};
    softcut::app::RunRequest req;
    req.interrupt = &flag;
    req.progress = [&](int frame, int, double) { if (frame == 1) flag = true; };  // as a signal would, mid-run
    softcut::app::RunOutcome out;
    REQUIRE(scenario_error(f, &out, req) == "");
    CHECK(out.result.reason == softcut::sim::ExitReason::interrupted);
    CHECK(out.result.frames == 2);
    CHECK(contains(slurp(out.out_dir / "summary.json"), "\"interrupted\": true"));
    CHECK(slurp(out.out_dir / "displacements.csv").rfind("frame,time,node,ux,uy,uz\n", 0) == 0);
    // Expectations after the stop are reported as not reached.
    bool pending = false;
    for (const auto& e : out.expectations) pending = pending || contains(e.message, "not reached");
    CHECK(pending);
  }

  TEST_CASE("the instruction budget applies per call: long runs are fine, an endless on_frame is not") {
    softcut::app::RunRequest req;
    req.instruction_budget = 150'000;  // the main chunk's checks take most of 100k
    const auto ok = write_scenario("runner_budget_ok", std::string(kBoxHead) +
        "s:on_frame(function(f) local x = 0 for i = 1, 10000 do x = x + i end end)\nreturn s\n");
    softcut::app::RunOutcome out;
    CHECK(scenario_error(ok, &out, req) == "");  // 6 frames x ~40k instructions > 150k in total
    CHECK(out.result.frames == 6);
    const auto bad = write_scenario("runner_budget_bad", std::string(kBoxHead) +
        "s:on_frame(function(f)\n  while true do end\nend)\nreturn s\n");
    const std::string e = scenario_error(bad, nullptr, req);
    CHECK(e.rfind(bad.string() + ":8: instruction budget of 150000 instructions exceeded", 0) == 0);
  }

  TEST_CASE("output settings reach the engine: logged nodes, VTU series") {
    const auto f = write_scenario("runner_vtu", std::string(kBoxHead) +
        "s:output{ vtu = true, vtu_every = 2, log = softcut.select.nodes{ 0, 44 } }\nreturn s\n");
    softcut::app::RunOutcome out;
    REQUIRE(scenario_error(f, &out) == "");
    CHECK(fs::exists(out.out_dir / "series.pvd"));
    CHECK(fs::exists(out.out_dir / "vtu" / "frame_000000.vtu"));
    CHECK(fs::exists(out.out_dir / "vtu" / "frame_000004.vtu"));
    CHECK_FALSE(fs::exists(out.out_dir / "vtu" / "frame_000001.vtu"));
    std::istringstream csv(slurp(out.out_dir / "displacements.csv"));
    int rows = 0;
    for (std::string line; std::getline(csv, line);) ++rows;
    CHECK(rows == 1 + 6 * 2);  // header + frames x logged nodes
  }

  TEST_CASE("no script code runs after the run: expectations not reached are read from the spec") {
    // A script that plants a function where the runner used to call one after
    // the last frame cannot change (or stop) what is reported then.
    const fs::path f = write_scenario(
        "runner_after",
        "local P = softcut.params{ force = 0.05, label = 'x', fast = false }\n" + std::string(kBoxHead) +
            "require('scenario').pending = function() error('script code ran after the run') end\n" + kPull);
    softcut::app::RunRequest req;
    req.max_frames = 1;
    softcut::app::RunOutcome out;
    REQUIRE(scenario_error(f, &out, req) == "");
    int not_reached = 0;
    for (const auto& e : out.expectations) not_reached += contains(e.message, "not reached");
    CHECK(not_reached == 3);
  }

  TEST_CASE("--frames limits the run") {
    softcut::app::RunRequest req;
    req.max_frames = 2;
    softcut::app::RunOutcome out;
    REQUIRE(scenario_error(params_scenario("runner_frames"), &out, req) == "");
    CHECK(out.result.frames == 2);
  }

  TEST_CASE("scenario-level errors name the file and what to add") {
    CHECK(contains(scenario_error(write_scenario("runner_none", "local x = 1\n")), "the script made no scenario"));
    CHECK(contains(scenario_error(write_scenario("runner_nomesh", "return softcut.scenario{ duration = 1 }\n")),
                   "scenario.lua: scenario: no mesh"));
    CHECK(contains(scenario_error(write_scenario("runner_nofix", R"(
local s = softcut.scenario{ duration = 1 }
s:mesh{ generate = "box" }
return s
)")),
                   "scenario.lua:2: scenario: no fixed nodes"));
    CHECK(contains(scenario_error(write_scenario("runner_late", std::string(kBoxHead) + "s:expect{ at = 3, nodes = tip, max = 1 }\nreturn s\n")),
                   "scenario.lua:7: expectation 'expect1': at = 3 s is after the end of the timeline (duration = 0.5 s)"));
  }

  TEST_CASE("load_scenario_spec fills the engine's spec") {
    softcut::app::RunRequest req;
    req.scenario = params_scenario("runner_spec");
    const softcut::sim::ScenarioSpec spec = softcut::app::load_scenario_spec(req);
    CHECK(spec.mesh.generator == "box");
    CHECK(spec.mesh.options.at("max.x") == 0.1);
    REQUIRE(spec.loads.size() == 1);
    CHECK(spec.loads[0].name == "pull");
    CHECK(spec.loads[0].direction.z() == -1);
    CHECK(spec.loads[0].magnitude.kind == softcut::tools::Ramp::Kind::linear);
    CHECK(spec.loads[0].magnitude.to == doctest::Approx(0.05));
    CHECK(spec.materials.at(0).preset == "liver");
    CHECK(spec.timeline.fps == 10);
    CHECK(spec.fixed.kind == softcut::sim::NodeSelector::Kind::box);
  }

  TEST_CASE("s:scalpel cuts through the Lua API: Frame:cutting, pressure, ids of new nodes - bad blades name the line") {
    const std::string body = std::string(kBoxHead) + R"(
s:operational{ box = { min = {0.02, -1, -1}, max = {0.08, 1, 1} } }
s:scalpel{ name = "blade", length = 0.06, axis = {0, 1, 0}, radius = 0.004, cut_pressure = 100,
  path = softcut.path.polyline{ times = {0, 0.1, 0.5}, points = {{0.055, 0.02, 0.0425}, {0.055, 0.02, 0.0425}, {0.055, 0.02, 0.02}} },
  force = softcut.ramp.constant(1) }
local newest, pressure
s:on_frame(function(f)
  local c = f:cutting()
  if c.nodes > m.num_nodes then newest = f:displacement(c.nodes - 1) end
  if f.time == 0 then pressure = f:tool("blade").pressure end
end)
s:expect{ name = "cut", at = 0.5, check = function(f)
  local c = f:cutting()
  -- an incision, not a cut through: faces opened, still one piece
  return c.events > 0 and c.nodes_added > 0 and c.components == 1 and c.pieces == 1 and c.detached == 0
    and c.faces_separated > 0 and c.faces_pending >= 0 and newest ~= nil, "no cut"
end }
s:expect{ name = "pressure", at = 0.5, check = function(f)
  return math.abs(pressure - 1 / (0.06 * 0.008)) < 1e-9, ("pressure %g"):format(pressure)
end }
return s
)";
    softcut::app::RunOutcome out;
    REQUIRE(scenario_error(write_scenario("runner_scalpel", body), &out) == "");
    REQUIRE(out.expectations.size() == 2);
    CHECK(out.expectations[0].ok);
    CHECK(out.expectations[1].ok);
    CHECK(softcut::test::read_json(out.out_dir / "summary.json")["cutting"]["scalpels"] == 1);

    // Every scalpel field and s:cutting reach the engine's spec.
    softcut::app::RunRequest req;
    req.scenario = write_scenario("runner_scalpel_spec", std::string(kBoxHead) + R"(
s:operational{ box = { min = {0.02, -1, -1}, max = {0.08, 1, 1} } }
s:scalpel{ name = "blade", length = 0.03, axis = {0, 0, 2}, radius = 0.002, cut_pressure = 5e3, back = {0, 0.01, 0},
  path = softcut.path.fixed{ 0.05, 0.02, 0.05 }, stiffness = 50, start = 0.1, stop = 0.4, shaft = {0, 1, 1} }
s:grasper{ name = "jaw", path = softcut.path.fixed{ 0, 0, 0.05 }, stiffness = 5, shaft = {1, 0, 1} }
s:probe{ name = "tip", path = softcut.path.fixed{ 0, 0, 0.05 }, stiffness = 5, shaft = {-1, 0, 1} }
s:cutting{ snap_fraction = 0.2, min_dihedral = 12 }
s:output{ render = { show_inclusions = false, cut_color = {0.5, 0.1, 0.2} } }
return s
)");
    const softcut::sim::ScenarioSpec spec = softcut::app::load_scenario_spec(req);
    REQUIRE(spec.tools.size() == 3);
    CHECK(spec.tools[0].shaft == Eigen::Vector3d(0, 1, 1));  // drawing only: each tool's shaft
    CHECK(spec.tools[1].shaft == Eigen::Vector3d(1, 0, 1));
    CHECK(spec.tools[2].shaft == Eigen::Vector3d(-1, 0, 1));
    CHECK_FALSE(spec.outputs.render.show_inclusions);
    CHECK(spec.outputs.render.cut_color == Eigen::Vector3d(0.5, 0.1, 0.2));
    const softcut::tools::ToolSpec& t = spec.tools[0];
    CHECK(t.kind == softcut::tools::ToolSpec::Kind::scalpel);
    CHECK(t.drive == softcut::tools::ToolSpec::Drive::spring);
    CHECK(t.blade_length == 0.03);
    CHECK(t.blade_axis == Eigen::Vector3d(0, 0, 2));
    CHECK(t.blade_back == Eigen::Vector3d(0, 0.01, 0));
    CHECK(t.radius == 0.002);
    CHECK(t.cut_pressure == 5e3);
    CHECK(t.stiffness == 50);
    CHECK(t.start == 0.1);
    CHECK(t.stop == 0.4);
    CHECK(spec.cutting.snap_fraction == 0.2);
    CHECK(spec.cutting.min_dihedral_deg == 12);

    const fs::path bad = write_scenario("runner_scalpel_bad", std::string(kBoxHead) + R"(
s:scalpel{ name = "blade", path = softcut.path.fixed{ 0, 0, 0 }, force = 1 }
return s
)");
    const std::string err = scenario_error(bad);
    CHECK(contains(err, bad.string() + ":8: scalpel: missing field 'cut_pressure'"));

    // A zero shaft is refused where it is written (leaving it out means the default).
    const fs::path zero = write_scenario("runner_shaft_zero", std::string(kBoxHead) + R"(
s:grasper{ name = "jaw", path = softcut.path.fixed{ 0, 0, 0.05 }, stiffness = 5, shaft = {0, 0, 0} }
return s
)");
    CHECK(contains(scenario_error(zero), zero.string() + ":8: grasper: field 'shaft' must be a nonzero vector"));
    // A cut colour outside [0, 1] is refused, naming the setting.
    const fs::path colour = write_scenario("runner_cut_color", std::string(kBoxHead) + R"(
s:output{ render = { cut_color = {0.5, 1.5, 0.2} } }
return s
)");
    CHECK(contains(scenario_error(colour), "outputs.render: cut_color must be RGB in [0, 1]"));
  }

  TEST_CASE("a script without Lua: the run asks it for its spec and confines its writes, calls it per frame and reports its verdicts") {
    const fs::path dir = softcut::test::scratch_dir("app_cpp_script");
    CppScript::Log log;
    softcut::app::RunRequest req;
    req.scenario = dir / "bar.cpp";  // names the script in messages; never opened
    req.out_dir = dir / "out";
    req.backend = softcut::backend::Backend::cpu;
    const softcut::app::RunOutcome out =
        softcut::app::run_scenario(req, [&](const softcut::app::RunRequest& r, softcut::OutputBudget*, const softcut::Watchdog*) {
          CHECK(r.scenario == req.scenario);
          return std::make_unique<CppScript>(&log, dir / "ignored", 3);
        });
    CHECK(out.name == "cantilever");
    CHECK(out.out_dir == fs::canonical(dir / "out"));
    CHECK(log.confined == out.out_dir);  // confined to the folder made, not the spec's
    CHECK(log.starts == 1);
    CHECK(log.frame_at_start == 0);
    CHECK(log.frames == 3);
    CHECK(out.result.frames == 3);  // frames 0 .. 2 of 10, then the script stopped it
    CHECK(out.result.reason == softcut::sim::ExitReason::stopped);
    CHECK(log.checks == 1);
    REQUIRE(out.expectations.size() == 2);
    CHECK(out.expectations[0].name == "sags");
    CHECK(out.expectations[0].ok);
    CHECK(out.expectations[1].name == "asked");
    CHECK_FALSE(out.expectations[1].ok);
    CHECK(out.expectations[1].message == "expectation 1 asked at t = 0.100000");
    const std::string summary = slurp(out.out_dir / "summary.json");
    CHECK(contains(summary, "\"description\": \"a bar sags\""));
    CHECK(contains(summary, "\"exit_reason\": \"stopped\""));
    CHECK(fs::exists(out.out_dir / "displacements.csv"));
    CHECK_FALSE(fs::exists(dir / "ignored"));
  }

  TEST_CASE("the main chunk may not write a file: no output folder exists yet, whatever --out says") {
    const fs::path file = write_scenario("runner_early_write", std::string(kBoxHead) + R"(
local h = io.open("early.txt", "w")
return s
)");
    const std::string err = scenario_error(file);
    CHECK(contains(err, "scenario.lua:8: io.open: 'early.txt': the script's main chunk may not write files"));
    CHECK_FALSE(fs::exists(file.parent_path() / "early.txt"));
    CHECK_FALSE(fs::exists(file.parent_path() / "out" / "early.txt"));
  }

  TEST_CASE("a scenario's description reaches summary.json printable and bounded, whatever the script puts there") {
    softcut::app::RunOutcome out;
    const fs::path file = write_scenario("runner_description", std::string(kBoxHead) + R"(
s.description = "lesion \27[31m\0" .. ("x"):rep(10 * 1024 * 1024)
return s
)");
    REQUIRE(scenario_error(file, &out) == "");
    const std::string d = softcut::test::read_json(out.out_dir / "summary.json")["scenario"]["description"];
    CHECK(d.starts_with("lesion \\x1B[31m\\x00xxx"));
    CHECK(d.ends_with("..."));
    CHECK(d.size() <= 2100);
    CHECK(fs::file_size(out.out_dir / "summary.json") < 20000);
  }

  TEST_CASE("a scenario's params reach summary.json printable and bounded - names must be typeable after --set") {
    softcut::app::RunOutcome out;
    const fs::path file = write_scenario("runner_params_bound",
        "local P = softcut.params{ note = \"a\\27[2J\\0\" .. (\"y\"):rep(10 * 1024 * 1024), force = 1 }\n" +
            std::string(kBoxHead) + "return s\n");
    REQUIRE(scenario_error(file, &out) == "");
    const auto params = softcut::test::read_json(out.out_dir / "summary.json")["params"];
    CHECK(params["force"] == "1");
    const std::string note = params["note"];
    CHECK(note.starts_with("a\\x1B[2J\\x00yyy"));
    CHECK(note.ends_with("..."));
    CHECK(note.size() <= 2100);
    CHECK(fs::file_size(out.out_dir / "summary.json") < 20000);

    const fs::path spaced = write_scenario("runner_params_name", "local P = softcut.params{ [\"a b\"] = 1 }\n" +
                                                                     std::string(kBoxHead) + "return s\n");
    CHECK(contains(scenario_error(spaced), "scenario.lua:1: params: parameter name 'a b': use at most 64 letters"));
    const fs::path many = write_scenario("runner_params_many",
        "local d = {} for i = 1, 1001 do d['p' .. i] = i end\nlocal P = softcut.params(d)\n" +
            std::string(kBoxHead) + "return s\n");
    CHECK(contains(scenario_error(many), "scenario.lua:2: params: at most 1000 parameters"));
  }
}

TEST_SUITE("app/scenario_run") {
  TEST_CASE("a mesh of implausible size is a warning with its code in the outcome and summary.json") {
    // The head's box in millimetres, read as metres: 100 m long.
    std::string head = kBoxHead;
    head.replace(head.find("max = {0.1, 0.04, 0.04}"), 23, "max = {100, 40, 40}");
    head.replace(head.find("max = {0, 0.04, 0.04}"), 21, "max = {0, 40, 40}");
    head.replace(head.find("min = {0.1, 0, 0}, max = {0.1, 0.04, 0.04}"), 42, "min = {100, 0, 0}, max = {100, 40, 40}");
    const fs::path f = write_scenario("runner_mm", head + "s:output{ log = tip }\nreturn s\n");
    softcut::app::RunOutcome out;
    REQUIRE(scenario_error(f, &out) == "");
    const auto w = std::find_if(out.warnings.begin(), out.warnings.end(),
                                [](const std::string& x) { return softcut::warning_code(x) == "implausible_size"; });
    REQUIRE(w != out.warnings.end());
    CHECK(contains(*w, "scenario.lua:3: mesh (generator box (4 x 2 x 2 cells)): the body is 100 m across"));
    const auto summary = softcut::test::read_json(out.out_dir / "summary.json");
    bool found = false;
    for (const auto& x : summary.at("warnings")) found = found || softcut::warning_code(x.get<std::string>()) == "implausible_size";
    CHECK(found);
    // The same box in metres: no such warning.
    REQUIRE(scenario_error(write_scenario("runner_m", std::string(kBoxHead) + "s:output{ log = tip }\nreturn s\n"), &out) == "");
    CHECK(std::none_of(out.warnings.begin(), out.warnings.end(),
                       [](const std::string& x) { return softcut::warning_code(x) == "implausible_size"; }));
  }
}
