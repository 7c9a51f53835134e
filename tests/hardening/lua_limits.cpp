// The Lua sandbox's budgets end hostile or runaway scripts with a clear
// softcut::Error (never a crash, an OOM kill or a hang), and a scenario that
// asks for an absurd number of frames is refused before the frame loop.
#include <doctest/doctest.h>

#include <csignal>
#include <string>

#include "hardening_support.hpp"
#include "runtime.hpp"
#include "app/scenario_run.hpp"

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

  // Finding 5: Lua's pattern matcher runs in C, where the count hook never
  // fires. Each case runs in a child with a 5 s CPU limit, so a regression
  // (hours of backtracking) fails the test instead of hanging ctest.
  TEST_CASE("a backtracking string pattern ends at once with a clear error") {
    const int rc = softcut::hardening::in_child(RLIMIT_CPU, 5, [] {
      const std::string msg = run_snippet("local s = ('a'):rep(40)\nlocal m = s:match(('a*'):rep(40) .. 'b')");
      INFO(msg);
      CHECK(contains(msg, "bomb.lua:2: string.match: pattern 'a*a*a*"));
      CHECK(contains(msg, "with 40 repetition items over a 40-byte subject"));
      CHECK(contains(msg, "simplify the pattern or shorten the subject"));
      return (contains(msg, "string.match") && contains(msg, "40 repetition items")) ? 0 : 1;
    });
    CHECK(rc == 0);
  }

  TEST_CASE("every pattern function and route to it is guarded") {
    // string.* and s:method(...), the string metatable's __index, unanchored
    // searches, gmatch's whole iteration, gsub; captures, back-references,
    // %b and %f between the repetitions open no loophole.
    const char* calls[] = {
        "string.find(('a'):rep(30), ('a-'):rep(30) .. 'b')",
        "local s = ('a'):rep(30) return s:find(('a*'):rep(30) .. 'b')",
        "return getmetatable('').__index.match(('a'):rep(30), ('.*'):rep(30) .. '$b')",
        "for w in (('a'):rep(30)):gmatch(('a?'):rep(30) .. ('a'):rep(30) .. 'b') do end",
        "return (('x'):rep(25)):gsub(('x*'):rep(25) .. 'y', '')",
        "return (('ab'):rep(20)):match('(a*)' .. ('[ab]*%1()%f[%w]'):rep(12) .. 'c')",
        "return (('(a)'):rep(20)):find('^' .. ('.-%b()'):rep(16) .. 'z')",
        "local f = string.match return f(('0'):rep(48), ('%d*'):rep(24) .. '%a')",
        "return string.find(('a'):rep(5e6), ('a'):rep(1e6) .. 'b', 1, true)",
    };
    for (const char* code : calls) {
      const int rc = softcut::hardening::in_child(RLIMIT_CPU, 5, [&] {
        const std::string msg = run_snippet(code);
        INFO(code);
        INFO(msg);
        CHECK(contains(msg, "over the sandbox budget"));
        CHECK(contains(msg, "bomb.lua:1: string."));
        return contains(msg, "over the sandbox budget") ? 0 : 1;
      });
      INFO(code);
      CHECK(rc == 0);
    }
  }

  TEST_CASE("pattern work is charged: a loop of allowed searches ends at the budget") {
    // Each search is allowed (~1e6 steps, a few ms) but charged its bound:
    // uncharged, the loop would run budget / (5 instructions per iteration)
    // of them, hours.
    const int rc = softcut::hardening::in_child(RLIMIT_CPU, 5, [] {
      const std::string msg = run_snippet("local s = ('a'):rep(150)\nwhile true do s:match('^a*a*a*b') end");
      INFO(msg);
      CHECK(contains(msg, "bomb.lua:2"));
      CHECK((contains(msg, "instruction budget") || contains(msg, "over the sandbox budget")));
      return contains(msg, "budget") ? 0 : 1;
    });
    CHECK(rc == 0);
  }

  TEST_CASE("ordinary pattern uses still work in the sandbox") {
    const std::string msg = run_snippet(R"(
local function eq(a, b) if a ~= b then error(tostring(a) .. ' ~= ' .. tostring(b), 2) end end
eq((('Hello ${name}, frame ${n} of ${n}.'):gsub('%${(%w+)}', { name = 'liver', n = '7' })), 'Hello liver, frame 7 of 7.')
eq(string.find('a.b*c(d', '*c(', 1, true), 4)
local fields = {}
for f in ('node,12,0.25,-3e-4,,tip'):gmatch('([^,]*)') do fields[#fields + 1] = f end
eq(fields[1], 'node') eq(fields[4], '-3e-4') eq(fields[6], 'tip')
eq(('f(a, g(b, c), d) + 1'):match('%b()'), '(a, g(b, c), d)')
local k, v = ('  stiffness = 3.5e3  # Pa'):match('^%s*([%w_]+)%s*=%s*(.-)%s*#')
eq(k, 'stiffness') eq(v, '3.5e3')
eq(('say "hi" and "bye"'):match('(["\'])(.-)%1'), '"')
eq(select(2, ('the cut, the tool'):gsub('%f[%w]the%f[%W]', 'a')), 2)
local line = ('x'):rep(200) .. ' = ' .. ('y'):rep(200)
eq(#line:match('^(%w+)%s*=%s*(.*)$'), 200)
local csv = {} for i = 1, 2000 do csv[#csv + 1] = ('%d,%g,%g,%g'):format(i, i * 0.5, i * 0.25, -i) end
local text, sum = table.concat(csv, '\n'), 0
for a, b, c, d in text:gmatch('(%d+),([^,]+),([^,]+),([^\n]+)') do sum = sum + tonumber(d) end
eq(sum, -2001000)
eq(select(2, text:gsub('\n', '\n')), 1999)
eq(('abcabc'):find('b', math.mininteger), 2) eq(('abcabc'):find('b', -3), 5) eq(('abc'):find('b', math.maxinteger), nil)
eq(('abcabc'):match('(b)c', 3), 'b') eq(#('a'):rep(5e5):match('^a*', 2), 499999)
)");
    CHECK(msg == "");
  }

  TEST_CASE("the scenario loader applies the same budgets and names the scenario file") {
    softcut::app::RunRequest req;
    req.scenario = write_scenario("hardening_lua_loader", "local t = {} for i = 1, 1e9 do t[i] = {} end\n");
    req.render = false;
    req.memory_budget = 32u << 20;
    const std::string msg = error_of([&] { softcut::app::load_scenario_spec(req); });
    INFO(msg);
    CHECK(contains(msg, "memory budget"));
    CHECK(contains(msg, "scenario.lua"));
  }

  TEST_CASE("a scenario asking for 1e9 frames is refused before the frame loop") {
    softcut::app::RunRequest req;
    req.scenario = write_scenario("hardening_frames", box_scenario("1e9 / 30"));
    req.out_dir = req.scenario.parent_path() / "out";
    req.render = false;
    const std::string msg = error_of([&] { softcut::app::run_scenario(req); });
    INFO(msg);
    CHECK(contains(msg, "too many"));
    CHECK(contains(msg, "scenario.lua"));
    CHECK(!fs::exists(req.out_dir / "displacements.csv"));
  }

  TEST_CASE("a duration that overflows the frame counter is refused") {
    softcut::app::RunRequest req;
    req.scenario = write_scenario("hardening_frames_inf", box_scenario("1e300"));
    req.out_dir = req.scenario.parent_path() / "out";
    req.render = false;
    const std::string msg = error_of([&] { softcut::app::run_scenario(req); });
    INFO(msg);
    CHECK(contains(msg, "too many"));
  }

  TEST_CASE("a scenario asking for a billion-tet mesh is refused before it is generated") {
    const char* requests[] = {
        R"(generate = "box", options = { nx = 1000, ny = 1000, nz = 300 })",
        R"(generate = "cylinder", options = { rings = 300, layers = 1000 })",
        R"(generate = "tube", options = { target_tets = 1e9 })",
        R"(generate = "ligament", options = { along = 1000, across = 1000, through = 100 })",
        R"(generate = "liver", options = { target_tets = 1e9 })",
        R"(generate = "kidney", options = { target_tets = 0, cell_size = 1e-5 })",
        R"(generate = "knee_ligament", options = { target_tets = 0, cell_size = 0.001, fine_radius = 1, fine_ratio = 0.06 })",
    };
    for (const std::string r : requests) {
      CAPTURE(r);
      const long long before = softcut::hardening::peak_rss_bytes();
      softcut::app::RunRequest req;
      req.scenario = write_scenario("hardening_huge_mesh", std::string("local s = softcut.scenario{ duration = 1, fps = 1 }\n") +
                                                                    "s:mesh{ " + r + " }\n");
      const std::string msg = error_of([&] { softcut::app::load_scenario_spec(req); });
      INFO(msg);
      CHECK(contains(msg, "scenario.lua:2"));
      CHECK(contains(msg, "over this run's limit of 2000000"));
      CHECK(contains(msg, "--max-tets"));
      CHECK(softcut::hardening::peak_rss_bytes() - before < (64ll << 20));
    }
  }

  TEST_CASE("a loop of mesh loads or of selections ends at the instruction budget") {
    // Native work is charged: uncharged, each loop would run for hours on a
    // budget of 2e7 instructions (a mesh load is ~40 instructions of Lua).
    const char* loops[] = {
        "for i = 1, 1e9 do\n  local s = softcut.scenario{ duration = 1, fps = 1 }\n"
        "  s:mesh{ generate = 'box', options = { nx = 30, ny = 30, nz = 30 } }\nend\n",
        "local s = softcut.scenario{ duration = 1, fps = 1 }\n"
        "s:mesh{ generate = 'box', options = { nx = 30, ny = 30, nz = 30 } }\n"
        "for i = 1, 1e9 do s:fix{ nodes = softcut.select.box{ min = {0, 0, 0}, max = {0.5, 1, 1} } } end\n",
    };
    for (const std::string code : loops) {
      CAPTURE(code);
      const int rc = softcut::hardening::in_child(RLIMIT_CPU, 60, [&] {
        softcut::app::RunRequest req;
        req.scenario = write_scenario("hardening_native_loop", code);
        req.instruction_budget = 20'000'000;
        const std::string msg = error_of([&] { softcut::app::load_scenario_spec(req); });
        INFO(msg);
        CHECK(contains(msg, "instruction budget of 20000000 instructions exceeded"));
        CHECK((contains(msg, "scenario.lua:3") || contains(msg, "scenario.lua:4")));
        return contains(msg, "instruction budget") ? 0 : 1;
      });
      CHECK(rc == 0);
    }
  }

  TEST_CASE("selections built in long loops or containing themselves: no stack overflow") {
    // Before: converting a 2e5-deep union recursed once per level and
    // overflowed the C++ stack (segfault). Chains are now spliced flat, so a
    // union of 2000 slabs selects exactly what one box does.
    const std::string head = "local s = softcut.scenario{ duration = 1, fps = 1 }\n"
                             "s:mesh{ generate = 'box', options = { nx = 20, ny = 2, nz = 2 } }\n";
    softcut::app::RunRequest req;
    req.scenario = write_scenario("hardening_long_union", head + R"(
local u = softcut.select.box{ min = {-1, -1, -1}, max = {0, 1, 1} }
for i = 1, 2000 do u = u + softcut.select.box{ min = {0, -1, -1}, max = {i / 4000, 1, 1} } end
local one = softcut.select.box{ min = {-1, -1, -1}, max = {0.5, 1, 1} }
local a, b = s:select(u), s:select(one)
assert(#a == #b and #a == 11 * 9, #a .. " vs " .. #b)
for k = 1, #a do assert(a[k] == b[k]) end
local t = softcut.select.all()
for i = 1, 2000 do t = t - softcut.select.box{ min = {0.5, -1, -1}, max = {1, 1, 1} } end
assert(#s:select(t) == 10 * 9)
s:fix{ nodes = u }
)");
    CHECK(error_of([&] { softcut::app::load_scenario_spec(req); }) == "");
    req.scenario = write_scenario("hardening_self_union", head + R"(
local u = softcut.select.all() + softcut.select.all()
u.children[2] = u
s:fix{ nodes = u }
)");
    const std::string msg = error_of([&] { softcut::app::load_scenario_spec(req); });
    INFO(msg);
    CHECK(contains(msg, "scenario.lua:4: selection: more than 100000 shapes and set operations"));
  }

  TEST_CASE("meshes a script keeps count against the memory budget - dropped ones are given back") {
    // Before: each mesh handle's arrays lived outside the Lua heap, so a
    // script keeping a 2M-tet mesh per on_frame call grew without bound.
    const std::string loop = "local keep = {}\nfor i = 1, 40 do\n  local s = softcut.scenario{ duration = 1, fps = 1 }\n"
                             "  s:mesh{ generate = 'box', options = { nx = 20, ny = 20, nz = 20 } }\n";
    softcut::app::RunRequest req;
    req.memory_budget = 16u << 20;
    req.instruction_budget = 1'000'000'000;
    req.scenario = write_scenario("hardening_kept_meshes", loop + "  keep[i] = s\nend\n");
    const std::string msg = error_of([&] { softcut::app::load_scenario_spec(req); });
    INFO(msg);
    CHECK(contains(msg, "scenario.lua:4: mesh: memory budget of 16 MiB exceeded: this mesh needs 2 MiB"));
    req.scenario = write_scenario("hardening_dropped_meshes", loop + "end\nreturn softcut.scenario{ duration = 1 }\n");
    const std::string dropped = error_of([&] { softcut::app::load_scenario_spec(req); });
    INFO(dropped);
    CHECK(!contains(dropped, "memory budget"));
    CHECK(contains(dropped, "no mesh"));  // the last scenario has none: the loop itself ran through
  }

  TEST_CASE("metamethods on the script's tables do not run while the engine reads them") {
    // Before: the engine read lists with luaL_len after the script had ended,
    // outside any protected call: a __len that raised an error aborted the
    // process (Lua panic), one returning maxinteger hung it.
    const std::string head = "local s = softcut.scenario{ duration = 1, fps = 1 }\n"
                             "s:mesh{ generate = 'box' }\n"
                             "local u = softcut.select.box{ min = {-1, -1, -1}, max = {0, 1, 1} } + softcut.select.box{ "
                             "min = {-1, -1, -1}, max = {0, 0.5, 1} }\n"
                             "s:fix{ nodes = u }\n";
    for (const std::string tail : {
             "setmetatable(u.children, { __len = function() error('boom') end })\n",
             "setmetatable(u.children, { __len = function() return math.maxinteger end })\n",
             "setmetatable(s._fixed, { __len = function() while true do end end })\n",
             "setmetatable(getmetatable(s), { __index = function() error('boom') end })\nreturn s\n",
         }) {
      CAPTURE(tail);
      softcut::app::RunRequest req;
      req.scenario = write_scenario("hardening_metamethods", head + tail);
      const std::string msg = error_of([&] { softcut::app::load_scenario_spec(req); });
      CHECK(msg == "");
    }
  }
}
