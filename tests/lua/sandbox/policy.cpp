#include "sandbox/policy.hpp"

#include <doctest/doctest.h>
#include <lua.hpp>

#include <cmath>
#include <fstream>

#include "lua/lua_test_support.hpp"

namespace fs = std::filesystem;
using softcut::test::contains;
using softcut::test::lua_error;

TEST_SUITE("lua/sandbox/policy") {
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

  TEST_CASE("sandbox: binary chunks are refused, text chunks load") {
    CHECK(contains(lua_error("load(string.dump(function() return 1 end))"), "binary chunks are refused"));
    CHECK(lua_error("assert(load('return 1 + 1')() == 2)") == "");
    softcut::lua::SandboxOptions trusted;
    trusted.trusted = true;
    CHECK(lua_error("assert(load(string.dump(function() return 7 end))() == 7)", trusted) == "");
    CHECK(lua_error("assert(type(os.getenv) == 'function')", trusted) == "");
  }
}
