#include "runtime.hpp"

#include <lua.hpp>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <initializer_list>
#include <map>
#include <mutex>
#include <utility>

#include "bindings.hpp"
#include "core/checked_file.hpp"
#include "core/error.hpp"
#include "core/printable.hpp"
#include "lua_embedded.hpp"
#include "runtime_patterns.hpp"
#include "sandbox_limits.hpp"

namespace fs = std::filesystem;

namespace softcut::lua {

namespace {

const char* kBudgetKey = "softcut.budget";
const char* kOptionsKey = "softcut.options";
const char* kInternalKey = "softcut.internal";
const char* kLoadedKey = "softcut.loaded";

// Message handler: API misuse errors (tables {message=...}) stay one line;
// everything else gets a traceback.
int message_handler(lua_State* L) {
  if (lua_istable(L, 1)) {  // raw access: a user's error table may have any metatable
    lua_pushliteral(L, "softcut_api_error");
    lua_rawget(L, 1);
    const bool api = lua_toboolean(L, -1);
    lua_pop(L, 1);
    if (api) {
      lua_pushliteral(L, "message");
      lua_rawget(L, 1);
      return 1;
    }
  }
  const char* msg = luaL_tolstring(L, 1, nullptr);
  luaL_traceback(L, L, msg, 1);
  return 1;
}

// load(chunk [, name [, mode [, env]]]) with mode forced to text.
int sandboxed_load(lua_State* L) {
  if (lua_type(L, 1) == LUA_TSTRING) {
    size_t n = 0;
    const char* s = lua_tolstring(L, 1, &n);
    if (n > 0 && s[0] == LUA_SIGNATURE[0])
      return luaL_error(L, "load: binary chunks are refused in the sandbox (they can crash the "
                           "interpreter); load Lua source text, or run with --trust");
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
// work (runtime_patterns.hpp) and is refused when the bound exceeds what is
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
  if (w.steps <= allowed) {
    lua_pushvalue(L, lua_upvalueindex(1));
    lua_insert(L, 1);
    lua_call(L, lua_gettop(L) - 1, LUA_MULTRET);
    return lua_gettop(L);
  }
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

// The embedded library compiled once per process: every Runtime loads
// ~73 KB of Lua source, and parsing it dominated the cost of a fresh state
// (the lua fuzz target makes one per input). The bytecode is dumped from our
// own source with its debug info (messages keep softcut/<name>.lua:line) and
// never comes from a script, so loading it as binary is safe in the sandbox.
struct BytecodeCache {
  std::mutex mutex;
  std::map<std::string, std::string, std::less<>> chunks;  // module name -> lua_dump output
};

BytecodeCache& bytecode_cache() {
  static BytecodeCache cache;
  return cache;
}

int dump_writer(lua_State*, const void* p, size_t n, void* ud) {
  try {
    static_cast<std::string*>(ud)->append(static_cast<const char*>(p), n);
    return 0;
  } catch (...) {  // no exception may cross Lua's C frames; the cache just stays empty
    return 1;
  }
}

// Pushes the compiled chunk of `s` (or its load error): status as luaL_loadbufferx.
int load_embedded(lua_State* L, const EmbeddedScript& s, const char* chunkname) {
  BytecodeCache& cache = bytecode_cache();
  {
    std::lock_guard<std::mutex> lock(cache.mutex);
    auto it = cache.chunks.find(s.name);
    if (it != cache.chunks.end())
      return luaL_loadbufferx(L, it->second.data(), it->second.size(), chunkname, "b");
  }
  const int status = luaL_loadbufferx(L, s.source.data(), s.source.size(), chunkname, "t");
  if (status != LUA_OK) return status;
  std::string code;
  if (lua_dump(L, dump_writer, &code, 0) == 0) {
    std::lock_guard<std::mutex> lock(cache.mutex);
    cache.chunks.emplace(std::string(s.name), std::move(code));
  }
  return status;
}

// A module name of the scenario's own: dotted words ("common",
// "lib.organs"), nothing a path could hide in ("..", "/", "~").
bool is_module_name(std::string_view name) {
  if (name.empty() || name.size() > 200) return false;
  bool word_start = true;
  for (const char c : name) {
    if (c == '.') {
      if (word_start) return false;
      word_start = true;
    } else if (std::isalnum(static_cast<unsigned char>(c)) || c == '_') {
      if (word_start && std::isdigit(static_cast<unsigned char>(c))) return false;
      word_start = false;
    } else {
      return false;
    }
  }
  return !word_start;
}

constexpr std::size_t kMaxModuleBytes = 8u << 20;
const char kLoadingMark = 0;  // its address marks a module whose chunk is running (a cycle)

// The module's value on top of the stack: nil becomes true (as in Lua's
// require), kept in the cache table at `loaded` under `name`, and returned.
int keep_loaded(lua_State* L, int loaded, const char* name) {
  if (lua_isnil(L, -1)) {
    lua_pop(L, 1);
    lua_pushboolean(L, 1);
  }
  lua_pushvalue(L, -1);
  lua_setfield(L, loaded, name);
  return 1;
}

// The rest of require(name) after the embedded library: `name.lua` (dots are
// folders) read below the scenario's folder through the checked open (no
// link, no "..": is_module_name), loaded as text, run once with (name, file)
// like Lua's own require and cached; budgets apply as to the script itself.
// Lua raises errors with longjmp, so every C++ object lives in a scope that
// has ended before any Lua call or error.
int user_require(lua_State* L, const char* name, int loaded) {
  // Kept in thread-local strings, which no longjmp skips the destructor of.
  static thread_local std::string failure, file, text;
  failure.clear(), text.clear();
  {
    const SandboxOptions& opt = options_of(L);
    std::string rel = name, names;
    std::replace(rel.begin(), rel.end(), '.', '/');
    rel += ".lua";
    for (const EmbeddedScript& s : embedded_scripts()) names += cat(names.empty() ? "" : ", ", s.name);
    file = (opt.read_dir / rel).string();
    if (!is_module_name(name)) {
      failure = cat("require: '", printable(name, 80), "' is not a module name (words of letters, digits and '_' "
                    "joined by '.': require \"common\" loads common.lua, \"lib.organs\" lib/organs.lua, below "
                    "the scenario's folder)");
    } else if (opt.read_dir.empty()) {
      failure = cat("require: no module '", name, "' (not in the embedded library: ", names, ")");
    } else {
      try {
        int missing = 0;
        const UniqueFd fd = open_below_if_exists(opt.read_dir, rel, Access::read, "module", &missing);
        if (!fd) {
          failure = cat("require: no module '", name, "': not in the embedded library (", names, ") and no ", file,
                        " below the scenario's folder");
        } else {
          text = read_whole(fd, "module", file, kMaxModuleBytes);
          if (!text.empty() && text[0] == '#') text.insert(0, "--");  // a shebang line stays a comment, as Lua does
        }
      } catch (const std::exception& e) {
        failure = cat("require '", name, "': ", e.what());
      }
    }
  }
  if (!failure.empty()) {
    luaL_where(L, 1);
    lua_pushlstring(L, failure.data(), failure.size());
    lua_concat(L, 2);
    return lua_error(L);
  }
  // Parsing is the script's work, as load()'s is: about an instruction a byte
  // (a module that fails or returns false is read again by the next require).
  charge_or_raise(L, double(text.size()), "require");
  lua_pushliteral(L, "@");
  lua_pushlstring(L, file.data(), file.size());
  lua_concat(L, 2);  // the chunk name
  if (luaL_loadbufferx(L, text.data(), text.size(), lua_tostring(L, -1), "t") != LUA_OK) return lua_error(L);
  lua_remove(L, -2);  // the chunk name
  lua_pushlstring(L, file.data(), file.size());  // the chunk's second argument
  // Stack: ... chunk file
  lua_pushlightuserdata(L, const_cast<char*>(&kLoadingMark));
  lua_setfield(L, loaded, name);
  lua_pushstring(L, name);  // (name, file), as Lua's require passes them
  lua_insert(L, -2);
  if (lua_pcall(L, 2, 1, 0) != LUA_OK) {
    lua_pushnil(L);  // not loaded: a later require tries again
    lua_setfield(L, loaded, name);
    return lua_error(L);  // the module's own error, unchanged
  }
  return keep_loaded(L, loaded, name);
}

// require(name) for the embedded library: chunk "=softcut/<name>.lua",
// called with (name, internal) so library modules reach the C bindings.
int embedded_require(lua_State* L) {
  const char* name = luaL_checkstring(L, 1);
  // Own cache, not package.loaded: that one holds the full os / io libraries
  // (luaL_requiref registers them there), which the sandbox must not hand out.
  luaL_getsubtable(L, LUA_REGISTRYINDEX, kLoadedKey);
  const int loaded = lua_gettop(L);
  lua_getfield(L, loaded, name);
  if (lua_touserdata(L, -1) == &kLoadingMark) {
    luaL_where(L, 1);
    lua_pushfstring(L, "require: module '%s' requires itself, directly or through other modules (a cycle)", name);
    lua_concat(L, 2);
    return lua_error(L);
  }
  if (lua_toboolean(L, -1)) return 1;
  lua_pop(L, 1);
  for (const EmbeddedScript& s : embedded_scripts()) {
    if (s.name != name) continue;
    int status;
    {
      const std::string chunk = cat("=softcut/", s.name, ".lua");
      status = load_embedded(L, s, chunk.c_str());
    }  // no C++ object alive across lua_error
    if (status != LUA_OK) return lua_error(L);
    lua_pushstring(L, name);
    lua_getfield(L, LUA_REGISTRYINDEX, kInternalKey);
    lua_call(L, 2, 1);
    return keep_loaded(L, loaded, name);
  }
  return user_require(L, name, loaded);
}

int where_binding(lua_State* L) {
  const std::string w = user_where(L);
  lua_pushlstring(L, w.data(), w.size());
  return 1;
}

void open_internal(lua_State* L) {
  lua_newtable(L);
  lua_pushcfunction(L, where_binding);
  lua_setfield(L, -2, "where");
  open_bindings(L);  // fills the table on top with the engine bindings
  lua_setfield(L, LUA_REGISTRYINDEX, kInternalKey);
}

}  // namespace

const SandboxOptions& options_of(lua_State* L) {
  lua_getfield(L, LUA_REGISTRYINDEX, kOptionsKey);
  auto* opt = static_cast<const SandboxOptions*>(lua_touserdata(L, -1));
  lua_pop(L, 1);
  return *opt;
}

double max_tets(lua_State* L) {
  const SandboxOptions& opt = options_of(L);
  return opt.trusted ? HUGE_VAL : opt.max_tets;
}

void charge_work(lua_State* L, double instructions, const std::string& what) {
  Runtime::Budget* b = budget_of(L);
  // The script's work: while a call into it runs (from any of its frames,
  // coroutines and load()ed chunks included) and while the engine reads the
  // tables it left (a list shared a thousand times is copied a thousand times).
  if (!b->instruction_limit || !(b->calls_active > 0 || b->reading_spec)) return;
  b->instructions += static_cast<long long>(std::min(instructions, 1e15));
  if (b->instructions > b->instruction_limit) {
    std::string msg = cat(user_where(L), ": ", what, ": instruction budget of ", b->instruction_limit,
                          " instructions exceeded (engine work such as generating meshes, evaluating selections and "
                          "reading the scenario's lists counts too; a loop of them?); run with --trust to lift the "
                          "sandbox budgets");
    if (!b->fatal) b->fatal = true, b->fatal_message = msg;  // sticky, like the hook's
    throw Error(msg);
  }
}

void charge_memory(lua_State* L, std::size_t bytes, const std::string& what) {
  Runtime::Budget* b = budget_of(L);
  const auto fits = [&] { return !b->limit || b->used + b->native + bytes <= b->limit; };
  // The collector paces itself by the Lua heap alone: a step sized by the
  // engine memory lets dead handles go over time, and a full collection runs
  // before a charge is refused (their __gc gives their memory back).
  lua_gc(L, LUA_GCSTEP, int(std::min<std::size_t>(bytes >> 10, 1 << 20)));
  if (!fits()) lua_gc(L, LUA_GCCOLLECT);
  if (!fits())
    fail(what, ": memory budget of ", b->limit >> 20, " MiB exceeded: this mesh needs ", (bytes + (1 << 20) - 1) >> 20,
         " MiB next to ", (b->used + b->native) >> 20, " MiB of Lua data and meshes the scenario holds (meshes kept "
         "in a loop?); run with --trust to lift the sandbox budgets");
  b->native += bytes;
}

void release_memory(lua_State* L, std::size_t bytes) {
  Runtime::Budget* b = budget_of(L);
  b->native -= std::min(bytes, b->native);
}

bool may_read(lua_State* L, const fs::path& path) {
  const SandboxOptions& opt = options_of(L);
  return opt.trusted || !relative_below(opt.read_dir, path).empty();
}

std::string user_where(lua_State* L) {
  // At most kWhereLevels frames: lua_getstack(L, n) walks n frames itself,
  // so a scan of a 1e5-deep recursion would cost 1e10 steps per message.
  constexpr int kWhereLevels = 64;
  lua_Debug ar;
  for (int level = 0; level < kWhereLevels && lua_getstack(L, level, &ar); ++level) {
    lua_getinfo(L, "Sl", &ar);
    if (ar.source && ar.source[0] == '@' && ar.currentline > 0)
      return cat(ar.source + 1, ":", ar.currentline);  // the full name (short_src cuts at 60 chars)
  }
  return "?";
}

std::string user_prefix(lua_State* L) {
  const std::string w = user_where(L);
  return w == "?" ? std::string() : w + ": ";
}

int protect(lua_State* L, const std::function<int()>& f) {
  bool failed = false;
  {
    std::string msg;
    try {
      return f();
    } catch (const std::exception& e) {
      msg = e.what();
      failed = true;
    } catch (...) {
      msg = "unknown C++ exception";
      failed = true;
    }
    lua_pushlstring(L, msg.data(), msg.size());
  }  // msg destroyed before the longjmp below
  (void)failed;
  return lua_error(L);
}

void push_library(lua_State* L) {
  lua_pushcfunction(L, embedded_require);
  lua_pushliteral(L, "softcut");
  lua_call(L, 1, 1);
}

Runtime::Runtime(const SandboxOptions& opt) : opt_(opt), budget_(new Budget) {
  if (!opt_.trusted) {
    budget_->limit = opt_.memory_budget;
    budget_->instruction_limit = opt_.instruction_budget;
  }
  L_ = lua_newstate(budget_alloc, budget_);
  if (!L_) {
    delete budget_;
    fail("lua: cannot create a Lua state (out of memory)");
  }
  // A Lua error outside any protected call (there should be none) ends the
  // process with a message instead of abort().
  lua_atpanic(L_, [](lua_State* L) -> int {
    const char* m = lua_tostring(L, -1);
    std::fprintf(stderr, "softcut: error: Lua error outside a protected call: %s\n", m ? m : "(no message)");
    std::fflush(stderr);
    std::_Exit(1);
  });
  lua_pushlightuserdata(L_, &opt_);
  lua_setfield(L_, LUA_REGISTRYINDEX, kOptionsKey);
  lua_pushlightuserdata(L_, budget_);
  lua_setfield(L_, LUA_REGISTRYINDEX, kBudgetKey);
  if (opt_.trusted) {
    luaL_openlibs(L_);
    install_sticky_stops(L_);
  } else {
    open_sandbox(L_);
  }
  lua_pushcfunction(L_, embedded_require);
  if (opt_.trusted) {
    // Embedded modules first, then package.path / cpath as usual.
    lua_getglobal(L_, "package");
    lua_getfield(L_, -1, "searchers");
    lua_pushcfunction(L_, [](lua_State* L) -> int {
      const char* name = luaL_checkstring(L, 1);
      for (const EmbeddedScript& s : embedded_scripts())
        if (s.name == name) {
          lua_pushcfunction(L, embedded_require);
          lua_pushnil(L);
          return 2;
        }
      lua_pushfstring(L, "no embedded module '%s'", name);
      return 1;
    });
    // shift searchers up by one and insert at 2 (after preload)
    const int n = int(lua_rawlen(L_, -2));
    for (int i = n; i >= 2; --i) {
      lua_rawgeti(L_, -2, i);
      lua_rawseti(L_, -3, i + 1);
    }
    lua_rawseti(L_, -2, 2);
    lua_pop(L_, 1);
    // The scenario's folder first, so `require "common"` finds the same
    // file trusted or not.
    if (!opt_.read_dir.empty()) {
      lua_getfield(L_, -1, "path");
      const std::string path = cat((opt_.read_dir / "?.lua").string(), ";", lua_tostring(L_, -1));
      lua_pop(L_, 1);
      lua_pushlstring(L_, path.data(), path.size());
      lua_setfield(L_, -2, "path");
    }
    lua_pop(L_, 1);
    lua_pop(L_, 1);  // embedded_require
  } else {
    lua_setglobal(L_, "require");
  }
  budget_->interrupt = opt_.interrupt;
  budget_->deadline = opt_.deadline;
  budget_->timeout_s = opt_.timeout_s;
  if (!opt_.trusted) budget_->output = opt_.output;
  if (!opt_.trusted || opt_.interrupt || opt_.deadline) lua_sethook(L_, count_hook, LUA_MASKCOUNT, kHookInterval);
  try {
    lua_pushcfunction(L_, [](lua_State* L) -> int {
      open_internal(L);
      push_library(L);
      lua_setglobal(L, "softcut");
      return 0;
    });
    call(0, 0);
  } catch (...) {
    lua_close(L_);
    delete budget_;
    throw;
  }
}

Runtime::~Runtime() {
  lua_close(L_);
  delete budget_;
}

bool Runtime::stopped() const { return budget_->fatal; }

void Runtime::push_internal() { lua_getfield(L_, LUA_REGISTRYINDEX, kInternalKey); }

std::size_t Runtime::memory_used() const { return budget_->used + budget_->native; }
long long Runtime::instructions_used() const { return budget_->instructions; }

void Runtime::call(int nargs, int nresults) {
  if (budget_->fatal) {  // sticky: nothing runs after the budget, an interrupt or the deadline
    lua_pop(L_, nargs + 1);
    throw Error(budget_->fatal_message);
  }
  const int base = lua_gettop(L_) - nargs;  // index of the function
  lua_pushcfunction(L_, message_handler);
  lua_insert(L_, base);
  budget_->memory_exceeded = false;
  budget_->instructions = 0;  // the budget is per entry from C++ (main chunk, each on_frame)
  ++budget_->calls_active;
  const int status = lua_pcall(L_, nargs, nresults, base);
  --budget_->calls_active;
  lua_remove(L_, base);
  if (status == LUA_OK) return;
  std::string msg;
  if (status == LUA_ERRMEM || budget_->memory_exceeded) {
    msg = cat(chunk_.empty() ? "" : chunk_ + ": ", "memory budget of ", budget_->limit >> 20,
              " MiB exceeded by the scenario's Lua data and meshes (a huge table or string?); "
              "run with --trust to lift the sandbox budgets");
    if (status != LUA_ERRMEM) msg += cat(" [", lua_tostring(L_, -1) ? lua_tostring(L_, -1) : "", "]");
  } else {
    const char* m = lua_tostring(L_, -1);
    msg = m ? m : "(error object is not a string)";
  }
  // A fatal stop is what ends the call, whatever the script raised after it.
  if (budget_->fatal && msg.find(budget_->fatal_message) == std::string::npos) msg = budget_->fatal_message;
  // A script chooses its error's size: it reaches the summary and the
  // terminal bounded.
  constexpr std::size_t kMaxMessage = 8192;
  if (msg.size() > kMaxMessage) msg = cat(msg.substr(0, kMaxMessage), "... (", msg.size(), " bytes, cut)");
  lua_pop(L_, 1);
  throw Error(msg);
}

void Runtime::run_file(const fs::path& path, int nresults) {
  chunk_ = path.string();
  const std::string chunk = "@" + path.string();
  std::string text = read_regular_file(path, "the scenario file");
  if (!text.empty() && text[0] == '#') text.insert(0, "--");  // shebang line stays a comment
  if (luaL_loadbufferx(L_, text.data(), text.size(), chunk.c_str(), opt_.trusted ? "bt" : "t") != LUA_OK) {
    std::string msg = lua_tostring(L_, -1);
    lua_pop(L_, 1);
    // Errors raised outside the parser's position tracking (nesting deeper
    // than Lua's C-level limit) come without the file: name it.
    if (msg.rfind(path.string(), 0) != 0)
      msg = cat(path.string(), ": ", msg,
                msg.find("C stack overflow") != std::string::npos ? " (the script nests too deeply; flatten it)" : "");
    throw Error(msg);
  }
  call(0, nresults);
}

void Runtime::run_string(std::string_view code, const std::string& chunkname, int nresults) {
  if (luaL_loadbufferx(L_, code.data(), code.size(), chunkname.c_str(), opt_.trusted ? "bt" : "t") != LUA_OK) {
    std::string msg = lua_tostring(L_, -1);
    lua_pop(L_, 1);
    throw Error(msg);
  }
  call(0, nresults);
}

}  // namespace softcut::lua
