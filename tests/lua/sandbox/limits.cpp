#include "sandbox/limits.hpp"

#include <doctest/doctest.h>
#include <lua.hpp>

#include <cmath>
#include <fstream>

#include "lua/lua_test_support.hpp"

namespace fs = std::filesystem;
using softcut::test::contains;
using softcut::test::lua_error;

TEST_SUITE("lua/sandbox/limits") {
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
