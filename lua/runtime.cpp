#include "runtime.hpp"

#include <lua.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string_view>

#include "core/checked_file.hpp"
#include "core/error.hpp"
#include "library.hpp"
#include "sandbox/limits.hpp"
#include "sandbox/policy.hpp"

namespace fs = std::filesystem;

namespace softcut::lua {

namespace {

const char* kBudgetKey = "softcut.budget";
const char* kOptionsKey = "softcut.options";

// "attempt to call a nil value (method 'grasp')" when the name was just
// looked up on a softcut object or namespace and missed: the library's
// did-you-mean instead (check.lua, explain_call), else the message as is.
void explain_missing_call(lua_State* L, std::string& msg) {
  std::string kind, key;
  for (const char* k : {"method", "field"}) {
    const std::string head = cat("attempt to call a nil value (", k, " '");
    const size_t at = msg.find(head);
    if (at == std::string::npos) continue;
    const size_t from = at + head.size(), to = msg.find("')", from);
    if (to == std::string::npos || to - from > 200) return;
    kind = k, key = msg.substr(from, to - from);
    const std::string where = user_where(L);
    lua_getfield(L, LUA_REGISTRYINDEX, kInternalKey);
    lua_getfield(L, -1, "explain_call");
    lua_remove(L, -2);
    lua_pushstring(L, kind.c_str());
    lua_pushlstring(L, key.data(), key.size());
    lua_pushlstring(L, where.data(), where.size());
    if (lua_pcall(L, 3, 1, 0) == LUA_OK && lua_type(L, -1) == LUA_TSTRING) msg = msg.substr(0, at) + lua_tostring(L, -1);
    lua_pop(L, 1);
    return;
  }
}

// "stack traceback:" with the script's frames only: the library's own
// (=softcut/...) and C functions are left out (they say nothing about the
// user's code). At most the innermost kLevels frames are walked
// (lua_getstack walks from the top: a deep recursion costs depth^2 else).
std::string user_traceback(lua_State* L, int level) {
  constexpr int kLevels = 64, kShown = 20;
  std::string out = "stack traceback:";
  lua_Debug ar, caller;
  const auto hidden = [](const lua_Debug& d) {
    return *d.what == 'C' || std::string_view(d.source).rfind("=softcut", 0) == 0;
  };
  int shown = 0, lv = level;
  for (; lv < level + kLevels && shown < kShown && lua_getstack(L, lv, &ar); ++lv) {
    lua_getinfo(L, "Sln", &ar);
    if (hidden(ar)) continue;
    out += cat("\n\t", ar.short_src, ":", ar.currentline, ": in ");
    // A function's name comes from its caller's code: the library's local
    // 'fn' says nothing to the script's author.
    const bool named = ar.name && lua_getstack(L, lv + 1, &caller) && lua_getinfo(L, "S", &caller) && !hidden(caller);
    if (*ar.what == 'm') out += "main chunk";
    else if (named) out += cat(*ar.namewhat ? ar.namewhat : "function", " '", ar.name, "'");
    else out += cat("function <", ar.short_src, ":", ar.linedefined, ">");
    ++shown;
  }
  if (lua_getstack(L, lv, &ar)) out += "\n\t...";
  return out;
}

// Message handler: API misuse errors (tables {message=...}) stay one line;
// everything else gets the script's traceback.
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
  {
    std::string msg;
    if (lua_type(L, 1) == LUA_TSTRING || lua_type(L, 1) == LUA_TNUMBER || luaL_getmetafield(L, 1, "__tostring")) {
      if (lua_gettop(L) > 1) lua_pop(L, 1);  // the __tostring field
      size_t n = 0;
      const char* m = luaL_tolstring(L, 1, &n);
      msg.assign(m, n);
      lua_pop(L, 1);
      if (lua_type(L, 1) == LUA_TSTRING) {
        if (!budget_of(L)->fatal) explain_missing_call(L, msg);
      } else {  // error(42): Lua adds no position to a value that is not a string
        msg.insert(0, user_prefix(L));
      }
    } else {
      // error({}) or error(): Lua would print "table: 0x55..." or "nil".
      msg = cat(user_prefix(L), "error raised with ", luaL_typename(L, 1), " as its message; pass a string, e.g. "
                "error(\"what went wrong\")", lua_type(L, 1) == LUA_TTABLE ? ", or give the table a __tostring metamethod" : "");
    }
    msg += "\n" + user_traceback(L, 1);
    lua_pushlstring(L, msg.data(), msg.size());
  }
  return 1;
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

Runtime::Runtime(const SandboxOptions& opt) : opt_(opt), budget_(new Budget) {
  if (!opt_.trusted) {
    budget_->limit = opt_.memory_budget;
    budget_->instruction_limit = opt_.instruction_budget;
    budget_->cpu_limit_s = std::max(0.0, opt_.cpu_seconds);
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
  install_require(L_, opt_);
  budget_->interrupt = opt_.interrupt;
  budget_->deadline = opt_.deadline;
  budget_->timeout_s = opt_.timeout_s;
  if (!opt_.trusted) budget_->output = opt_.output;
  if (!opt_.trusted || opt_.interrupt || opt_.deadline) lua_sethook(L_, count_hook, LUA_MASKCOUNT, kHookInterval);
  try {
    lua_pushcfunction(L_, [](lua_State* L) -> int {
      open_library(L);
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
  const bool outermost = budget_->calls_active == 0;
  if (outermost) begin_call(L_, budget_);  // and the CPU time
  ++budget_->calls_active;
  const int status = lua_pcall(L_, nargs, nresults, base);
  --budget_->calls_active;
  if (outermost) end_call(budget_);
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
  run_source(read_regular_file(path, "the scenario file"), path, nresults);
}

void Runtime::run_source(std::string text, const fs::path& path, int nresults) {
  chunk_ = path.string();
  const std::string chunk = "@" + path.string();
  if (!text.empty() && text[0] == '#') text.insert(0, "--");  // shebang line stays a comment
  if (load_text(L_, text.data(), text.size(), chunk.c_str(), opt_.trusted ? "bt" : "t") != LUA_OK) {
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
  if (load_text(L_, code.data(), code.size(), chunkname.c_str(), opt_.trusted ? "bt" : "t") != LUA_OK) {
    std::string msg = lua_tostring(L_, -1);
    lua_pop(L_, 1);
    throw Error(msg);
  }
  call(0, nresults);
}

}  // namespace softcut::lua
