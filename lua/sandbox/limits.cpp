#include "sandbox/limits.hpp"

#include <lua.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "core/error.hpp"

namespace softcut::lua {

namespace {

// Work inside C functions is charged as instructions: one per element moved
// or visited, one per kBytesPerInstruction bytes copied or allocated (a Lua
// VM instruction costs a few ns; memcpy moves a few bytes per ns).
constexpr double kBytesPerInstruction = 8;

// Turns the budget fatal with `msg` (what the script will see, once, and
// every later attempt too).
void make_fatal(Runtime::Budget* b, std::string msg) {
  if (b->fatal) return;
  b->fatal = true;
  b->fatal_message = std::move(msg);
}

std::string budget_message(lua_State* L, Runtime::Budget* b, const char* what) {
  const std::string where = user_where(L);
  return cat(where, ": ", what ? what : "", what ? ": " : "", "instruction budget of ", b->instruction_limit,
             " instructions exceeded (an endless loop?); run with --trust to lift the sandbox budgets");
}

}  // namespace

Runtime::Budget* budget_of(lua_State* L) {
  void* ud = nullptr;
  lua_getallocf(L, &ud);
  return static_cast<Runtime::Budget*>(ud);
}

void* budget_alloc(void* ud, void* ptr, std::size_t osize, std::size_t nsize) {
  auto* b = static_cast<Runtime::Budget*>(ud);
  const std::size_t old = ptr ? osize : 0;
  if (nsize == 0) {
    b->used -= old;
    std::free(ptr);
    return nullptr;
  }
  if (b->limit && nsize > old && b->used - old + nsize + b->native > b->limit) {
    b->memory_exceeded = true;
    return nullptr;  // Lua raises LUA_ERRMEM after an emergency collection
  }
  void* p = std::realloc(ptr, nsize);
  if (!p) return nullptr;
  b->used = b->used - old + nsize;
  // Bytes allocated are work done in C (string.rep, concatenation, upper on
  // a huge string): charged here, raised by the hook within kHookInterval
  // instructions. An allocation may not raise itself.
  if (b->instruction_limit && nsize > old) b->instructions += (long long)(double(nsize - old) / kBytesPerInstruction);
  return p;
}

void begin_call(lua_State* L, Runtime::Budget* b) {
  set_running_state(L);
  if (!(b->cpu_limit_s > 0)) return;
  b->cpu_start_s = thread_cpu_seconds();
  b->cpu_polls = 0;
  b->cpu_timer = b->timer.arm(b->cpu_limit_s);
}

void end_call(Runtime::Budget* b) {
  if (b->cpu_timer) b->timer.disarm();
  b->cpu_timer = false;
  set_running_state(nullptr);
}

namespace {

// Past the call's CPU time: fatal. Woken early (engine work the clock
// exempts ran meanwhile): the timer is set again for what is left.
void check_cpu(lua_State* L, Runtime::Budget* b) {
  const double used = thread_cpu_seconds() - b->cpu_start_s;
  if (used >= b->cpu_limit_s) {
    make_fatal(b, cat(user_where(L), ": CPU time limit of ", b->cpu_limit_s, " s per call exceeded (this call into "
                      "the script ran ", std::round(used * 10) / 10, " s: a loop of costly work inside Lua's C code, "
                      "on huge strings or tables?); run with --trust to lift the sandbox budgets"));
  } else if (b->cpu_timer) {
    b->cpu_timer = b->timer.arm(b->cpu_limit_s - used);
  }
}

}  // namespace

void count_hook(lua_State* L, lua_Debug*) {
  Runtime::Budget* b = budget_of(L);
  // Called at once (count 1) by the CPU timer's signal or after a fatal stop,
  // else every kHookInterval instructions.
  const bool woken = lua_gethookcount(L) != kHookInterval;
  b->instructions += woken ? 1 : kHookInterval;
  set_running_state(L);  // a coroutine's hook runs on the coroutine
  if (!b->fatal) {
    if (b->interrupt && b->interrupt->load()) {
      make_fatal(b, user_where(L) + ": interrupted");
    } else if (b->deadline && b->deadline->load()) {
      make_fatal(b, cat(user_where(L), ": the scenario's wall-clock limit of ", b->timeout_s,
                        " s was reached (--timeout SECONDS raises it)"));
    } else if (b->instruction_limit && b->instructions > b->instruction_limit) {
      make_fatal(b, budget_message(L, b, nullptr));
    } else if (b->cpu_limit_s > 0 && (woken || (!b->cpu_timer && ++b->cpu_polls % 16 == 0))) {
      check_cpu(L, b);
    }
  }
  if (b->fatal) raise_fatal(L);
  if (woken) lua_sethook(L, count_hook, LUA_MASKCOUNT, kHookInterval);
}

int raise_fatal(lua_State* L) {
  Runtime::Budget* b = budget_of(L);
  // Every later instruction hits the hook again at once.
  lua_sethook(L, count_hook, LUA_MASKCOUNT, 1);
  lua_pushlstring(L, b->fatal_message.data(), b->fatal_message.size());
  return lua_error(L);
}

int call_original(lua_State* L, int nresults) {
  lua_pushvalue(L, lua_upvalueindex(1));
  lua_insert(L, 1);
  lua_call(L, lua_gettop(L) - 1, nresults);
  return lua_gettop(L);
}

namespace {

// Whether an error message starts with a position, "file:12: " (first line).
bool has_position(const char* m, size_t n) {
  for (size_t i = 0; i < n && m[i] != '\n'; ++i) {
    if (m[i] != ':') continue;
    size_t j = i + 1;
    while (j < n && m[j] >= '0' && m[j] <= '9') ++j;
    if (j > i + 1 && j < n && m[j] == ':') return true;
  }
  return false;
}

}  // namespace

int call_original_placed(lua_State* L, int nresults, const char* name) {
  lua_pushvalue(L, lua_upvalueindex(1));
  lua_insert(L, 1);
  const int status = lua_pcall(L, lua_gettop(L) - 1, nresults, 0);
  if (status == LUA_OK) return lua_gettop(L);
  if (budget_of(L)->fatal) raise_fatal(L);
  size_t n = 0;
  const char* m = lua_type(L, -1) == LUA_TSTRING ? lua_tolstring(L, -1, &n) : nullptr;
  if (status != LUA_ERRMEM && m && !has_position(m, n)) {
    {
      // The original raised with luaL_where of its caller, this wrapper (a C
      // function: no line): the script's line instead, and the function's
      // name where Lua could not find it ("bad argument #1 to '?'").
      std::string msg(m, n);
      const size_t q = msg.find(" to '?'");
      if (name && q != std::string::npos) msg.replace(q, 7, cat(" to '", name, "'"));
      msg.insert(0, user_prefix(L));
      lua_pushlstring(L, msg.data(), msg.size());
    }  // no C++ object alive across lua_error
    lua_replace(L, -2);
  }
  return lua_error(L);
}

namespace {

// Lua's parser is C code that no hook reaches, and some inputs take it
// quadratic time (a 1e6-term `a or a or ...` parses for many minutes): the
// text goes to it in pieces and the CPU time is checked between them.
struct PieceReader {
  const char* p;
  size_t left;
  const char* chunkname;
  double start;  // CPU clock the limit counts from, s
};

constexpr size_t kPieceBytes = 4096;

const char* read_piece(lua_State* L, void* ud, size_t* size) {
  auto* r = static_cast<PieceReader*>(ud);
  if (r->left == 0) return nullptr;
  Runtime::Budget* b = budget_of(L);
  if (b->cpu_limit_s > 0 && !b->fatal && thread_cpu_seconds() - r->start >= b->cpu_limit_s) {
    std::string where = user_where(L);
    if (where == "?") where = r->chunkname[0] == '@' || r->chunkname[0] == '=' ? r->chunkname + 1 : "load";
    make_fatal(b, cat(where, ": CPU time limit of ", b->cpu_limit_s, " s per call exceeded while Lua parsed the chunk "
                      "(a huge or deeply chained expression?); run with --trust to lift the sandbox budgets"));
  }
  if (b->fatal) raise_fatal(L);  // the parser's protected call returns it; the next instruction raises it again
  const size_t k = std::min(r->left, kPieceBytes);
  *size = k;
  const char* piece = r->p;
  r->p += k, r->left -= k;
  return piece;
}

}  // namespace

int load_text(lua_State* L, const char* text, size_t n, const char* chunkname, const char* mode) {
  Runtime::Budget* b = budget_of(L);
  PieceReader r{text, n, chunkname, b->calls_active > 0 ? b->cpu_start_s : thread_cpu_seconds()};
  return lua_load(L, read_piece, &r, chunkname, mode);
}

void charge_or_raise(lua_State* L, double instructions, const char* what) {
  Runtime::Budget* b = budget_of(L);
  if (b->fatal) raise_fatal(L);
  if (!b->instruction_limit || !(instructions > 0)) return;
  const double left = double(b->instruction_limit - std::min(b->instructions, b->instruction_limit));
  if (!(instructions <= left)) {
    make_fatal(b, budget_message(L, b, what));
    raise_fatal(L);
  }
  b->instructions += (long long)instructions;
}

namespace {

// --- calls that catch errors: fatal ones go on up -------------------------

// Calls the original (upvalue 1) with all arguments; when it reports a
// failure (first result false) while the budget is fatal, raises instead.
int rethrowing_call(lua_State* L) {
  if (budget_of(L)->fatal) raise_fatal(L);  // nothing more runs, no handler, no __close
  // coroutine.resume runs another state: back here, this one runs again (the
  // CPU timer's signal must never reach a coroutine that may be freed).
  lua_State* const running = running_state();
  call_original(L);
  set_running_state(running);
  if (budget_of(L)->fatal && lua_gettop(L) >= 1 && lua_isboolean(L, 1) && !lua_toboolean(L, 1)) raise_fatal(L);
  return lua_gettop(L);
}

// xpcall's message handler, shielded: Lua runs the handler where the error
// was raised, and an error raised by the count hook is raised with hooks
// off, so a handler that loops would never be stopped. After a fatal stop
// the script's handler is skipped (the message goes on unchanged).
int shielded_handler(lua_State* L) {
  if (budget_of(L)->fatal) return 1;
  return call_original(L, 1);
}

// coroutine.close, nested at most kMaxCloseDepth deep: each nested close
// takes C stack that Lua 5.4.4 does not count (fixed in 5.4.5), so 20,000
// coroutines closing each other from __close crashed the process.
constexpr int kMaxCloseDepth = 100;

int bounded_close_body(lua_State* L) {
  return call_original(L);
}

int bounded_close(lua_State* L) {
  Runtime::Budget* b = budget_of(L);
  if (b->fatal) raise_fatal(L);
  if (b->close_depth >= kMaxCloseDepth)
    return luaL_error(L, "coroutine.close: nested more than %d deep (closing a coroutine from a __close that "
                         "closes another); the sandbox refuses deeper nesting", kMaxCloseDepth);
  // The original inside a protected call, so the depth is given back on the
  // way out whatever happens, then any error goes on up.
  const int n = lua_gettop(L);
  lua_pushvalue(L, lua_upvalueindex(1));
  lua_pushcclosure(L, bounded_close_body, 1);
  lua_insert(L, 1);
  ++b->close_depth;
  lua_State* const running = running_state();
  const int status = lua_pcall(L, n, LUA_MULTRET, 0);
  set_running_state(running);
  --b->close_depth;
  if (status != LUA_OK) return lua_error(L);
  if (b->fatal && lua_isboolean(L, 1) && !lua_toboolean(L, 1)) raise_fatal(L);
  return lua_gettop(L);
}

int rethrowing_xpcall(lua_State* L) {
  luaL_checktype(L, 2, LUA_TFUNCTION);
  lua_pushvalue(L, 2);
  lua_pushcclosure(L, shielded_handler, 1);
  lua_replace(L, 2);
  return rethrowing_call(L);
}

void wrap_rethrowing(lua_State* L, const char* table, const char* name) {
  if (table) lua_getglobal(L, table); else lua_pushglobaltable(L);
  lua_getfield(L, -1, name);
  if (lua_isfunction(L, -1)) {
    lua_pushcclosure(L, std::strcmp(name, "xpcall") == 0  ? rethrowing_xpcall
                        : std::strcmp(name, "close") == 0 ? bounded_close
                                                          : rethrowing_call,
                     1);
    lua_setfield(L, -2, name);
  } else {
    lua_pop(L, 1);
  }
  lua_pop(L, 1);
}

// setmetatable(t, mt) refusing a metatable with __gc: Lua runs finalizers
// with its hooks off, so an endless __gc would hang the run (or its end,
// when the state is closed) beyond any budget. An object is only ever
// finalized if its metatable had __gc when it was set, so checking here is
// enough.
int sandboxed_setmetatable(lua_State* L) {
  if (lua_type(L, 2) == LUA_TTABLE) {
    lua_pushliteral(L, "__gc");
    const bool gc = lua_rawget(L, 2) != LUA_TNIL;
    lua_pop(L, 1);
    if (gc)
      return luaL_error(L, "setmetatable: __gc metamethods (finalizers) are not available in the sandbox: Lua runs "
                           "them outside the instruction budget; close resources explicitly, or run with --trust");
  }
  return call_original(L, 1);
}

// --- C library functions charged by the size of their work ---------------

enum class Cost { rep, concat, move, shift, sort, unpack, bytes_arg1, load, collect, range, strings };

// Argument i as a number (integers and numeric strings), else `def`; kept a
// double so that no huge or NaN argument is ever converted to an integer.
double opt_num(lua_State* L, int i, double def) { return lua_isnumber(L, i) ? double(lua_tonumber(L, i)) : def; }

double span(double from, double to) { return to >= from ? to - from + 1 : 0; }

// #t as the table library will see it: a __len metamethod (script code,
// under the hook) may claim any length, and the library then loops over it.
double raw_length(lua_State* L, int i) {
  if (lua_type(L, i) != LUA_TTABLE) return 0;
  if (!luaL_getmetafield(L, i, "__len")) return double(lua_rawlen(L, i));
  lua_pop(L, 1);
  lua_len(L, i);
  const double n = lua_isnumber(L, -1) ? double(lua_tonumber(L, -1)) : 0;
  lua_pop(L, 1);
  return n;
}

double cost_of(lua_State* L, Cost c) {
  switch (c) {
    case Cost::rep: {  // string.rep(s, n [, sep]): n rounds, n * (#s + #sep) bytes
      size_t ls = 0, lsep = 0;
      if (!lua_isstring(L, 1)) return 0;
      lua_tolstring(L, 1, &ls);
      if (lua_isstring(L, 3)) lua_tolstring(L, 3, &lsep);
      const double n = std::max(0.0, opt_num(L, 2, 0));
      const Runtime::Budget* b = budget_of(L);
      // A result over the memory budget is refused by the allocator before
      // any work; an empty one ("" x n) is n rounds of work and no memory.
      if (b->limit && n * double(ls + lsep) > double(b->limit)) return 0;
      return n + n * double(ls + lsep) / kBytesPerInstruction;
    }
    case Cost::concat:  // table.concat(t [, sep [, i [, j]]]): elements visited
      return span(opt_num(L, 3, 1), opt_num(L, 4, raw_length(L, 1)));
    case Cost::move:  // table.move(a1, f, e, t [, a2])
      return span(opt_num(L, 2, 1), opt_num(L, 3, 0));
    case Cost::shift:  // table.insert(t, pos, v) / table.remove(t, pos): the elements after pos move;
                       // appending (insert(t, v)) and popping (remove(t)) move none
      if (lua_gettop(L) >= (lua_toboolean(L, lua_upvalueindex(4)) ? 2 : 3))
        return span(opt_num(L, 2, 1), raw_length(L, 1));
      return 0;
    case Cost::sort: {
      const double n = raw_length(L, 1);
      return n * std::log2(n + 2);
    }
    case Cost::unpack:  // table.unpack(t [, i [, j]])
      return span(opt_num(L, 2, 1), opt_num(L, 3, raw_length(L, 1)));
    case Cost::bytes_arg1: {  // utf8.len / utf8.offset scan their string
      size_t n = 0;
      if (lua_type(L, 1) == LUA_TSTRING) lua_tolstring(L, 1, &n);
      return double(n) / kBytesPerInstruction;
    }
    case Cost::load: {  // parsing: a byte of source costs about an instruction
      size_t n = 0;
      if (lua_type(L, 1) == LUA_TSTRING) lua_tolstring(L, 1, &n);
      return double(n);
    }
    case Cost::range: {  // string.byte / utf8.codepoint(s, i, j): one value per position, at most #s
      size_t n = 0;
      if (lua_type(L, 1) == LUA_TSTRING) lua_tolstring(L, 1, &n);
      // Negative positions count from the end, as the library reads them.
      const auto pos = [&](double p) { return p < 0 ? double(n) + p + 1 : p; };
      const double i = pos(opt_num(L, 2, 1));
      return std::min(double(n), span(std::max(i, 1.0), pos(opt_num(L, 3, i))));
    }
    case Cost::strings: {  // string.format / pack / unpack / packsize, tonumber: scan their strings
      size_t total = 0;
      for (int a = 1, top = lua_gettop(L); a <= top; ++a)
        if (lua_type(L, a) == LUA_TSTRING) total += lua_rawlen(L, a);
      return double(total) / kBytesPerInstruction;
    }
    case Cost::collect: {  // a full collection walks the whole heap
      const char* opt = lua_type(L, 1) == LUA_TSTRING ? lua_tostring(L, 1) : "collect";
      const Runtime::Budget* b = budget_of(L);
      return std::strcmp(opt, "collect") == 0 || std::strcmp(opt, "step") == 0
                 ? double(b->used) / kBytesPerInstruction
                 : 0;
    }
  }
  return 0;
}

// string.rep whose result would not fit in what is left of the memory
// budget: refused at the script's line before Lua tries (its own refusals,
// "resulting string too large" or out of memory, name no line).
void refuse_huge_rep(lua_State* L) {
  const Runtime::Budget* b = budget_of(L);
  if (!b->limit || !lua_isstring(L, 1)) return;
  size_t ls = 0, lsep = 0;
  lua_tolstring(L, 1, &ls);
  if (lua_isstring(L, 3)) lua_tolstring(L, 3, &lsep);
  const double n = opt_num(L, 2, 0);
  if (!(n > 0)) return;
  const double bytes = n * double(ls) + (n - 1) * double(lsep);
  const double left = double(b->limit) - double(std::min(b->limit, b->used + b->native));
  if (!(bytes > left)) return;
  char size[32];
  std::snprintf(size, sizeof size, "%.3g", bytes);
  luaL_error(L, "string.rep: memory budget of %d MiB exceeded: the result would take %s bytes, more than the %d MiB "
                "left; build a smaller string, or run with --trust to lift the sandbox budgets",
             int(b->limit >> 20), size, int(left / (1 << 20)));
}

int charged_call(lua_State* L) {
  const auto c = static_cast<Cost>(lua_tointeger(L, lua_upvalueindex(2)));
  const char* name = lua_tostring(L, lua_upvalueindex(3));
  if (c == Cost::rep) refuse_huge_rep(L);
  charge_or_raise(L, cost_of(L, c), name);
  return call_original_placed(L, LUA_MULTRET, name);
}

void wrap_charged(lua_State* L, const char* table, const char* name, Cost c) {
  if (table) lua_getglobal(L, table); else lua_pushglobaltable(L);
  lua_getfield(L, -1, name);
  if (!lua_isfunction(L, -1)) {
    lua_pop(L, 2);
    return;
  }
  lua_pushinteger(L, lua_Integer(c));
  if (table) lua_pushfstring(L, "%s.%s", table, name); else lua_pushstring(L, name);
  lua_pushboolean(L, std::strcmp(name, "remove") == 0);  // for Cost::shift: remove's pos is its 2nd argument
  lua_pushcclosure(L, charged_call, 4);
  lua_setfield(L, -2, name);
  lua_pop(L, 1);
}

// load(reader_function, ...): each piece the reader returns is parsed, so
// each is charged like a source string.
int charged_reader(lua_State* L) {
  Runtime::Budget* b = budget_of(L);
  if (b->cpu_limit_s > 0 && !b->fatal && thread_cpu_seconds() - b->cpu_start_s >= b->cpu_limit_s)
    make_fatal(b, cat(user_where(L), ": CPU time limit of ", b->cpu_limit_s, " s per call exceeded while Lua parsed "
                      "the chunk (a huge or deeply chained expression?); run with --trust to lift the sandbox budgets"));
  if (b->fatal) raise_fatal(L);
  lua_pushvalue(L, lua_upvalueindex(1));
  lua_call(L, 0, 1);
  size_t n = 0;
  if (lua_type(L, -1) == LUA_TSTRING) lua_tolstring(L, -1, &n);
  charge_or_raise(L, double(n), "load");
  return 1;
}

int charged_load(lua_State* L) {
  if (lua_type(L, 1) == LUA_TFUNCTION) {
    lua_pushvalue(L, 1);
    lua_pushcclosure(L, charged_reader, 1);
    lua_replace(L, 1);
  } else {
    charge_or_raise(L, cost_of(L, Cost::load), "load");
  }
  return call_original_placed(L, LUA_MULTRET, "load");
}

}  // namespace

// coroutine.wrap over the wrapped resume and close: Lua's own wrap closes a
// coroutine that died in an error right away, running its __close handlers
// on a coroutine whose hooks the count hook's error left off.
const char* kWrap = R"(
local create, resume, close, error, select = coroutine.create, coroutine.resume, coroutine.close, error, select
local function finish(co, ok, ...)
  if ok then return ... end
  local e = ...
  close(co)
  error(e, 0)
end
coroutine.wrap = function(f)
  local co = create(f)
  return function(...) return finish(co, resume(co, ...)) end
end
)";

