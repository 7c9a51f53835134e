#include "scenario_script.hpp"

#include <lua.hpp>

#include <memory>

#include "core/checked_file.hpp"
#include "core/error.hpp"
#include "core/printable.hpp"
#include "core/watchdog.hpp"
#include "runtime.hpp"
#include "sim/model.hpp"
#include "spec_reader.hpp"
#include "wrap_frame.hpp"

namespace fs = std::filesystem;

namespace softcut::lua {

namespace {

// Runs the script in `rt`; leaves the Scenario table on the stack and
// returns its absolute index.
int run_script(Runtime& rt, const ScriptRequest& req) {
  lua_State* L = rt.state();
  const fs::path file = fs::absolute(req.scenario).lexically_normal();
  std::string checked_text;  // read below scenario_root, before the script's state is touched
  if (!req.scenario_root.empty()) {
    const fs::path rel = req.scenario.lexically_normal().lexically_relative(req.scenario_root.lexically_normal());
    if (rel.empty() || relative_below(req.scenario_root, rel) != rel)
      fail(req.scenario.string(), ": not below ", req.scenario_root.string());
    checked_text = read_below(req.scenario_root, rel, "the scenario file", std::size_t(64) << 20);
  } else if (!fs::is_regular_file(file)) {
    fail(req.scenario.string(), ": no such scenario file");
  }
  rt.push_internal();
  lua_newtable(L);
  for (const auto& [k, v] : req.overrides) {
    lua_pushlstring(L, v.data(), v.size());
    lua_setfield(L, -2, k.c_str());
  }
  lua_setfield(L, -2, "overrides");
  lua_pushstring(L, rt.options().read_dir.c_str());  // resolved: the checked opens work below it
  lua_setfield(L, -2, "scenario_dir");
  lua_pushstring(L, file.stem().c_str());
  lua_setfield(L, -2, "scenario_stem");
  lua_pushstring(L, req.scenario.lexically_normal().c_str());
  lua_setfield(L, -2, "scenario_file");
  lua_pop(L, 1);

  // Messages name the file as the user gave it.
  if (req.scenario_root.empty()) rt.run_file(req.scenario.lexically_normal(), 1);
  else rt.run_source(std::move(checked_text), req.scenario.lexically_normal(), 1);
  const int top = lua_gettop(L);
  auto is_scenario = [L](int idx) {
    if (!lua_istable(L, idx) || !lua_getmetatable(L, idx)) return false;
    lua_pushliteral(L, "__name");
    lua_rawget(L, -2);  // raw: a script's metatable may have a metatable of its own
    const bool yes = lua_isstring(L, -1) && std::string(lua_tostring(L, -1)) == "Scenario";
    lua_pop(L, 2);
    return yes;
  };
  if (!is_scenario(top)) {
    lua_pop(L, 1);
    rt.push_internal();
    lua_getfield(L, -1, "last_scenario");
    lua_remove(L, -2);
    if (!is_scenario(-1))
      fail(file.string(), ": the script made no scenario (call softcut.scenario{ duration = ... } and return it)");
  }
  rt.push_internal();
  lua_getfield(L, -1, "params_declared");
  const bool declared = lua_toboolean(L, -1);
  lua_pop(L, 2);
  if (!req.overrides.empty() && !declared)
    fail(file.string(), ": --set ", req.overrides.begin()->first,
         "=...: the scenario declares no parameters (add local P = softcut.params{ name = default, ... })");
  return lua_gettop(L);
}

SandboxOptions sandbox_of(const ScriptRequest& req) {
  SandboxOptions opt = req.sandbox;
  opt.write_dir.clear();  // no writes before confine_writes(): the output folder is made after the script ran
  if (req.watchdog && req.watchdog->seconds() > 0)
    opt.deadline = &req.watchdog->expired(), opt.timeout_s = req.watchdog->seconds();
  // Resolved once: the checked opens then work below the real folder, and
  // any link below it is refused.
  std::error_code ec;
  const fs::path folder = fs::absolute(req.scenario).lexically_normal().parent_path();
  opt.read_dir = fs::canonical(folder, ec);
  if (ec) opt.read_dir = folder;
  return opt;
}

// luaL_ref of the value on top of the stack inside a protected call (the
// registry may grow: out of memory there must not be a Lua panic).
int protected_ref(lua_State* L) {
  if (!lua_checkstack(L, 2)) fail("out of Lua stack space");
  lua_pushcfunction(L, [](lua_State* L) -> int {
    lua_pushinteger(L, luaL_ref(L, LUA_REGISTRYINDEX));
    return 1;
  });
  lua_insert(L, -2);
  if (lua_pcall(L, 1, 1, 0) != LUA_OK) {
    lua_pop(L, 1);
    fail("memory budget exceeded while preparing the frame loop (run with --trust to lift the sandbox budgets)");
  }
  const int ref = int(lua_tointeger(L, -1));
  lua_pop(L, 1);
  return ref;
}

// One on_frame call: after_frame(scenario, frame handle, frame, time, dt,
// number of nodes), made inside Runtime::call's protected call.
struct FrameCall {
  int fn_ref, s_ref;
  const sim::Model* model;
  sim::State* state;
  FrameContext* ctx = nullptr;
  int expectation = -1;  // >= 0: run_check of this expectation (0-based), 2 results
};

int frame_trampoline(lua_State* L) {
  auto* fc = static_cast<FrameCall*>(lua_touserdata(L, 1));
  lua_rawgeti(L, LUA_REGISTRYINDEX, fc->fn_ref);
  lua_rawgeti(L, LUA_REGISTRYINDEX, fc->s_ref);
  FrameContext* ctx = push_frame_context(L);
  ctx->model = fc->model;
  ctx->state = fc->state;
  fc->ctx = ctx;
  lua_pushinteger(L, fc->state->frame);
  lua_pushnumber(L, fc->state->time);
  lua_pushnumber(L, fc->model->dt);
  lua_pushinteger(L, lua_Integer(fc->state->displacement.rows()));  // grows when cutting adds nodes
  if (fc->expectation < 0) {
    lua_call(L, 6, 1);
    return 1;
  }
  lua_pushinteger(L, fc->expectation + 1);
  lua_call(L, 7, 2);
  return 2;
}

// Calls fc's function through frame_trampoline inside Runtime::call's
// protected call (everything that may allocate, the frame handle and stack
// growth, happens there, so running out of memory is an error of the run, not
// a Lua panic) and leaves its `results` values on the stack. The frame handle
// goes stale on return: one the script keeps cannot reach the State.
void call_frame(Runtime& rt, lua_State* L, FrameCall& fc, int results, const char* what) {
  struct Reset {
    FrameCall& fc;
    ~Reset() {
      if (fc.ctx) fc.ctx->model = nullptr, fc.ctx->state = nullptr;
    }
  } reset{fc};
  if (!lua_checkstack(L, 3)) fail(what, ": out of Lua stack space");
  lua_pushcfunction(L, frame_trampoline);
  lua_pushlightuserdata(L, &fc);
  rt.call(1, results);
}

// A Lua scenario file as the run's script. The Scenario table stays on the
// Lua stack at index s_ (the main chunk's result); the frame callbacks live
// in the registry from start() on.
class LuaScenario final : public sim::ScenarioScript {
 public:
  explicit LuaScenario(const ScriptRequest& req)
      : rt_(sandbox_of(req)), source_(fs::absolute(req.scenario).lexically_normal()) {
    s_ = run_script(rt_, req);
  }

