// lua/api.lua + scripts/lua_api_docs.lua: the API description is complete, and
// docs/lua-api.md and docs/softcut.d.lua are its current renderings.
#include <doctest/doctest.h>
#include <lua.hpp>

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "core/atomic_file.hpp"
#include "lua_test_support.hpp"

namespace fs = std::filesystem;

using softcut::test::slurp;

namespace {

// A runtime that finds the docs renderer, a tool beside the scripts (not
// part of the embedded library), with require.
softcut::lua::SandboxOptions docs_options() {
  softcut::lua::SandboxOptions opt;
  opt.read_dir = fs::path(SOFTCUT_SOURCE_DIR) / "scripts";
  return opt;
}

std::string render(const char* fn) {
  softcut::lua::Runtime rt(docs_options());
  rt.run_string(softcut::cat("return require('lua_api_docs').", fn, "()"), "=docs", 1);
  std::string s = lua_tostring(rt.state(), -1);
  return s;
}

// Every function reachable from `softcut` and the method tables.
std::vector<std::string> registered() {
  softcut::lua::Runtime rt(docs_options());
  lua_State* L = rt.state();
  rt.run_string(R"(
local sc, check = require("scenario"), require("check")
local names = require("lua_api_docs").registered(softcut,
  { Scenario = sc.Scenario, Frame = sc.Frame, Selection = check.Selection, Ramp = check.Ramp, Path = check.Path })
return table.concat(names, "\n"))", "=reg", 1);
  std::vector<std::string> out;
  std::istringstream ss(lua_tostring(L, -1));
  for (std::string line; std::getline(ss, line);) out.push_back(line);
  return out;
}

void compare_or_write(const fs::path& file, const std::string& text) {
  if (std::getenv("SOFTCUT_WRITE_DOCS")) {
    fs::create_directories(file.parent_path());
    softcut::write_file_atomic(file, text);
  }
  INFO("regenerate with SOFTCUT_WRITE_DOCS=1 test_lua -ts=lua/api");
  CHECK(slurp(file) == text);
}

}  // namespace

TEST_SUITE("lua/api") {
  TEST_CASE("every registered function is described in api.lua and documented in docs/lua-api.md") {
    const std::vector<std::string> names = registered();
    CHECK(names.size() > 40);
    const std::string md = slurp(fs::path(SOFTCUT_SOURCE_DIR) / "docs" / "lua-api.md");
    softcut::lua::SandboxOptions opt;
    opt.trusted = true;
    softcut::lua::Runtime rt(opt);
    for (const std::string& n : names) {
      CAPTURE(n);
      rt.run_string(softcut::cat("assert(require('api').by_name['", n, "'])"), "=api", 0);
      CHECK(md.find("### `" + n) != std::string::npos);
    }
    // And the other way: nothing described that does not exist.
    rt.run_string("local n = 0 for _, f in ipairs(require('api').functions) do n = n + 1 end return n", "=api", 1);
    CHECK(lua_tointeger(rt.state(), -1) == lua_Integer(names.size()));
  }

  TEST_CASE("docs/lua-api.md is the rendering of api.lua") {
    compare_or_write(fs::path(SOFTCUT_SOURCE_DIR) / "docs" / "lua-api.md", render("markdown"));
  }

  TEST_CASE("docs/softcut.d.lua is the rendering of api.lua and is valid Lua") {
    const std::string text = render("annotations");
    compare_or_write(fs::path(SOFTCUT_SOURCE_DIR) / "docs" / "softcut.d.lua", text);
    softcut::lua::Runtime rt;
    rt.run_string(text, "=softcut.d.lua", 0);
  }

  TEST_CASE("the introduction's example scenario runs and meets its expectation") {
    const std::string md = render("markdown");
    const size_t a = md.find("```lua\n") + 7, b = md.find("```", a);
    const fs::path f = softcut::test::write_scenario("api_intro", md.substr(a, b - a));
    softcut::app::RunOutcome out;
    REQUIRE(softcut::test::scenario_error(f, &out) == "");
    REQUIRE(out.expectations.size() == 1);
    CHECK(out.expectations[0].ok);
    CHECK(out.result.reason == softcut::sim::ExitReason::completed);
  }

  TEST_CASE("every example in api.lua runs its checks without an argument error") {
    // Constructors' examples are complete expressions: evaluate them.
    softcut::lua::SandboxOptions opt;
    opt.trusted = true;
    softcut::lua::Runtime rt(opt);
    rt.run_string(R"(
for _, f in ipairs(require("api").functions) do
  if f.name:match("^softcut%.[%w_]+%.[%w_]+$") and not f.name:match("^softcut%.vec") then
    local chunk = assert(load("return " .. f.example, "=" .. f.name))
    local ok, err = pcall(chunk)
    if not ok and not tostring(err):match("named node set") then error(f.name .. ": " .. tostring(err)) end
  end
end)", "=examples", 0);
  }
}
