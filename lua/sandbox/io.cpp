// The sandbox's io library (sandbox/limits.hpp, push_sandboxed_io).
#include <lua.hpp>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>

#include "core/checked_file.hpp"
#include "core/error.hpp"
#include "core/output_budget.hpp"
#include "core/printable.hpp"
#include "sandbox/limits.hpp"

namespace fs = std::filesystem;

namespace softcut::lua {

namespace {

// Bytes a write of argument i will produce (numbers as at most LUAI_MAXSHORTLEN).
std::size_t written_bytes(lua_State* L, int from) {
  std::size_t total = 0;
  for (int i = from, n = lua_gettop(L); i <= n; ++i) {
    size_t len = 0;
    if (lua_type(L, i) == LUA_TNUMBER) len = 40;
    else if (lua_type(L, i) == LUA_TSTRING) lua_tolstring(L, i, &len);
    total += len;
  }
  return total;
}

// Charges a write of `bytes` to the instruction budget and the run's output
// budget; raises (a plain error) when the output budget cannot take it.
void charge_output(lua_State* L, std::size_t bytes, const char* what) {
  charge_or_raise(L, double(bytes) / 8, what);
  Runtime::Budget* b = budget_of(L);
  if (!b->output || b->output->try_charge(bytes)) return;  // the message (and where) only on failure
  bool failed = false;
  {
    std::string msg;
    try {
      b->output->charge(bytes, cat(user_where(L), ": ", what));
    } catch (const std::exception& e) {
      msg = e.what();
      failed = true;
    }
    if (failed) lua_pushlstring(L, msg.data(), msg.size());
  }  // msg gone before the longjmp
  if (failed) lua_error(L);
}

// file:write / io.write: the original (upvalue 1) after the charge; the
// first data argument is `from` (2 for the method, 1 for io.write).
int charged_write(lua_State* L) {
  const int from = int(lua_tointeger(L, lua_upvalueindex(2)));
  charge_output(L, written_bytes(L, from), from == 2 ? "file:write" : "io.write");
  return call_original(L);
}

// file:seek that cannot move past the end: a write there would make a
// sparse file of any size for a few bytes of output budget.
int bounded_seek(lua_State* L) {
  auto* p = static_cast<luaL_Stream*>(luaL_checkudata(L, 1, LUA_FILEHANDLE));
  if (p->closef && p->f) {
    static const char* const kWhence[] = {"set", "cur", "end", nullptr};
    const int whence = luaL_checkoption(L, 2, "cur", kWhence);
    const lua_Integer offset = luaL_optinteger(L, 3, 0);
    std::fflush(p->f);
    struct stat st {};
    const long here = std::ftell(p->f);
    if (::fstat(::fileno(p->f), &st) == 0 && here >= 0) {
      const double base = whence == 0 ? 0.0 : whence == 1 ? double(here) : double(st.st_size);
      if (base + double(offset) > double(st.st_size))
        return luaL_error(L, "file:seek: moving past the end of the file (to byte %f of %I) is not available in "
                             "the sandbox; write the bytes in between, or run with --trust",
                          base + double(offset), lua_Integer(st.st_size));
    }
  }
  return call_original(L);
}

// print, with its bytes charged like io.write.
int charged_print(lua_State* L) {
  const int n = lua_gettop(L);
  std::size_t total = 0;
  for (int i = 1; i <= n; ++i) {
    size_t len = 0;
    luaL_tolstring(L, i, &len);  // leaves the strings at n+1 .. 2n
    total += len + 1;
  }
  charge_output(L, total, "print");
  for (int i = 1; i <= n; ++i) {
    size_t len = 0;
    const char* s = lua_tolstring(L, n + i, &len);
    if (i > 1) std::fputc('\t', stdout);
    std::fwrite(s, 1, len, stdout);
  }
  std::fputc('\n', stdout);
  std::fflush(stdout);
  return 0;
}

// warn(msg1, ...), with its bytes charged like io.write (it writes to stderr).
int charged_warn(lua_State* L) {
  charge_output(L, written_bytes(L, 1), "warn");
  return call_original(L, 0);
}

int close_stream(lua_State* L) {
  auto* p = static_cast<luaL_Stream*>(luaL_checkudata(L, 1, LUA_FILEHANDLE));
  const int ok = std::fclose(p->f) == 0;
  return luaL_fileresult(L, ok, nullptr);
}

// io.open(name [, mode]) and io.lines(name, ...) (upvalue 1: true for lines)
// through the checked open: below the scenario folder for reading, below
// the output folder for writing; relative names resolve against them.
int sandboxed_open(lua_State* L) {
  const char* name = luaL_checkstring(L, 1);
  const bool lines = lua_toboolean(L, lua_upvalueindex(1));
  const char* mode = lines ? "r" : luaL_optstring(L, 2, "r");
  Access access = Access::read;
  if (!parse_access(mode, access)) return luaL_argerror(L, 2, "invalid mode");
  // Every file opened for writing counts a block against the output budget,
  // so a loop of empty files cannot fill a disk's inodes.
  if (writes(access)) charge_output(L, 4096, lines ? "io.lines" : "io.open");
  // The handle first, marked closed: if Lua raises below, nothing leaks.
  auto* p = static_cast<luaL_Stream*>(lua_newuserdatauv(L, sizeof(luaL_Stream), 0));
  p->f = nullptr;
  p->closef = nullptr;
  luaL_setmetatable(L, LUA_FILEHANDLE);
  const int handle = lua_gettop(L);
  int fd = -1, missing = 0;
  bool refused = false;
  {
    std::string msg;
    try {
      const SandboxOptions& opt = options_of(L);
      const fs::path& dir = writes(access) ? opt.write_dir : opt.read_dir;
      const fs::path rel = dir.empty() ? fs::path() : relative_below(dir, fs::path(name));
      const char* fn = lines ? "io.lines" : "io.open";
      if (dir.empty() && writes(access)) {
        msg = cat(fn, ": '", printable(name), "': the script's main chunk may not write files (the output folder is "
                  "made after it ran); write from on_frame, below the output folder, or run with --trust");
      } else if (rel.empty()) {
        msg = cat(fn, ": '", printable(name), "' is outside the ", writes(access) ? "output folder '" : "scenario folder '",
                  printable(dir.string()), "' (the sandbox reads below the scenario folder and writes below the output "
                  "folder; run with --trust to lift this)");
      } else {
        fd = open_below_if_exists(dir, rel, access, fn, &missing).release();
      }
    } catch (const std::exception& e) {
      msg = e.what();
    }
    refused = !msg.empty();
    if (refused) lua_pushlstring(L, msg.data(), msg.size());
  }  // C++ objects gone before anything below can longjmp
  if (refused) {
    luaL_where(L, 1);
    lua_insert(L, -2);
    lua_concat(L, 2);
    return lua_error(L);
  }
  if (fd < 0) {  // a missing file: nil, message, errno, as io.open says
    luaL_pushfail(L);
    lua_pushfstring(L, "%s: %s", name, std::strerror(missing));
    lua_pushinteger(L, missing);
    return 3;
  }
  p->f = ::fdopen(fd, mode);
  if (!p->f) {
    ::close(fd);
    return luaL_fileresult(L, 0, name);
  }
  p->closef = close_stream;
  if (!lines) return 1;
  // io.lines: the iterator, and the file as the generic for's to-be-closed
  // value, so it is closed when the loop ends.
  lua_getfield(L, handle, "lines");
  lua_pushvalue(L, handle);
  for (int i = 2; i < handle; ++i) lua_pushvalue(L, i);
  lua_call(L, handle - 1, 1);
  lua_pushnil(L);
  lua_pushnil(L);
  lua_pushvalue(L, handle);
  return 4;
}

}  // namespace

void push_sandboxed_io(lua_State* L) {
  luaL_requiref(L, LUA_IOLIBNAME, luaopen_io, 0);  // the full library (registry only)
  const int full = lua_gettop(L);
  // File handles' methods: write charged, seek bounded; the metatable locked
  // (getmetatable returns false), so no script can give handles a __gc.
  luaL_getmetatable(L, LUA_FILEHANDLE);
  lua_getfield(L, -1, "__index");
  lua_getfield(L, -1, "write");
  lua_pushinteger(L, 2);
  lua_pushcclosure(L, charged_write, 2);
  lua_setfield(L, -2, "write");
  lua_getfield(L, -1, "seek");
  lua_pushcclosure(L, bounded_seek, 1);
  lua_setfield(L, -2, "seek");
  lua_pop(L, 1);
  lua_pushboolean(L, 0);
  lua_setfield(L, -2, "__metatable");
  lua_pop(L, 1);

  lua_newtable(L);
  lua_getfield(L, full, "write");
  lua_pushinteger(L, 1);
  lua_pushcclosure(L, charged_write, 2);
  lua_setfield(L, -2, "write");
  for (const char* k : {"type", "stdout", "stderr"}) {
    lua_getfield(L, full, k);
    lua_setfield(L, -2, k);
  }
  for (int lines = 0; lines < 2; ++lines) {
    lua_pushboolean(L, lines);
    lua_pushcclosure(L, sandboxed_open, 1);
    lua_setfield(L, -2, lines ? "lines" : "open");
  }
  lua_remove(L, full);

  lua_pushcfunction(L, charged_print);
  lua_setglobal(L, "print");
  lua_getglobal(L, "warn");
  lua_pushcclosure(L, charged_warn, 1);
  lua_setglobal(L, "warn");
}

}  // namespace softcut::lua
