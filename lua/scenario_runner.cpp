#include "scenario_runner.hpp"

#include <lua.hpp>

#include <algorithm>
#include <limits>
#include <memory>

#include "convert.hpp"
#include "core/checked_file.hpp"
#include "core/error.hpp"
#include "core/output_budget.hpp"
#include "core/printable.hpp"
#include "core/watchdog.hpp"
#include "gpu/egl_context.hpp"
#include "render/frame_writer.hpp"
#include "runtime.hpp"
#include "sandbox_limits.hpp"
#include "sim/model.hpp"
#include "sim/outputs.hpp"
#include "wrap_frame.hpp"
#include "wrap_mesh.hpp"

namespace fs = std::filesystem;

namespace softcut::lua {

namespace {

// Pushes t[key] and returns its type (raw access: plain data tables).
int push_field(lua_State* L, int idx, const char* key) {
  idx = lua_absindex(L, idx);
  if (lua_type(L, idx) != LUA_TTABLE)  // a script may put anything where a table belongs
    fail("expected a table with field '", key, "', got ", lua_typename(L, lua_type(L, idx)));
  lua_pushstring(L, key);
  return lua_rawget(L, idx);
}

// Calls fn(table at idx_item) for each entry of list t[key].
template <class Fn>
void each(lua_State* L, int idx, const char* key, Fn&& fn) {
  if (push_field(L, idx, key) == LUA_TTABLE) {
    const auto n = static_cast<lua_Integer>(lua_rawlen(L, -1));  // raw: no metamethod runs outside a pcall
    for (lua_Integer i = 1; i <= n; ++i) {
      if (lua_rawgeti(L, -1, i) != LUA_TTABLE) fail("scenario field '", key, "' entry ", i, " is not a table");
      fn(lua_gettop(L));
      lua_pop(L, 1);
    }
  }
  lua_pop(L, 1);
}

// The name, source position and region every region assignment (s:material,
// s:prestress) carries.
template <class Assignment>
Assignment region_assignment(lua_State* L, int m) {
  Assignment a;
  a.name = get_string(L, m, "name");
  a.where = get_string(L, m, "where");
  push_field(L, m, "region");
  a.tets = to_tet_selector(L, -1);
  lua_pop(L, 1);
  return a;
}

sim::ScenarioSpec spec_from_table(lua_State* L, int s, const fs::path& source) {
  sim::ScenarioSpec spec;
  const std::string where = get_string(L, s, "where");
  spec.name = get_string(L, s, "name", "scenario");
  spec.source = source;
  spec.versions["lua"] = LUA_RELEASE;
  spec.timeline.duration = get_number(L, s, "duration", 1.0);
  spec.timeline.frame_rate = get_number(L, s, "fps", 30.0);

  if (push_field(L, s, "_mesh") != LUA_TTABLE) fail(where, ": scenario: no mesh (add s:mesh{ file = ... } or s:mesh{ generate = ... })");
  push_field(L, -1, "handle");
  const MeshHandle* h = to_mesh_handle(L, -1);
  if (!h) fail(where, ": scenario: mesh handle missing");
  // The mesh the script loaded is passed on: compile never opens the file
  // again (outside the sandbox's checked open).
  spec.mesh = h->source;
  spec.mesh.preloaded = std::make_shared<const mesh::TetMesh>(h->loaded.mesh);
  spec.mesh.preloaded_sets = h->loaded.named_sets;
  spec.mesh.preloaded_warnings = h->warnings;
  lua_pop(L, 2);

  each(L, s, "_materials", [&](int m) {
    auto a = region_assignment<sim::MaterialAssignment>(L, m);
    a.preset = get_string(L, m, "tissue");
    a.young = get_number(L, m, "young", 0.0);
    a.poisson = get_number(L, m, "poisson", -2.0);
    spec.materials.push_back(a);
  });

  each(L, s, "_prestress", [&](int m) {
    auto a = region_assignment<sim::PrestressAssignment>(L, m);
    const double xx = get_number(L, m, "xx", 0.0), yy = get_number(L, m, "yy", 0.0), zz = get_number(L, m, "zz", 0.0);
    const double yz = get_number(L, m, "yz", 0.0), zx = get_number(L, m, "zx", 0.0), xy = get_number(L, m, "xy", 0.0);
    a.strain << xx, xy, zx, xy, yy, yz, zx, yz, zz;
    spec.prestress.push_back(a);
  });

  push_field(L, s, "_operational");
  spec.operational = to_tet_selector(L, -1);
  lua_pop(L, 1);

  std::vector<sim::NodeSelector> fixed;
  each(L, s, "_fixed", [&](int f) {
    push_field(L, f, "sel");
    fixed.push_back(to_node_selector(L, -1));
    lua_pop(L, 1);
  });
  if (fixed.empty())
    fail(where, ": scenario: no fixed nodes, so the body can float away (the stiffness matrix is singular); "
                "add s:fix{ nodes = softcut.select... }");
  if (fixed.size() == 1) {
    spec.fixed = fixed[0];
  } else {
    spec.fixed.kind = sim::NodeSelector::Kind::union_of;
    spec.fixed.children = fixed;
    spec.fixed.where = fixed[0].where;
  }

  each(L, s, "_loads", [&](int l) {
    sim::LoadSpec ls;
    ls.name = get_string(L, l, "name");
    ls.where = get_string(L, l, "where");
    push_field(L, l, "nodes");
    ls.nodes = to_node_selector(L, -1);
    lua_pop(L, 1);
    ls.direction_kind = get_string(L, l, "kind") == "normal" ? sim::LoadSpec::Direction::normal
                                                             : sim::LoadSpec::Direction::world;
    ls.direction = get_vec3(L, l, "direction", ls.direction);
    push_field(L, l, "magnitude");
    ls.magnitude = to_ramp(L, -1);
    lua_pop(L, 1);
    ls.per_node = get_bool(L, l, "per_node", false);
    spec.loads.push_back(ls);
  });

  // Expectations: bounds are checked by the engine, check functions through
  // RunHooks::check (after_frame's run_check), by their index in this list.
  each(L, s, "_expect", [&](int e) {
    sim::ExpectationSpec es;  // name and where are the script's: bounded and printable for the terminal
    es.name = printable(get_string(L, e, "name"), 2000);
    es.where = printable(get_string(L, e, "where"), 2000);
    es.at = get_number(L, e, "at", 0.0);
    es.bounds = has_field(L, e, "nodes");
    if (es.bounds) {
      push_field(L, e, "nodes");
      es.nodes = to_node_selector(L, -1);
      lua_pop(L, 1);
      es.measure = get_string(L, e, "measure") == "max" ? sim::ExpectationSpec::Measure::max
                                                        : sim::ExpectationSpec::Measure::mean;
      const std::string c = get_string(L, e, "component");
      using C = sim::ExpectationSpec::Component;
      es.component = c == "x" ? C::x : c == "y" ? C::y : c == "z" ? C::z : C::magnitude;
      if (has_field(L, e, "min")) es.min = get_number(L, e, "min", 0.0);
      if (has_field(L, e, "max")) es.max = get_number(L, e, "max", 0.0);
    }
    spec.expectations.push_back(es);
  });

  each(L, s, "_tools", [&](int t) {
    tools::ToolSpec ts;
    ts.name = get_string(L, t, "name");
    ts.where = get_string(L, t, "where");
    const std::string kind = get_string(L, t, "kind");
    ts.kind = kind == "grasper"   ? tools::ToolSpec::Kind::grasper
              : kind == "scalpel" ? tools::ToolSpec::Kind::scalpel
                                  : tools::ToolSpec::Kind::probe;
    ts.drive = get_string(L, t, "drive") == "spring" ? tools::ToolSpec::Drive::spring : tools::ToolSpec::Drive::force;
    push_field(L, t, "path");
    ts.path = to_path(L, -1);
    lua_pop(L, 1);
    ts.radius = get_number(L, t, "radius", ts.radius);
    if (push_field(L, t, "force") != LUA_TNIL) ts.force = to_ramp(L, -1);
    lua_pop(L, 1);
    ts.direction = get_vec3(L, t, "direction", Eigen::Vector3d::Zero());
    ts.stiffness = get_number(L, t, "stiffness", 0.0);
    ts.active_from = get_number(L, t, "start", 0.0);
    ts.active_until = get_number(L, t, "stop", std::numeric_limits<double>::infinity());
    ts.implicit = get_bool(L, t, "implicit", ts.implicit);
    ts.blade_length = get_number(L, t, "length", ts.blade_length);
    ts.blade_axis = get_vec3(L, t, "axis", ts.blade_axis);
    ts.cut_pressure = get_number(L, t, "cut_pressure", ts.cut_pressure);
    ts.blade_back = get_vec3(L, t, "back", ts.blade_back);
    ts.shaft = get_vec3(L, t, "shaft", ts.shaft);
    spec.tools.push_back(ts);
  });

  if (push_field(L, s, "_output") == LUA_TTABLE) {
    const int o = lua_gettop(L);
    sim::OutputSpec& out = spec.outputs;
    if (push_field(L, o, "log") == LUA_TTABLE) {
      out.log_all_surface = false;
      out.log_nodes = to_node_selector(L, -1);
    }
    lua_pop(L, 1);
    out.csv = get_bool(L, o, "csv", true);
    out.vtu = get_bool(L, o, "vtu", false);
    out.vtu_every = get_int(L, o, "vtu_every", 1);
    if (push_field(L, o, "render") == LUA_TTABLE) {
      const int r = lua_gettop(L);
      sim::RenderSettings& rs = out.render;
      rs.enabled = true;
      rs.width = get_int(L, r, "width", rs.width);
      rs.height = get_int(L, r, "height", rs.height);
      rs.auto_frame = !has_field(L, r, "eye") && !has_field(L, r, "target");
      rs.azimuth_deg = get_number(L, r, "azimuth", rs.azimuth_deg);
      rs.elevation_deg = get_number(L, r, "elevation", rs.elevation_deg);
      rs.orbit_deg_per_s = get_number(L, r, "orbit", rs.orbit_deg_per_s);
      rs.eye = get_vec3(L, r, "eye", rs.eye);
      rs.target = get_vec3(L, r, "target", rs.target);
      rs.up = get_vec3(L, r, "up", rs.up);
      rs.fov_deg = get_number(L, r, "fov", rs.fov_deg);
      rs.every = get_int(L, r, "every", 1);
      rs.contact_sheet = get_bool(L, r, "contact_sheet", rs.contact_sheet);
      rs.msaa_samples = get_int(L, r, "msaa", rs.msaa_samples);
      rs.wireframe = get_bool(L, r, "wireframe", false);
      rs.show_interface = get_bool(L, r, "show_interface", rs.show_interface);
      rs.show_forces = get_bool(L, r, "show_forces", true);
      rs.show_loads = get_bool(L, r, "show_loads", false);
      rs.background = get_vec3(L, r, "background", rs.background);
      rs.style = get_string(L, r, "style", "clinical") == "paper" ? sim::RenderSettings::Style::paper
                                                                 : sim::RenderSettings::Style::clinical;
      rs.tissue_colors = get_vec3s(L, r, "tissue_colors");
      rs.cut_color = get_vec3(L, r, "cut_color", rs.cut_color);
      rs.show_inclusions = get_bool(L, r, "show_inclusions", rs.show_inclusions);
    }
    lua_pop(L, 1);
  }
  lua_pop(L, 1);

  if (push_field(L, s, "_solver") == LUA_TTABLE) {
    const int v = lua_gettop(L);
    spec.solver.cg_tolerance = get_number(L, v, "tolerance", spec.solver.cg_tolerance);
    spec.solver.cg_max_iterations = get_int(L, v, "max_iterations", 0);
    spec.solver.backend = sim::parse_backend(get_string(L, v, "backend", "auto"));
    spec.solver.storage = hybrid::parse_storage(get_string(L, v, "mode", "auto"));
    spec.solver.gpu_fp64 = get_bool(L, v, "gpu_fp64", spec.solver.gpu_fp64);
  }
  lua_pop(L, 1);
  if (push_field(L, s, "_cutting") == LUA_TTABLE) {
    const int v = lua_gettop(L);
    spec.cutting.snap_fraction = get_number(L, v, "snap_fraction", spec.cutting.snap_fraction);
    spec.cutting.min_dihedral_deg = get_number(L, v, "min_dihedral", spec.cutting.min_dihedral_deg);
  }
  lua_pop(L, 1);
  return spec;
}

// Runs the script in `rt`; leaves the Scenario table on the stack and
// returns its absolute index.
int run_script(Runtime& rt, const RunRequest& req) {
  lua_State* L = rt.state();
  const fs::path file = fs::absolute(req.scenario).lexically_normal();
  if (!fs::is_regular_file(file)) fail(req.scenario.string(), ": no such scenario file");
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

  rt.run_file(req.scenario.lexically_normal(), 1);  // messages name the file as the user gave it
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

std::string first_line(const std::string& s) { return s.substr(0, s.find('\n')); }

// spec_from_table inside lua_pcall. It reads the script's tables with raw
// access only, so no script code runs; but a Lua error raised while reading
// (out of memory) must become an Error, not a panic outside any protected call.
sim::ScenarioSpec read_spec(lua_State* L, int s, const fs::path& source) {
  struct Job {
    fs::path source;
    sim::ScenarioSpec spec;
  } job{source, {}};
  lua_pushcfunction(L, [](lua_State* L) -> int {
    auto* j = static_cast<Job*>(lua_touserdata(L, 1));
    return protect(L, [L, j] {
      j->spec = spec_from_table(L, 2, j->source);
      return 0;
    });
  });
  lua_pushlightuserdata(L, &job);
  lua_pushvalue(L, s);
  // What the engine copies out of the script's tables is charged to the
  // instruction budget like the script's own work.
  Runtime::Budget* b = budget_of(L);
  b->reading_spec = true;
  const int status = lua_pcall(L, 2, 0, 0);
  b->reading_spec = false;
  if (status != LUA_OK) {
    std::string msg = status == LUA_ERRMEM ? cat(source.filename().string(), ": memory budget exceeded while reading "
                                                 "the scenario; run with --trust to lift the sandbox budgets")
                      : lua_type(L, -1) == LUA_TSTRING ? lua_tostring(L, -1)
                                                       : "error while reading the scenario";
    lua_pop(L, 1);
    // A field the script set after its checks ran (s.duration = "long") is
    // found only here: the message names the scenario file.
    if (msg.find(source.filename().string()) == std::string::npos) msg = cat(source.string(), ": ", msg);
    throw Error(msg);
  }
  return std::move(job.spec);
}

SandboxOptions sandbox_of(const RunRequest& req, OutputBudget* output = nullptr, const Watchdog* dog = nullptr) {
  SandboxOptions opt;
  opt.output = output;
  if (dog && dog->seconds() > 0) opt.deadline = &dog->expired(), opt.timeout_s = dog->seconds();
  opt.trusted = req.trusted;
  // Resolved once: the checked opens then work below the real folder, and
  // any link below it is refused.
  std::error_code ec;
  const fs::path folder = fs::absolute(req.scenario).lexically_normal().parent_path();
  opt.read_dir = fs::canonical(folder, ec);
  if (ec) opt.read_dir = folder;
  opt.instruction_budget = req.instruction_budget;
  opt.memory_budget = req.memory_budget;
  opt.max_tets = req.max_tets;
  opt.interrupt = req.interrupt;
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

// The output folder from the final spec, made and resolved once: `--out DIR`
// as the user gave it, else renders/<name>/ with the name checked (after the
// script has run: a script may change s.name at any time) and the folder made
// below renders/ without following a link there.
fs::path make_output_folder(const RunRequest& req, const std::string& name) {
  fs::path dir;
  if (!req.out_dir.empty()) {
    std::error_code ec;
    fs::create_directories(req.out_dir, ec);
    if (ec || !fs::is_directory(req.out_dir))
      fail(req.out_dir.string(), ": cannot create the output folder (", ec ? ec.message() : "not a folder",
           "); choose another with --out or fix the path");
    dir = req.out_dir;
  } else {
    sim::check_scenario_name(name);
    const fs::path root = fs::absolute("renders");
    std::error_code ec;
    fs::create_directories(root, ec);
    if (ec) fail(root.string(), ": cannot create the output root (", ec.message(), "); choose a folder with --out");
    dir = make_folder_below(root, name, "output folder");
  }
  return fs::canonical(dir);
}

// Frame buffers of a rendered frame, bytes: colour and depth per sample,
// the resolved and read-back images and the PNG encoder's copy.
double render_bytes(const sim::RenderSettings& r) {
  const double pixels = double(r.width) * double(r.height);
  return pixels * 8.0 * std::max(1, r.msaa_samples) + pixels * 4.0 * 3.0;
}

}  // namespace

sim::ScenarioSpec load_scenario_spec(const RunRequest& req) {
  Runtime rt(sandbox_of(req));
  const int s = run_script(rt, req);
  return read_spec(rt.state(), s, fs::absolute(req.scenario).lexically_normal());
}

namespace {
RunOutcome run_watched(const RunRequest& req, const Watchdog& dog);
}

RunOutcome run_scenario(const RunRequest& req) {
  // Made before the Lua state: the watchdog outlives it, so a hang while the
  // state is closed is still ended.
  Watchdog dog(req.timeout_s, std::clamp(req.timeout_s / 10, 5.0, 60.0),
               cat(req.scenario.string(), ": the wall-clock limit of ", req.timeout_s,
                   " s (--timeout) passed and the run did not stop (stuck outside the script); exiting without "
                   "finishing the outputs"));
  try {
    return run_watched(req, dog);
  } catch (const TimeoutError&) {
    throw;
  } catch (const Error& e) {
    // The limit struck before the frame loop (the script's main chunk,
    // compile): the same exit status as a timeout in the loop.
    if (dog.expired()) throw TimeoutError(e.what());
    throw;
  }
}

namespace {

RunOutcome run_watched(const RunRequest& req, const Watchdog& dog) {
  // The run owns --out from its start: a script that fails before the
  // outputs are written must not leave the last run's summary there, where
  // it would read as this run's.
  std::error_code ec;
  if (!req.out_dir.empty() && fs::is_directory(req.out_dir, ec)) sim::clear_earlier_outputs(req.out_dir);
  OutputBudget output(req.max_output);
  Runtime rt(sandbox_of(req, &output, &dog));
  lua_State* L = rt.state();
  const int s = run_script(rt, req);
  RunOutcome out;
  sim::ScenarioSpec spec = read_spec(L, s, fs::absolute(req.scenario).lexically_normal());
  out.name = spec.name;
  out.description = get_string(L, s, "description");
  out.tolerance = get_number(L, s, "tolerance", 1e-6);
  {
    const std::string file = req.scenario.string();
    try {
      sim::check_spec(spec);  // before anything is made from it (compile checks again)
      out.out_dir = make_output_folder(req, spec.name);
    } catch (const Error& e) {
      const std::string msg = e.what();
      if (msg.rfind(file, 0) == 0) throw;
      fail(file, ": ", msg);
    }
  }
  rt.set_write_dir(out.out_dir);
  spec.outputs.dir = out.out_dir;
  spec.command_line = req.command_line;
  // The parameters after --set, as softcut.params left them (a list of
  // {name, text} in the internal table the script cannot reach).
  rt.push_internal();
  lua_getfield(L, -1, "params_effective");
  for (lua_Integer i = 1; lua_istable(L, -1); ++i) {
    if (lua_rawgeti(L, -1, i) != LUA_TTABLE) {
      lua_pop(L, 1);
      break;
    }
    lua_rawgeti(L, -1, 1);
    lua_rawgeti(L, -2, 2);
    if (lua_type(L, -2) == LUA_TSTRING && lua_type(L, -1) == LUA_TSTRING)
      spec.params.emplace_back(lua_tostring(L, -2), lua_tostring(L, -1));
    lua_pop(L, 3);
  }
  lua_pop(L, 2);
  spec.outputs.timeout_s = std::max(0.0, req.timeout_s);
  spec.outputs.max_bytes = req.max_output;
  if (req.render_every > 0) spec.outputs.render.enabled = true, spec.outputs.render.every = req.render_every;
  if (!req.render) spec.outputs.render.enabled = false;
  if (req.width > 0) spec.outputs.render.width = req.width;
  if (req.height > 0) spec.outputs.render.height = req.height;
  if (req.msaa_samples >= 0) spec.outputs.render.msaa_samples = req.msaa_samples;
  if (req.backend) spec.solver.backend = *req.backend;
  spec.solver.cache_dir = req.cache_dir;
  if (!req.trusted) {
    // What the scenario's numbers make the engine allocate counts against
    // the sandbox's memory budget too, checked before it is allocated.
    spec.solver.max_bytes = double(req.memory_budget);
    const sim::RenderSettings& r = spec.outputs.render;
    if (r.enabled && render_bytes(r) > double(req.memory_budget))
      fail(req.scenario.string(), ": rendering ", r.width, " x ", r.height, " frames with ", r.msaa_samples,
           " MSAA samples needs about ", int(render_bytes(r) / (1 << 20)), " MiB of frame buffers, more than the ",
           req.memory_budget >> 20, " MiB memory budget of the sandbox; render smaller (--size WxH), with fewer "
           "samples (--msaa N), or run with --trust");
  }

  // One EGL context for the GPU backend and rendering, made here (the engine
  // never creates one) and outliving the Model and the renderer.
  std::unique_ptr<gpu::EglContext> context;
  if (sim::wants_gpu_context(spec)) {
    const bool required = spec.solver.backend == sim::Backend::gpu || spec.outputs.render.enabled;
    try {
      context = std::make_unique<gpu::EglContext>();
    } catch (const Error& e) {
      if (required) throw;
      out.warnings.push_back(cat("no OpenGL context (", first_line(e.what()), "); solver backend auto uses the CPU"));
    }
  }
  const sim::Model model = sim::compile(spec, sim::RunResources{context.get()});
  // Frames are drawn on a worker thread while the next frame is simulated,
  // unless the GPU solver needs the shared context on this thread.
  std::unique_ptr<render::FrameWriter> frames;
  if (spec.outputs.render.enabled) {
    const bool solver_on_gpu = model.solver->backend().backend == sim::Backend::gpu;
    frames = std::make_unique<render::FrameWriter>(*context,
                                                   solver_on_gpu || req.render_inline
                                                       ? render::FrameWriter::Mode::inline_draw
                                                       : render::FrameWriter::Mode::worker,
                                                   2, &output);
  }
  out.num_frames = model.num_frames;
  sim::State state = sim::make_state(model);

  // The Scenario table and the glue function live in the registry while the
  // loop runs.
  lua_pushvalue(L, s);
  const int s_ref = protected_ref(L);
  rt.run_string("return require('scenario').after_frame", "=softcut/after_frame", 1);
  const int fn_ref = protected_ref(L);
  rt.run_string("return require('scenario').run_check", "=softcut/run_check", 1);
  const int check_ref = protected_ref(L);
  rt.run_string("return require('scenario').checks_of", "=softcut/checks_of", 1);
  lua_rawgeti(L, LUA_REGISTRYINDEX, s_ref);
  rt.call(1, 1);
  const int checks_ref = protected_ref(L);

  sim::RunHooks hooks;
  // A check function's verdict: (ok, message) copied out bounded and
  // printable (the message is the script's), inside a protected call.
  hooks.check = [&](int index, const sim::Model& m, sim::State& st) {
    FrameCall fc{check_ref, checks_ref, &m, &st, nullptr, index};
    call_frame(rt, L, fc, 2, "expect");
    std::pair<bool, std::string> verdict{lua_toboolean(L, -2) != 0, ""};
    if (lua_type(L, -1) == LUA_TSTRING) {
      size_t len = 0;
      const char* text = lua_tolstring(L, -1, &len);
      verdict.second = printable(std::string(text, len), 2000);
    }
    lua_pop(L, 2);
    return verdict;
  };
  hooks.interrupt = req.interrupt;
  hooks.timed_out = &dog.expired();
  hooks.max_frames = req.max_frames;
  hooks.progress = req.progress;
  hooks.on_frame = [&](const sim::Model& m, sim::State& st) {
    FrameCall fc{fn_ref, s_ref, &m, &st};
    call_frame(rt, L, fc, 1, "on_frame");
    const bool go_on = lua_toboolean(L, -1);
    lua_pop(L, 1);
    return go_on && !st.stop_requested;
  };


  sim::Recorder rec(model, out.out_dir, &output);
  if (frames) rec.set_frame_writer(frames.get());
  out.result = sim::run(model, state, rec, hooks);
  out.step_ms = state.stats.total.sum / std::max(1, state.stats.frames);
  out.frames_rendered = rec.frames_rendered();
  if (out.frames_rendered) {
    out.render_ms = rec.render_frame_thread_ms().sum / out.frames_rendered;
    const render::FrameWriterStats st = frames->stats();  // one locked snapshot
    out.render_work_ms = st.work.total_ms() / std::max(1, st.frames);
  }
  out.warnings.insert(out.warnings.end(), model.warnings.begin(), model.warnings.end());
  out.warnings.insert(out.warnings.end(), state.warnings.begin(), state.warnings.end());

  // Expectation outcomes, from the engine (never from a table the script
  // could forge), listed in the order they were checked (time, then declaration), those
  // not reached last; summary.json keeps the declaration order.
  std::vector<size_t> order;
  for (size_t i = 0; i < model.spec.expectations.size() && i < state.expectations.size(); ++i) order.push_back(i);
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    const sim::ExpectationOutcome &x = state.expectations[a], &y = state.expectations[b];
    return x.reached != y.reached ? x.reached : x.reached && x.time < y.time;
  });
  for (size_t i : order) {
    const sim::ExpectationSpec& e = model.spec.expectations[i];
    const sim::ExpectationOutcome& o = state.expectations[i];
    out.expectations.push_back(ExpectationResult{e.name, e.where, o.reached, o.ok, o.message});
  }
  return out;
}

}  // namespace

}  // namespace softcut::lua
