// lua/wrap_frame.cpp: what on_frame can read and change.
#include <doctest/doctest.h>

#include <fstream>
#include <sstream>

#include "lua_test_support.hpp"

using softcut::test::contains;
using softcut::test::kBoxHead;
using softcut::test::scenario_error;
using softcut::test::write_scenario;

namespace {

std::string run_box(const std::string& name, const std::string& tail, softcut::app::RunOutcome* out = nullptr) {
  const auto f = write_scenario(name, std::string(kBoxHead) + tail + "\nreturn s\n");
  return scenario_error(f, out);
}

// Value of `column` (3..5 = ux..uz) for (frame, node) in a displacements.csv.
double csv_value(const std::filesystem::path& csv, int frame, int node, int column) {
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream ss(line);
    double v[6];
    for (double& x : v) ss >> x;
    if (int(v[0]) == frame && int(v[2]) == node) return v[column];
  }
  return NAN;
}

}  // namespace

TEST_SUITE("lua/wrap_frame") {
  TEST_CASE("displacement and position agree with the log and the rest mesh") {
    softcut::app::RunOutcome out;
    const std::string e = run_box("frame_read", R"(
s:load{ name = "pull", nodes = tip, force = {0, 0, -0.05} }
s:output{ log = softcut.select.all() }
local node = s:select(tip)[1]
s:on_frame(function(f)
  local u, x = f:displacement(node), f:position(node)
  assert(math.abs(x[1] - (0.1 + u[1])) < 1e-15)
  if f.frame == 3 then
    local log = io.open("seen.txt", "w")
    log:write(("%d %.17g"):format(node, u[3]))
    log:close()
  end
  assert(f:max_displacement(tip) >= math.abs(f:mean_displacement(tip)[3]) - 1e-15)
end)
)", &out);
    REQUIRE(e == "");
    std::ifstream seen(out.out_dir / "seen.txt");
    int node = -1;
    double uz = 0;
    seen >> node >> uz;
    CHECK(uz < 0);
    CHECK(uz == doctest::Approx(csv_value(out.out_dir / "displacements.csv", 3, node, 5)).epsilon(1e-8));  // CSV: %.9e
  }

  TEST_CASE("set_load scales and switches a load from the next frame") {
    softcut::app::RunOutcome out;
    const std::string e = run_box("frame_load", R"(
s:load{ name = "pull", nodes = tip, force = {0, 0, -0.05} }
local base
s:on_frame(function(f)
  local uz = f:mean_displacement(tip)[3]
  if f.frame == 0 then base = uz; f:set_load("pull", { scale = 2 }) end
  if f.frame == 1 then assert(math.abs(uz - 2 * base) < 1e-12 * math.abs(base), uz .. " " .. base); f:set_load("pull", { enabled = false }) end
  if f.frame == 2 then assert(math.abs(uz) < 1e-12 * math.abs(base), uz) end
end)
)", &out);
    CHECK(e == "");
    CHECK(out.result.frames == 6);
  }

  TEST_CASE("stop ends the run after the frame - the summary says stopped") {
    softcut::app::RunOutcome out;
    CHECK(run_box("frame_stop", "s:on_frame(function(f) if f.frame == 2 then f:stop() end end)", &out) == "");
    CHECK(out.result.frames == 3);
    CHECK(out.result.reason == softcut::sim::ExitReason::stopped);
  }

  TEST_CASE("tools: read state, move, switch off - unknown names suggested") {
    const std::string e = run_box("frame_tool", R"(
s:probe{ name = "tip", path = {0.12, 0.02, 0.02}, radius = 0.005, force = 0.01 }
s:on_frame(function(f)
  local t = f:tool("tip")
  if f.frame == 0 then assert(t.tip[1] == 0.12); f:move_tool("tip", {0.13, 0.02, 0.02}) end
  if f.frame == 1 then assert(t.tip[1] == 0.13, t.tip[1]); f:move_tool("tip", nil); f:enable_tool("tip", false) end
  if f.frame == 2 then assert(t.tip[1] == 0.12); assert(not t.engaged) end
  if f.frame == 3 then f:tool("tpi") end
end)
)");
    CHECK(contains(e, "scenario.lua:14: tool: no tool 'tpi' (did you mean 'tip'?)"));
  }

  TEST_CASE("a frame kept past its call fails cleanly - bad node ids are caught") {
    CHECK(contains(run_box("frame_keep", R"(
local kept
s:on_frame(function(f) if f.frame == 0 then kept = f else kept:displacement(0) end end)
)"), "this frame is over"));
    CHECK(contains(run_box("frame_edit", "s:on_frame(function(f) s:fix{ nodes = tip } end)"),
                   "scenario.lua:7: fix: the scenario is already running; change it from on_frame with f:set_load"));
    CHECK(contains(run_box("frame_node", "s:on_frame(function(f) f:displacement(10000) end)"),
                   "scenario.lua:7: displacement: node 10000 out of range (the mesh has 45 nodes, ids 0..44)"));
    // A selection caches its ids in a field the script can overwrite: every
    // binding that reads ids checks them (max_displacement read out of range).
    for (const std::string call : {"f:max_displacement(fake)", "f:mean_displacement(fake)"}) {
      CAPTURE(call);
      const std::string e = run_box("frame_fake_ids", "local fake = softcut.select.all()\nfake._ids = { 44, 123456789 }\n"
                                                      "s:on_frame(function(f) local u = " + call + " end)");
      INFO(e);
      CHECK(contains(e, "scenario.lua:9: " + call.substr(2, call.find('(') - 2) +
                            ": node 123456789 out of range (the mesh has 45 nodes now)"));
    }
    // An expectation's selection is evaluated by the engine from what it
    // selects (sim/expectations.hpp), never from the cached ids: the forged
    // id is not used, the run measures all 45 nodes and passes.
    softcut::app::RunOutcome out;
    const std::string e = run_box("frame_fake_expect", "local fake = softcut.select.all()\nfake._ids = { -1 }\n"
                                                       "s:expect{ name = 'e', at = 0, nodes = fake, component = 'x', min = 0 }",
                                  &out);
    CHECK(e == "");
    REQUIRE(out.expectations.size() == 1);
    CHECK(contains(out.expectations[0].message, "mean ux of 45 nodes at t = "));
  }

  TEST_CASE("an error in on_frame ends the run with a traceback - outputs are finished and marked") {
    const auto f = write_scenario("frame_error", std::string(kBoxHead) +
                                                    "s:on_frame(function(f)\n  if f.frame == 2 then error('boom') end\nend)\nreturn s\n");
    const std::string e = scenario_error(f);
    CHECK(e.rfind(f.string() + ":8: boom", 0) == 0);
    CHECK(contains(e, "stack traceback:"));
    std::ifstream summary(f.parent_path() / "out" / "summary.json");
    std::stringstream ss;
    ss << summary.rdbuf();
    CHECK(contains(ss.str(), "\"exit_reason\": \"error\""));
    CHECK(std::filesystem::exists(f.parent_path() / "out" / "displacements.csv"));
  }
}
