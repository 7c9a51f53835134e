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

  TEST_CASE("the embedded library is the global softcut and require-able") {
    CHECK(lua_error("assert(require('softcut') == softcut)\nassert(type(softcut.scenario) == 'function')") == "");
    CHECK(lua_error("assert(softcut.version:match('^%d+%.%d+'))") == "");
  }

  TEST_CASE("sandbox: process and native-code escapes are refused with a clear message") {
    for (const char* code : {"os.execute('true')", "io.popen('ls')", "package.loadlib('libc.so.6', 'system')",
                             "os.exit(1)", "os.getenv('HOME')", "os.remove('x')", "debug.sethook()", "dofile('x.lua')",
                             "loadfile('x.lua')"}) {
      CAPTURE(code);
      const std::string e = lua_error(code);
      CHECK(contains(e, "not available in the sandbox"));
      CHECK(contains(e, "--trust"));
      CHECK(e.rfind("snippet.lua:1:", 0) == 0);
    }
    const std::string e = lua_error("require('os')");
    CHECK(contains(e, "require: no module 'os'"));
  }

  TEST_CASE("sandbox: files only below the scenario folder (read) and the output folder (write)") {
    const fs::path dir = softcut::test::scratch_dir("rt_files");
    fs::create_directories(dir / "scn");
    fs::create_directories(dir / "out");
    std::ofstream(dir / "scn" / "data.txt") << "hello\n";
    std::ofstream(dir / "secret.txt") << "no\n";
    softcut::lua::SandboxOptions opt;
    opt.read_dir = dir / "scn";
    opt.write_dir = dir / "out";
    CHECK(lua_error("assert(io.open('data.txt'):read('l') == 'hello')", opt) == "");
    const std::string passwd = lua_error("io.open('/etc/passwd')", opt);
    CHECK(contains(passwd, "io.open: '/etc/passwd' is outside the scenario folder"));
    CHECK(contains(lua_error("io.open('../secret.txt')", opt), "outside the scenario folder"));
    CHECK(contains(lua_error("io.lines('/etc/passwd')", opt), "io.lines: '/etc/passwd' is outside"));
    CHECK(contains(lua_error("io.open('../scn/data.txt', 'w')", opt), "outside the output folder"));
    CHECK(lua_error("local f = io.open('log.txt', 'w'); f:write('x'); f:close()", opt) == "");
    CHECK(fs::exists(dir / "out" / "log.txt"));
    CHECK(contains(lua_error("io.open('" + (dir / "scn" / "x.txt").string() + "', 'a')", opt), "outside the output folder"));
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

  TEST_CASE("sandbox: binary chunks are refused, text chunks load") {
    CHECK(contains(lua_error("load(string.dump(function() return 1 end))"), "binary chunks are refused"));
    CHECK(lua_error("assert(load('return 1 + 1')() == 2)") == "");
    softcut::lua::SandboxOptions trusted;
    trusted.trusted = true;
    CHECK(lua_error("assert(load(string.dump(function() return 7 end))() == 7)", trusted) == "");
    CHECK(lua_error("assert(type(os.getenv) == 'function')", trusted) == "");
  }

  TEST_CASE("sandbox: an endless loop ends at the instruction budget") {
    softcut::lua::SandboxOptions opt;
    opt.instruction_budget = 2'000'000;
    const std::string e = lua_error("local i = 0\nwhile true do i = i + 1 end", opt);
    CHECK(e.rfind("snippet.lua:2: instruction budget of 2000000 instructions exceeded", 0) == 0);
    CHECK(contains(e, "--trust"));
    // A coroutine does not escape it.
    CHECK(contains(lua_error("coroutine.wrap(function() while true do end end)()", opt), "instruction budget"));
  }

  TEST_CASE("sandbox: a huge allocation ends at the memory budget") {
    softcut::lua::SandboxOptions opt;
    opt.memory_budget = 32u << 20;
    CHECK(contains(lua_error("local s = string.rep('x', 64 * 1024 * 1024)", opt), "memory budget of 32 MiB exceeded"));
    CHECK(contains(lua_error("local t = {}\nfor i = 1, 1e8 do t[i] = i end", opt), "memory budget of 32 MiB exceeded"));
    // The state stays usable after a refused allocation.
    softcut::lua::Runtime rt(opt);
    CHECK_THROWS(rt.run_string("local s = string.rep('x', 64 * 1024 * 1024)", "=t", 0));
    rt.run_string("assert(#string.rep('x', 1000) == 1000)", "=t", 0);
    CHECK(rt.memory_used() < opt.memory_budget);
  }

  TEST_CASE("tight budgets (the lua fuzz target's) still load the library and a small scenario") {
    // tests/fuzz/fuzz_lua.cpp runs every input with these budgets: they must
    // leave room for real scenarios, or the fuzzer would only see refusals.
    softcut::lua::SandboxOptions opt;
    opt.instruction_budget = 100'000;
    opt.memory_budget = 8u << 20;
    softcut::lua::Runtime rt(opt);
    MESSAGE("library load: " << rt.instructions_used() << " instructions, " << rt.memory_used() << " bytes");
    CHECK(rt.memory_used() < opt.memory_budget / 2);
    softcut::app::RunRequest req;
    req.scenario = softcut::test::write_scenario("rt_tight", std::string(softcut::test::kBoxHead) + "return s\n");
    req.render = false;
    req.instruction_budget = opt.instruction_budget;
    req.memory_budget = opt.memory_budget;
    req.max_tets = 5000;
    CHECK_NOTHROW(softcut::app::load_scenario_spec(req));
  }

  TEST_CASE("an interruption flag stops running Lua code, also with --trust") {
    std::atomic<bool> flag{false};
    softcut::lua::SandboxOptions opt;
    opt.trusted = true;
    opt.interrupt = &flag;
    softcut::lua::Runtime rt(opt);
    flag = true;  // as the signal handler would
    CHECK_THROWS_WITH(rt.run_string("local x = 0\nwhile true do x = x + 1 end", "@loop.lua", 0),
                      doctest::Contains("loop.lua:2: interrupted"));
  }

  TEST_CASE("--trust lifts the budgets") {
    softcut::lua::SandboxOptions opt;
    opt.trusted = true;
    opt.instruction_budget = 1000;
    opt.memory_budget = 1u << 20;
    CHECK(lua_error("local t = {} for i = 1, 300000 do t[i] = i end", opt) == "");
  }

  TEST_CASE("native work is charged to the instruction budget and the mesh limit follows the sandbox") {
    softcut::lua::SandboxOptions opt;
    opt.instruction_budget = 1'000'000;
    opt.max_tets = 1234;
    softcut::lua::Runtime rt(opt);
    lua_State* L = rt.state();
    CHECK(softcut::lua::max_tets(L) == 1234);
    lua_register(L, "work", [](lua_State* L) -> int {
      return softcut::lua::protect(L, [L] {
        softcut::lua::charge_work(L, luaL_checknumber(L, 1), "here");
        return 0;
      });
    });
    CHECK_NOTHROW(rt.run_string("work(6e5)", "@snippet.lua", 0));
    CHECK_THROWS_WITH_AS(rt.run_string("work(6e5)\nwork(6e5)", "@snippet.lua", 0),
                         doctest::Contains("snippet.lua:2: here: instruction budget of 1000000 instructions exceeded"),
                         softcut::Error);
    // Spent is spent: every later call fails at once (sticky, issue #13).
    CHECK_THROWS_WITH_AS(rt.run_string("local x = 1", "@other.lua", 0), doctest::Contains("instruction budget"),
                         softcut::Error);
    // Work is the script's whenever a call into it runs, also from chunks
    // that are no user file (load()ed code, coroutines); the engine's own
    // work outside any call (compile, the frame loop) is not charged.
    softcut::lua::Runtime fresh(opt);
    lua_register(fresh.state(), "work", [](lua_State* L) -> int {
      return softcut::lua::protect(L, [L] {
        softcut::lua::charge_work(L, luaL_checknumber(L, 1), "here");
        return 0;
      });
    });
    CHECK_THROWS_WITH_AS(fresh.run_string("work(6e5)\nwork(6e5)", "=engine", 0), doctest::Contains("here: instruction budget"),
                         softcut::Error);
    softcut::lua::Runtime outside(opt);
    CHECK_NOTHROW(softcut::lua::charge_work(outside.state(), 1e12, "engine"));
    opt.trusted = true;
    softcut::lua::Runtime trusted(opt);
    CHECK(std::isinf(softcut::lua::max_tets(trusted.state())));
    lua_register(trusted.state(), "work", [](lua_State* L) -> int {
      return softcut::lua::protect(L, [L] {
        softcut::lua::charge_work(L, 1e18, "here");
        return 0;
      });
    });
    CHECK_NOTHROW(trusted.run_string("work()", "@snippet.lua", 0));
  }

  TEST_CASE("engine memory held for the script counts with the Lua heap against the memory budget") {
    softcut::lua::SandboxOptions opt;
    opt.memory_budget = 32u << 20;
    softcut::lua::Runtime rt(opt);
    lua_State* L = rt.state();
    const std::size_t heap = rt.memory_used();
    softcut::lua::charge_memory(L, 20u << 20, "here");
    CHECK(rt.memory_used() >= (20u << 20));
    CHECK(rt.memory_used() <= heap + (20u << 20));  // a collector step may have freed some heap
    CHECK_THROWS_WITH_AS(softcut::lua::charge_memory(L, 20u << 20, "here"),
                         doctest::Contains("here: memory budget of 32 MiB exceeded: this mesh needs 20 MiB"),
                         softcut::Error);
    // Lua allocations see it too, and the message names both.
    CHECK_THROWS_WITH(rt.run_string("local s = string.rep('x', 8 * 1024 * 1024)", "=t", 0),
                      doctest::Contains("memory budget of 32 MiB exceeded by the scenario's Lua data and meshes"));
    softcut::lua::release_memory(L, 20u << 20);
    CHECK(rt.memory_used() < heap + (1u << 20));
    CHECK_NOTHROW(rt.run_string("local s = string.rep('x', 8 * 1024 * 1024)", "=t", 0));
    opt.trusted = true;
    softcut::lua::Runtime trusted(opt);
    CHECK_NOTHROW(softcut::lua::charge_memory(trusted.state(), std::size_t(1) << 40, "here"));
  }
}