void install_sticky_stops(lua_State* L) {
  wrap_rethrowing(L, nullptr, "pcall");
  wrap_rethrowing(L, nullptr, "xpcall");
  wrap_rethrowing(L, LUA_COLIBNAME, "resume");
  wrap_rethrowing(L, LUA_COLIBNAME, "close");
  if (luaL_loadbufferx(L, kWrap, std::strlen(kWrap), "=softcut/sandbox", "t") == LUA_OK) lua_call(L, 0, 0);
  else lua_pop(L, 1);
}

void install_sandbox_limits(lua_State* L) {
  install_sticky_stops(L);
  lua_getglobal(L, "setmetatable");
  lua_pushcclosure(L, sandboxed_setmetatable, 1);
  lua_setglobal(L, "setmetatable");
  wrap_charged(L, LUA_STRLIBNAME, "rep", Cost::rep);
  wrap_charged(L, LUA_TABLIBNAME, "concat", Cost::concat);
  wrap_charged(L, LUA_TABLIBNAME, "move", Cost::move);
  wrap_charged(L, LUA_TABLIBNAME, "insert", Cost::shift);
  wrap_charged(L, LUA_TABLIBNAME, "remove", Cost::shift);
  wrap_charged(L, LUA_TABLIBNAME, "sort", Cost::sort);
  wrap_charged(L, LUA_TABLIBNAME, "unpack", Cost::unpack);
  wrap_charged(L, LUA_STRLIBNAME, "byte", Cost::range);
  wrap_charged(L, LUA_UTF8LIBNAME, "codepoint", Cost::range);
  for (const char* f : {"format", "pack", "unpack", "packsize"}) wrap_charged(L, LUA_STRLIBNAME, f, Cost::strings);
  wrap_charged(L, nullptr, "tonumber", Cost::strings);
  wrap_charged(L, LUA_UTF8LIBNAME, "len", Cost::bytes_arg1);
  wrap_charged(L, LUA_UTF8LIBNAME, "offset", Cost::bytes_arg1);
  wrap_charged(L, nullptr, "collectgarbage", Cost::collect);
  lua_getglobal(L, "load");
  lua_pushcclosure(L, charged_load, 1);
  lua_setglobal(L, "load");
}

}  // namespace softcut::lua
