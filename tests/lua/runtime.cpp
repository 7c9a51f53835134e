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

  TEST_CASE("an error value that is not a string is named as such, with the line that raised it") {
    const std::string t = lua_error("local x = 1\nerror({})\n");
    CHECK(t.rfind("snippet.lua:2: error raised with table as its message; pass a string", 0) == 0);
    CHECK(contains(t, "__tostring"));
    CHECK_FALSE(contains(t, "table: 0x"));
    CHECK(lua_error("\nerror()").rfind("snippet.lua:2: error raised with nil as its message", 0) == 0);
    CHECK(lua_error("\n\nerror(42)").rfind("snippet.lua:3: 42", 0) == 0);
    // A table with __tostring says what it says.
    CHECK(lua_error("error(setmetatable({}, { __tostring = function() return 'mine' end }))").rfind("snippet.lua:1: mine", 0) == 0);
  }

  TEST_CASE("tracebacks show the script's frames, not softcut's own or C functions") {
    // Raised in the script's __len, called by the library's argument check.
    const std::string e = lua_error("local bad = setmetatable({}, { __len = function() error('len') end })\n"
                                    "local function f() local n = softcut.vec.length(bad) return n end\nf()\n");
    INFO(e);
    CHECK(e.rfind("snippet.lua:1: len\nstack traceback:\n\tsnippet.lua:1: in function <snippet.lua:1>", 0) == 0);
    CHECK(contains(e, "\n\tsnippet.lua:2: in local 'f'"));
    CHECK(contains(e, "\n\tsnippet.lua:3: in main chunk"));
    CHECK_FALSE(contains(e, "softcut/"));
    // Raised in a comparator that table.sort (C) calls.
    const std::string c = lua_error("\ntable.sort({3, 2, 1}, function(a, b) error('cmp') end)\n");
    INFO(c);
    CHECK(contains(c, "snippet.lua:2: in main chunk"));
    CHECK_FALSE(contains(c, "[C]"));
    // A deep recursion: the first frames, then "...".
    const std::string deep = lua_error("local function f(n) if n == 0 then error('bottom') end return 1 + f(n - 1) end\nf(500)\n");
    CHECK(contains(deep, "snippet.lua:1: bottom"));
    CHECK(contains(deep, "\n\t..."));
  }

  TEST_CASE("errors raised inside wrapped C functions carry the script's line and the function's name") {
    CHECK(lua_error("\nlocal x = string.rep()").rfind("snippet.lua:2: bad argument #1 to 'string.rep'", 0) == 0);
    CHECK(lua_error("\nlocal x = ('a'):find('%')").rfind("snippet.lua:2: malformed pattern", 0) == 0);
    CHECK(lua_error("\nlocal f = load(string.dump(function() end))").rfind(
              "snippet.lua:2: load: binary chunks are refused in the sandbox", 0) == 0);
    const std::string rep = lua_error("\n\nlocal x = ('x'):rep(2^40)");
    CHECK(rep.rfind("snippet.lua:3: string.rep: memory budget of 512 MiB exceeded: the result would take 1.1e+12 bytes", 0) == 0);
    // Still catchable, still sticky when fatal.
    CHECK(lua_error("local ok, e = pcall(string.rep)\nassert(not ok and e:find('snippet.lua:1: bad argument'), e)") ==
          "");
  }
}
