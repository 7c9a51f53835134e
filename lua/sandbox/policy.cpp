#include "sandbox/policy.hpp"

#include <lua.hpp>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <string>

#include "core/error.hpp"
#include "core/printable.hpp"
#include "runtime.hpp"
#include "sandbox/limits.hpp"
#include "sandbox/patterns.hpp"

namespace softcut::lua {

namespace {

// load(chunk [, name [, mode [, env]]]) with mode forced to text; a string
// is parsed in pieces with the CPU time checked between them (load_text).
int sandboxed_load(lua_State* L) {
  if (lua_type(L, 1) == LUA_TSTRING) {
    size_t n = 0;
    const char* s = lua_tolstring(L, 1, &n);
    if (n > 0 && s[0] == LUA_SIGNATURE[0])
      return luaL_error(L, "load: binary chunks are refused in the sandbox (they can crash the "
                           "interpreter); load Lua source text, or run with --trust");
    const char* chunkname = luaL_optstring(L, 2, s);  // as Lua's load names a string chunk
    const int env = lua_gettop(L) >= 4 ? 4 : 0;
    if (load_text(L, s, n, chunkname, "t") != LUA_OK) {
      luaL_pushfail(L);
      lua_insert(L, -2);
      return 2;  // nil, message
    }
    if (env) {  // the first upvalue of a main chunk is its _ENV
      lua_pushvalue(L, env);
      if (!lua_setupvalue(L, -2, 1)) lua_pop(L, 1);
    }
    return 1;
  }
  const int top = lua_gettop(L);
  lua_pushvalue(L, lua_upvalueindex(1));
  lua_pushvalue(L, 1);
  if (top >= 2) lua_pushvalue(L, 2); else lua_pushnil(L);
  lua_pushliteral(L, "t");
  if (top >= 4) lua_pushvalue(L, 4);  // env only when given: nil would mean "no upvalue"
  lua_call(L, top >= 4 ? 4 : 3, LUA_MULTRET);
  return lua_gettop(L) - top;
}

// Refuses a name taken out of the sandbox, saying how to get it back.
int refused(lua_State* L) {
  return luaL_error(L, "%s is not available in the sandbox; run with --trust to allow it",
                    lua_tostring(L, lua_upvalueindex(1)));
}

void push_refused(lua_State* L, const char* name) {
  lua_pushstring(L, name);
  lua_pushcclosure(L, refused, 1);
}

// __index of a trimmed library table: names that exist only with --trust.
int refused_index(lua_State* L) {
  const char* lib = lua_tostring(L, lua_upvalueindex(1));
  const char* key = lua_tostring(L, 2);
  return luaL_error(L, "%s.%s is not available in the sandbox; run with --trust to allow it", lib,
                    key ? key : "?");
}

void set_refusing_metatable(lua_State* L, int t, const char* lib) {
  t = lua_absindex(L, t);
  lua_newtable(L);
  lua_pushstring(L, lib);
  lua_pushcclosure(L, refused_index, 1);
  lua_setfield(L, -2, "__index");
  lua_setmetatable(L, t);
}

// Copies library `lib` (opened into package.loaded only) keeping `keep`.
void push_trimmed(lua_State* L, lua_CFunction open, const char* lib, std::initializer_list<const char*> keep) {
  luaL_requiref(L, lib, open, 0);
  lua_newtable(L);
  for (const char* k : keep) {
    lua_getfield(L, -2, k);
    lua_setfield(L, -2, k);
  }
  lua_remove(L, -2);
}

// string.find / match / gmatch / gsub in the sandbox. Lua's matcher runs in
// C, where the count hook never fires, and backtracks exponentially on
// patterns like ('a*'):rep(40) .. 'b': each call first bounds its worst-case
// work (sandbox/patterns.hpp) and is refused when the bound exceeds what is
// left of the instruction budget (kPatternStepsPerInstruction matcher steps
// per instruction) or kPatternStepCap. The call is charged its bound (a
// refused one what it was allowed), so a loop of calls ends at the budget.
// Strings' metatable indexes this same table: s:match(...) is covered too.
constexpr double kPatternStepsPerInstruction = 8;
constexpr double kPatternStepCap = 1e9;  // ~1 s of matching, budget or not

int guarded_pattern(lua_State* L) {
  const auto call = static_cast<PatternCall>(lua_tointeger(L, lua_upvalueindex(2)));
  size_t n = 0, m = 0, repl = 0;
  const char* s = luaL_checklstring(L, 1, &n);
  const char* p = luaL_checklstring(L, 2, &m);
  size_t skip = 0;  // bytes before init: searches start there
  if (call == PatternCall::gsub) {
    const int t = lua_type(L, 3);
    luaL_argexpected(L, t == LUA_TNUMBER || t == LUA_TSTRING || t == LUA_TTABLE || t == LUA_TFUNCTION, 3,
                     "string/function/table");
    if (t == LUA_TSTRING || t == LUA_TNUMBER) lua_tolstring(L, 3, &repl);
    luaL_optinteger(L, 4, 0);
  } else {
    const lua_Integer init = luaL_optinteger(L, 3, 1);  // as Lua reads it: negative counts from the end
    if (init > 0) skip = size_t(std::min<lua_Integer>(init - 1, lua_Integer(n)));
    else if (init < 0 && init >= -lua_Integer(n)) skip = n - size_t(-init);  // -init: no overflow here
  }
  const bool plain = call == PatternCall::find && lua_toboolean(L, 4);
  Runtime::Budget* b = budget_of(L);
  double allowed = kPatternStepCap;
  if (b->instruction_limit)
    allowed = std::min(allowed, double(std::max(0LL, b->instruction_limit - b->instructions)) *
                                    kPatternStepsPerInstruction);
  PatternWork w;
  try {
    w = pattern_work(call, {s + skip, n - skip}, {p, m}, plain, repl, allowed);
  } catch (...) {  // std::bad_alloc: refuse below, no exception may cross Lua
    w.steps = HUGE_VAL;
  }
  b->instructions += static_cast<long long>(std::min(w.steps, allowed) / kPatternStepsPerInstruction);
  if (w.steps <= allowed) return call_original_placed(L, LUA_MULTRET, lua_tostring(L, lua_upvalueindex(3)));
  {
    const char* name = lua_tostring(L, lua_upvalueindex(3));
    std::string shown(p, std::min<size_t>(m, 60));
    for (char& c : shown)
      if (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) > 126) c = '?';
    if (m > 60) shown += "...";
    char steps[32], budget[32];
    std::snprintf(steps, sizeof steps, "%.3g", w.steps);
    std::snprintf(budget, sizeof budget, "%.3g", allowed);
    const std::string head = cat(user_prefix(L), name, ": ");
    const std::string tail = cat(" steps, over the sandbox budget of ", budget, " steps; ");
    const std::string msg =
        plain ? cat(head, "searching a ", m, "-byte string in a ", n - skip, "-byte subject could take up to ~",
                    steps, tail, "shorten the strings, or run with --trust to lift the sandbox budgets")
              : cat(head, "pattern '", shown, "' with ", w.repetitions, " repetition items over a ", n - skip,
                    "-byte subject could backtrack for ", std::isinf(w.steps) ? "more than the budget: over " : "up to ~",
                    std::isinf(w.steps) ? budget : steps, tail,
                    "simplify the pattern or shorten the subject, or run with --trust to lift the sandbox budgets");
    lua_pushlstring(L, msg.data(), msg.size());
  }  // C++ strings gone before the longjmp
  return lua_error(L);
}

void guard_string_patterns(lua_State* L) {
  lua_getglobal(L, LUA_STRLIBNAME);
  const std::pair<const char*, PatternCall> fns[] = {
      {"find", PatternCall::find}, {"match", PatternCall::match},
      {"gmatch", PatternCall::gmatch}, {"gsub", PatternCall::gsub}};
  for (const auto& [key, call] : fns) {
    lua_getfield(L, -1, key);
    lua_pushinteger(L, lua_Integer(call));
    lua_pushfstring(L, "string.%s", key);
    lua_pushcclosure(L, guarded_pattern, 3);
    lua_setfield(L, -2, key);
  }
  lua_pop(L, 1);
}

}  // namespace

