#include "library.hpp"

#include <lua.hpp>

#include <cctype>
#include <map>
#include <mutex>
#include <string>
#include <string_view>

#include "bindings.hpp"
#include "core/checked_file.hpp"
#include "core/error.hpp"
#include "core/printable.hpp"
#include "lua_embedded.hpp"
#include "runtime.hpp"
#include "sandbox/limits.hpp"

namespace fs = std::filesystem;

namespace softcut::lua {

namespace {

const char* kLoadedKey = "softcut.loaded";

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
// Each nested require takes C stack (its protected call); Lua's own limit
// (200 C levels) ends a 300-deep chain with "C stack overflow", naming
// neither module nor file.
constexpr int kMaxRequireDepth = 50;
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
          if (!text.empty() && text[0] == LUA_SIGNATURE[0])  // Lua's own refusal names neither module nor file
            failure = cat("require '", name, "': ", printable(file), " is a precompiled (binary) Lua chunk; the "
                          "sandbox loads modules from source text only (binary chunks can crash the interpreter): "
                          "require the .lua source, or run with --trust");
        }
      } catch (const std::exception& e) {
        failure = cat("require '", name, "': ", e.what());
      }
    }
  }
  Runtime::Budget* b = budget_of(L);
  if (failure.empty() && b->require_depth >= kMaxRequireDepth)
    failure = cat("require '", name, "' (", printable(file), "): the scenario's modules require each other ",
                  kMaxRequireDepth, " deep, the sandbox's limit; flatten the chain (one module may require many)");
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
  if (load_text(L, text.data(), text.size(), lua_tostring(L, -1), "t") != LUA_OK) return lua_error(L);
  lua_remove(L, -2);  // the chunk name
  lua_pushlstring(L, file.data(), file.size());  // the chunk's second argument
  // Stack: ... chunk file
  lua_pushlightuserdata(L, const_cast<char*>(&kLoadingMark));
  lua_setfield(L, loaded, name);
  lua_pushstring(L, name);  // (name, file), as Lua's require passes them
  lua_insert(L, -2);
  ++b->require_depth;
  const int status = lua_pcall(L, 2, 1, 0);
  --b->require_depth;
  if (status != LUA_OK) {
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

void install_require(lua_State* L, const SandboxOptions& opt) {
  lua_pushcfunction(L, embedded_require);
  if (opt.trusted) {
    // Embedded modules first, then package.path / cpath as usual.
    lua_getglobal(L, "package");
    lua_getfield(L, -1, "searchers");
    lua_pushcfunction(L, [](lua_State* L) -> int {
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
    const int n = int(lua_rawlen(L, -2));
    for (int i = n; i >= 2; --i) {
      lua_rawgeti(L, -2, i);
      lua_rawseti(L, -3, i + 1);
    }
    lua_rawseti(L, -2, 2);
    lua_pop(L, 1);
    // The scenario's folder first, so `require "common"` finds the same
    // file trusted or not.
    if (!opt.read_dir.empty()) {
      lua_getfield(L, -1, "path");
      const std::string path = cat((opt.read_dir / "?.lua").string(), ";", lua_tostring(L, -1));
      lua_pop(L, 1);
      lua_pushlstring(L, path.data(), path.size());
      lua_setfield(L, -2, "path");
    }
    lua_pop(L, 1);
    lua_pop(L, 1);  // embedded_require
  } else {
    lua_setglobal(L, "require");
  }
}

void open_library(lua_State* L) {
  open_internal(L);
  push_library(L);
  lua_setglobal(L, "softcut");
}

void push_library(lua_State* L) {
  lua_pushcfunction(L, embedded_require);
  lua_pushliteral(L, "softcut");
  lua_call(L, 1, 1);
}

}  // namespace softcut::lua