  sim::ScenarioSpec spec() override {
    lua_State* L = rt_.state();
    sim::ScenarioSpec spec = read_spec(L, s_, source_);
    // The parameters after --set, as softcut.params left them (a list of
    // {name, text} in the internal table the script cannot reach).
    rt_.push_internal();
    lua_getfield(L, -1, "params_effective");
    for (lua_Integer i = 1; lua_istable(L, -1); ++i) {
      if (lua_rawgeti(L, -1, i) != LUA_TTABLE) {
        lua_pop(L, 1);
        break;
      }
      lua_rawgeti(L, -1, 1);
      lua_rawgeti(L, -2, 2);
      if (lua_type(L, -2) == LUA_TSTRING && lua_type(L, -1) == LUA_TSTRING) {
        size_t nk = 0, nv = 0;
        const char* k = lua_tolstring(L, -2, &nk);
        const char* v = lua_tolstring(L, -1, &nv);
        // Bounded like the description: a string default may be any bytes.
        spec.params.emplace_back(printable({k, nk}, 64), printable({v, nv}, 2000));
      }
      lua_pop(L, 3);
    }
    lua_pop(L, 2);
    return spec;
  }

  void confine_writes(const fs::path& dir) override { rt_.set_write_dir(dir); }

  void start() override {
    lua_State* L = rt_.state();
    lua_pushvalue(L, s_);
    s_ref_ = protected_ref(L);
    rt_.run_string("return require('scenario').after_frame", "=softcut/after_frame", 1);
    frame_ref_ = protected_ref(L);
    rt_.run_string("return require('scenario').run_check", "=softcut/run_check", 1);
    check_ref_ = protected_ref(L);
    rt_.run_string("return require('scenario').checks_of", "=softcut/checks_of", 1);
    lua_rawgeti(L, LUA_REGISTRYINDEX, s_ref_);
    rt_.call(1, 1);
    checks_ref_ = protected_ref(L);
  }

  bool on_frame(const sim::Model& m, sim::State& st) override {
    lua_State* L = rt_.state();
    FrameCall fc{frame_ref_, s_ref_, &m, &st};
    call_frame(rt_, L, fc, 1, "on_frame");
    const bool go_on = lua_toboolean(L, -1);
    lua_pop(L, 1);
    return go_on;
  }

  // The verdict (ok, message), copied out bounded and printable (the message
  // is the script's), inside a protected call.
  std::pair<bool, std::string> check(int index, const sim::Model& m, sim::State& st) override {
    lua_State* L = rt_.state();
    FrameCall fc{check_ref_, checks_ref_, &m, &st, nullptr, index};
    call_frame(rt_, L, fc, 2, "expect");
    std::pair<bool, std::string> verdict{lua_toboolean(L, -2) != 0, ""};
    if (lua_type(L, -1) == LUA_TSTRING) {
      size_t len = 0;
      const char* text = lua_tolstring(L, -1, &len);
      verdict.second = printable(std::string(text, len), 2000);
    }
    lua_pop(L, 2);
    return verdict;
  }

 private:
  Runtime rt_;
  fs::path source_;
  int s_ = 0;
  int s_ref_ = LUA_NOREF, frame_ref_ = LUA_NOREF, check_ref_ = LUA_NOREF, checks_ref_ = LUA_NOREF;
};

}  // namespace

std::unique_ptr<sim::ScenarioScript> open_scenario(const ScriptRequest& req) {
  return std::make_unique<LuaScenario>(req);
}

}  // namespace softcut::lua