void open_sandbox(lua_State* L) {
  luaL_requiref(L, LUA_GNAME, luaopen_base, 1);
  luaL_requiref(L, LUA_STRLIBNAME, luaopen_string, 1);
  luaL_requiref(L, LUA_TABLIBNAME, luaopen_table, 1);
  luaL_requiref(L, LUA_MATHLIBNAME, luaopen_math, 1);
  luaL_requiref(L, LUA_UTF8LIBNAME, luaopen_utf8, 1);
  luaL_requiref(L, LUA_COLIBNAME, luaopen_coroutine, 1);
  lua_pop(L, 6);
  guard_string_patterns(L);

  push_refused(L, "dofile");
  lua_setglobal(L, "dofile");
  push_refused(L, "loadfile");
  lua_setglobal(L, "loadfile");
  lua_getglobal(L, "load");
  lua_pushcclosure(L, sandboxed_load, 1);
  lua_setglobal(L, "load");

  push_sandboxed_io(L);
  set_refusing_metatable(L, -1, "io");
  lua_setglobal(L, "io");

  push_trimmed(L, luaopen_os, LUA_OSLIBNAME, {"clock", "time", "date", "difftime"});
  set_refusing_metatable(L, -1, "os");
  lua_setglobal(L, "os");

  lua_newtable(L);
  set_refusing_metatable(L, -1, "package");
  lua_setglobal(L, "package");
  lua_newtable(L);
  set_refusing_metatable(L, -1, "debug");
  lua_setglobal(L, "debug");
  install_sandbox_limits(L);
}

}  // namespace softcut::lua
