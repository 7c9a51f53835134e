#include "runtime.hpp"

#include <doctest/doctest.h>
#include <lua.hpp>

#include <cmath>
#include <fstream>

#include "lua_test_support.hpp"

namespace fs = std::filesystem;
using softcut::test::contains;
using softcut::test::lua_error;

TEST_SUITE("lua/runtime") {
  TEST_CASE("a syntax error names the chunk's file and line") {
    const std::string e = lua_error("local a = 1\nlocal b = = 2\n");
    CHECK(e.rfind("snippet.lua:2:", 0) == 0);
    CHECK(contains(e, "unexpected symbol"));
  }

  TEST_CASE("a runtime error carries file:line and a traceback") {
    const std::string e = lua_error("local function f(t)\n  return t.x.y\nend\nf({})\n");
    CHECK(e.rfind("snippet.lua:2:", 0) == 0);
    CHECK(contains(e, "attempt to index a nil value"));
    CHECK(contains(e, "stack traceback:"));
    CHECK(contains(e, "snippet.lua:4: in main chunk"));
  }

  TEST_CASE("run_file loads the chunk as @path") {
    const fs::path f = softcut::test::write_scenario("rt_file", "local x = nil\nreturn x.y\n", "bad.lua");
    softcut::lua::Runtime rt;
    try {
      rt.run_file(f, 0);
      FAIL("no error");
    } catch (const softcut::Error& e) {
      CHECK(std::string(e.what()).rfind(f.string() + ":2:", 0) == 0);
    }
  }

  TEST_CASE("a C++ exception in a binding becomes a Lua error, catchable by pcall") {
    softcut::lua::Runtime rt;
    lua_State* L = rt.state();
    lua_pushcfunction(L, [](lua_State* L) -> int {
      return softcut::lua::protect(L, []() -> int { softcut::fail("engine said no"); });
    });
    lua_setglobal(L, "thrower");
    rt.run_string("local ok, msg = pcall(thrower)\nassert(not ok)\nassert(msg == 'engine said no', msg)\n", "@t.lua", 0);
    try {
      rt.run_string("\nthrower()", "@t.lua", 0);
      FAIL("no error");
    } catch (const softcut::Error& e) {
      CHECK(std::string(e.what()).rfind("engine said no", 0) == 0);
      CHECK(contains(e.what(), "t.lua:2: in main chunk"));
    }
  }
}
