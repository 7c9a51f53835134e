// The Lua sandbox's budgets end hostile or runaway scripts with a clear
// softcut::Error (never a crash, an OOM kill or a hang), and a scenario that
// asks for an absurd number of frames is refused before the frame loop.
#include <doctest/doctest.h>

#include <csignal>
#include <string>

#include "hardening_support.hpp"
#include "runtime.hpp"
#include "scenario_runner.hpp"

namespace fs = std::filesystem;
using softcut::hardening::contains;
using softcut::hardening::error_of;

namespace {

softcut::lua::SandboxOptions tight() {
  softcut::lua::SandboxOptions o;
  o.memory_budget = 32u << 20;
  o.instruction_budget = 20'000'000;
  return o;
}

// Runs `code` as the file <scratch>/bomb.lua, the way a scenario file runs.
std::string run_snippet(const std::string& code, const softcut::lua::SandboxOptions& opt = tight()) {
  const fs::path file = softcut::test::scratch_dir("hardening_lua_snippet") / "bomb.lua";
  softcut::hardening::put_file(file, code);
  return error_of([&] {
    softcut::lua::Runtime rt(opt);
    rt.run_file(file, 0);
  });
}

fs::path write_scenario(const std::string& name, const std::string& text) {
  const fs::path dir = softcut::test::scratch_dir(name);
  softcut::hardening::put_file(dir / "scenario.lua", text);
  return dir / "scenario.lua";
}

const char* kBox = R"(
local s = softcut.scenario{ duration = DURATION, fps = 30 }
s:mesh{ generate = "box", options = { min = {0, 0, 0}, max = {0.1, 0.04, 0.04}, nx = 2, ny = 1, nz = 1 } }
s:material{ tissue = "liver" }
s:fix{ nodes = softcut.select.box{ min = {0, 0, 0}, max = {0, 0.04, 0.04} } }
return s
)";

std::string box_scenario(const std::string& duration) {
  std::string s = kBox;
  s.replace(s.find("DURATION"), 8, duration);
  return s;
}

}  // namespace

TEST_SUITE("hardening/lua_limits") {
  TEST_CASE("a huge table ends at the memory budget with a clear message") {
    const std::string msg = run_snippet("local t = {} for i = 1, 1e9 do t[i] = i end");
    INFO(msg);
    CHECK(contains(msg, "memory budget"));
    CHECK(contains(msg, "bomb.lua"));
  }

  TEST_CASE("a deeply nested table ends at a budget with a clear message") {
    const std::string msg = run_snippet("local t = {} for i = 1, 1e9 do t = { t, i } end");
    INFO(msg);
    CHECK((contains(msg, "memory budget") || contains(msg, "instruction budget")));
    CHECK(contains(msg, "bomb.lua"));
  }

  TEST_CASE("deep nesting in the source is a syntax error, not a stack overflow") {
    const std::string deep = "return " + std::string(100000, '{') + std::string(100000, '}');
    const std::string msg = run_snippet(deep);
    INFO(msg.substr(0, 300));
    CHECK(!msg.empty());
    CHECK(contains(msg, "bomb.lua"));
    const std::string calls = "local x = " + std::string(100000, '(') + "1" + std::string(100000, ')');
    CHECK(!run_snippet(calls).empty());
  }

  TEST_CASE("a huge string and a string-doubling loop end at the memory budget") {
    const std::string rep = run_snippet("local s = string.rep('x', 1 << 30)");
    INFO(rep);
    CHECK(contains(rep, "memory budget"));
    CHECK(contains(run_snippet("local s = 'x' while true do s = s .. s end"), "memory budget"));
    CHECK(contains(run_snippet("local t = {} for i = 1, 1e9 do t[#t + 1] = tostring(i) .. 'padding' end"),
                   "memory budget"));
  }

  TEST_CASE("an endless loop and endless recursion end with a clear message") {
    const std::string loop = run_snippet("while true do end");
    INFO(loop);
    CHECK(contains(loop, "instruction budget"));
    CHECK(contains(loop, "bomb.lua:1"));
    const std::string rec = run_snippet("local function f(n) return 1 + f(n + 1) end f(1)");
    INFO(rec);
    CHECK(!rec.empty());
    CHECK(contains(rec, "bomb.lua"));
  }

  TEST_CASE("the scenario loader applies the same budgets and names the scenario file") {
    softcut::lua::RunRequest req;
    req.scenario = write_scenario("hardening_lua_loader", "local t = {} for i = 1, 1e9 do t[i] = {} end\n");
    req.render = false;
    req.memory_budget = 32u << 20;
    const std::string msg = error_of([&] { softcut::lua::load_scenario_spec(req); });
    INFO(msg);
    CHECK(contains(msg, "memory budget"));
    CHECK(contains(msg, "scenario.lua"));
  }

  TEST_CASE("a scenario asking for 1e9 frames is refused before the frame loop") {
    softcut::lua::RunRequest req;
    req.scenario = write_scenario("hardening_frames", box_scenario("1e9 / 30"));
    req.out_dir = req.scenario.parent_path() / "out";
    req.render = false;
    const std::string msg = error_of([&] { softcut::lua::run_scenario(req); });
    INFO(msg);
    CHECK(contains(msg, "too many"));
    CHECK(contains(msg, "scenario.lua"));
    CHECK(!fs::exists(req.out_dir / "displacements.csv"));
  }

  TEST_CASE("a duration that overflows the frame counter is refused") {
    softcut::lua::RunRequest req;
    req.scenario = write_scenario("hardening_frames_inf", box_scenario("1e300"));
    req.out_dir = req.scenario.parent_path() / "out";
    req.render = false;
    const std::string msg = error_of([&] { softcut::lua::run_scenario(req); });
    INFO(msg);
    CHECK(contains(msg, "too many"));
  }
}
