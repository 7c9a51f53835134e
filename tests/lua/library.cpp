#include "library.hpp"

#include <doctest/doctest.h>
#include <lua.hpp>

#include <cmath>
#include <fstream>

#include "lua_test_support.hpp"

namespace fs = std::filesystem;
using softcut::test::contains;
using softcut::test::lua_error;

TEST_SUITE("lua/library") {
  TEST_CASE("the embedded library is the global softcut and require-able") {
    CHECK(lua_error("assert(require('softcut') == softcut)\nassert(type(softcut.scenario) == 'function')") == "");
    CHECK(lua_error("assert(softcut.version:match('^%d+%.%d+'))") == "");
  }

  TEST_CASE("sandbox: require loads name.lua below the scenario folder, once, inside the budgets") {
    const fs::path dir = softcut::test::scratch_dir("rt_require");
    fs::create_directories(dir / "scn" / "lib");
    auto put = [](const fs::path& p, const std::string& text) { std::ofstream(p) << text; };
    put(dir / "scn" / "common.lua", "local name, file = ...\ncount = (count or 0) + 1\n"
                                    "return { name = name, file = file, twice = function(x) return 2 * x end }\n");
    put(dir / "scn" / "lib" / "organs.lua", "return { liver = require('common').twice(21) }\n");
    put(dir / "scn" / "nothing.lua", "x_set_by_nothing = true\n");
    put(dir / "scn" / "broken.lua", "return {\n");
    put(dir / "scn" / "fails.lua", "loads = (loads or 0) + 1\nerror('module says no')\n");
    put(dir / "scn" / "spin.lua", "while true do end\n");
    put(dir / "scn" / "cycle_a.lua", "return require('cycle_b')\n");
    put(dir / "scn" / "cycle_b.lua", "return require('cycle_a')\n");
    put(dir / "outside.lua", "return 'outside'\n");
    fs::create_symlink(dir / "outside.lua", dir / "scn" / "linked.lua");
    softcut::lua::SandboxOptions opt;
    opt.read_dir = dir / "scn";
    CHECK(lua_error("local c = require('common')\n"
                    "assert(c.name == 'common' and c.file:match('scn/common.lua$'), c.file)\n"
                    "assert(require('lib.organs').liver == 42)\n"
                    "assert(require('common') == c and count == 1, 'loaded once')\n"
                    "assert(require('nothing') == true and x_set_by_nothing)\n"
                    "assert(require('softcut') == softcut)",
                    opt) == "");
    // Errors name the module's file and line, or what to do.
    CHECK(contains(lua_error("require('broken')", opt), "broken.lua:2:"));
    CHECK(lua_error("assert(not pcall(require, 'fails'))\nassert(not pcall(require, 'fails'))\n"
                    "assert(loads == 2, 'a failed module is tried again')", opt) == "");
    const std::string missing = lua_error("require('absent')", opt);
    CHECK(missing.rfind("snippet.lua:1: require: no module 'absent'", 0) == 0);
    CHECK(contains(missing, "absent.lua below the scenario's folder"));
    for (const char* bad : {"../outside", "/etc/passwd", "lib/organs", "lib..organs", ".common", "common.", "1x", ""}) {
      CAPTURE(bad);
      CHECK(contains(lua_error(softcut::cat("require('", bad, "')"), opt), "is not a module name"));
    }
    CHECK(contains(lua_error("require('linked')", opt), "symbolic link"));
    CHECK(contains(lua_error("require('cycle_a')", opt), "module 'cycle_a' requires itself"));
    // The module's work is the script's: an endless loop in it ends at the budget, uncatchably.
    softcut::lua::SandboxOptions tight = opt;
    tight.instruction_budget = 2'000'000;
    CHECK(contains(lua_error("pcall(require, 'spin')\nlocal x = 1", tight), "instruction budget of 2000000"));
    // Reading and parsing count too: a big module that returns false is read again by every require.
    put(dir / "scn" / "big.lua", "#!/usr/bin/env lua\n" + std::string(100000, '-') + "\nreturn false\n");
    CHECK(lua_error("assert(require('big') == false)", tight) == "");  // a shebang line is a comment
    CHECK(contains(lua_error("for i = 1, 1000 do require('big') end", tight), "instruction budget of 2000000"));
    // Trusted runs find the same file first, through package.path.
    softcut::lua::SandboxOptions trusted = opt;
    trusted.trusted = true;
    CHECK(lua_error("assert(require('lib.organs').liver == 42)", trusted) == "");
  }
}
