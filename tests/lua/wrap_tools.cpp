// lua/wrap_tools.cpp: ramps and paths built in Lua, evaluated by the engine;
// tissue presets.
#include <doctest/doctest.h>

#include "lua_test_support.hpp"
#include "sim/tissue.hpp"

using softcut::test::contains;
using softcut::test::lua_error;

TEST_SUITE("lua/wrap_tools") {
  TEST_CASE("ramps evaluate to their closed forms") {
    CHECK(lua_error(R"(
local R = softcut.ramp
local function near(a, b) assert(math.abs(a - b) < 1e-15, a .. " vs " .. b) end
near(R.constant(0.7):at(123), 0.7)
local l = R.linear{ t0 = 1, t1 = 3, from = 2, to = 6 }
near(l:at(0), 2); near(l:at(2), 4); near(l:at(5), 6)
local s = R.smoothstep{ t1 = 2 }
for _, t in ipairs({0.3, 1.0, 1.7}) do local x = t / 2; near(s:at(t), 3 * x * x - 2 * x * x * x) end
local k = R.keyframes{ times = {0, 1, 3}, values = {0, 2, -2} }
near(k:at(-1), 0); near(k:at(0.5), 1); near(k:at(2), 0); near(k:at(9), -2)
local w = R.sine{ amplitude = 2, frequency = 0.5, offset = 1, t0 = 1 }
near(w:at(0.5), 1); near(w:at(1.5), 1 + 2 * math.sin(math.pi * 0.5))
)") == "");
  }

  TEST_CASE("paths evaluate to their closed forms") {
    CHECK(lua_error(R"(
local P = softcut.path
local function near(a, b) for i = 1, 3 do assert(math.abs(a[i] - b[i]) < 1e-15, i .. ": " .. a[i] .. " vs " .. b[i]) end end
near(P.fixed{ 1, 2, 3 }:at(7), {1, 2, 3})
local p = P.polyline{ times = {0, 1, 3}, points = {{0, 0, 0}, {1, 0, 0}, {1, 2, 0}} }
near(p:at(0.5), {0.5, 0, 0}); near(p:at(2), {1, 1, 0}); near(p:at(4), {1, 2, 0})
local c = P.catmull_rom{ times = {0, 1, 2}, points = {{0, 0, 0}, {1, 1, 0}, {2, 0, 0}} }
near(c:at(1), {1, 1, 0})
local a = P.arc{ center = {0, 0, 1}, start = {2, 0, 1}, sweep = math.pi / 2, t1 = 1 }
near(a:at(1), {0, 2, 1})
)") == "");
  }

  TEST_CASE("bad ramps and paths are errors at the constructing line") {
    CHECK(lua_error("\nlocal r = softcut.ramp.linear{ t0 = 2, t1 = 1 }") == "snippet.lua:2: ramp.linear: t1 = 1 must be > t0 = 2");
    CHECK(lua_error("softcut.ramp.keyframes{ times = {0, 1}, values = {1} }") ==
          "snippet.lua:1: ramp.keyframes: 2 times but 1 values (give one value per time)");
    CHECK(contains(lua_error("softcut.ramp.keyframes{ times = {0, 2, 1}, values = {1, 2, 3} }"),
                   "snippet.lua:1: ramp.keyframes: keyframe times must increase"));
    CHECK(contains(lua_error("softcut.path.polyline{ times = {0, 0}, points = {{0, 0, 0}, {1, 0, 0}} }"),
                   "snippet.lua:1: path.polyline"));
    CHECK(contains(lua_error("softcut.path.arc{ center = {0, 0, 0}, axis = {0, 0, 0}, start = {1, 0, 0}, sweep = 1, t1 = 1 }"),
                   "snippet.lua:1: path.arc"));
    CHECK(lua_error("softcut.ramp.sine{ amplitude = 1, frequency = -1 }") ==
          "snippet.lua:1: ramp.sine: field 'frequency' = -1 Hz is out of range: must be >= 0 Hz");
  }

  TEST_CASE("softcut.tissues mirrors the engine's presets") {
    softcut::lua::Runtime rt;
    for (const auto& p : softcut::sim::tissue_presets()) {
      CAPTURE(p.name);
      rt.run_string(softcut::cat("local t = softcut.tissues['", p.name, "']\nassert(t.young == ", p.material.young,
                                 " and t.poisson == ", p.material.poisson, " and #t.source > 0)"),
                    "=t", 0);
    }
  }

  TEST_CASE("vector helpers") {
    CHECK(lua_error(R"(
local V = softcut.vec
local a = V.add({1, 2, 3}, V.scale({1, 1, 1}, 2))
assert(a[1] == 3 and a[2] == 4 and a[3] == 5)
assert(V.dot({1, 2, 3}, {4, 5, 6}) == 32)
local c = V.cross({1, 0, 0}, {0, 1, 0}); assert(c[3] == 1 and c[1] == 0)
assert(V.length({3, 4, 0}) == 5)
local l = V.lerp({0, 0, 0}, {2, 4, 6}, 0.5); assert(l[2] == 2)
local d = V.sub({1, 1, 1}, {1, 2, 3}); assert(d[3] == -2)
)") == "");
    CHECK(lua_error("softcut.vec.add({1, 2}, {1, 2, 3})") ==
          "snippet.lua:1: vec.add: field 'a' must be a 3-vector {x, y, z} of finite numbers, got table");
  }
}
