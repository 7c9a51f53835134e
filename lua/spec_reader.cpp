#include "spec_reader.hpp"

#include <lua.hpp>

#include <string>

#include "convert.hpp"
#include "core/error.hpp"
#include "core/printable.hpp"
#include "runtime.hpp"
#include "sandbox/limits.hpp"
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
  spec.description = printable(get_string(L, s, "description"), 2000);  // one line in summary.json, bounded
  spec.reference_tolerance = get_number(L, s, "tolerance", 1e-6);
  spec.source = source;
  spec.versions["lua"] = LUA_RELEASE;
  spec.timeline.duration = get_number(L, s, "duration", 1.0);
  spec.timeline.fps = get_number(L, s, "fps", 30.0);
  spec.gravity = get_vec3(L, s, "gravity", Eigen::Vector3d::Zero());
  spec.timeline.where = printable(where, 2000);

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
    if (has_field(L, m, "model")) a.model = fem::parse_material_model(get_string(L, m, "model"));
    a.density = get_number(L, m, "density", 0.0);
    a.has_color = has_field(L, m, "color");
    a.color = get_vec3(L, m, "color", Eigen::Vector3d::Zero());
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
    sim::NodeSelector sel = to_node_selector(L, -1);
    lua_pop(L, 1);
    if (push_field(L, f, "path") == LUA_TTABLE) {  // a prescribed motion
      sim::MotionSpec mo;
      mo.path = to_path(L, -1);
      mo.name = get_string(L, f, "name");
      mo.where = get_string(L, f, "where");
      mo.nodes = std::move(sel);
      spec.motions.push_back(std::move(mo));
    } else {
      fixed.push_back(std::move(sel));
    }
    lua_pop(L, 1);
  });
  if (fixed.empty() && !spec.motions.empty()) {  // held by its motions alone
    spec.fixed = sim::NodeSelector::list({});
    spec.fixed.where = spec.motions[0].where;
  } else if (fixed.empty()) {
    fail(where, ": scenario: no fixed nodes, so the body can float away (the stiffness matrix is singular); "
                "add s:fix{ nodes = softcut.select... }");
  } else if (fixed.size() == 1) {
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
    ls.direction_kind = sim::parse_load_direction(get_string(L, l, "kind"));
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
      es.measure = sim::parse_measure(get_string(L, e, "measure", "mean"));
      es.component = sim::parse_component(get_string(L, e, "component", "magnitude"));
      if (has_field(L, e, "min")) es.min = get_number(L, e, "min", 0.0);
      if (has_field(L, e, "max")) es.max = get_number(L, e, "max", 0.0);
    }
    spec.expectations.push_back(es);
  });

  each(L, s, "_tools", [&](int t) {
    tools::ToolSpec ts;
    ts.name = get_string(L, t, "name");
    ts.where = get_string(L, t, "where");
    ts.kind = tools::parse_tool_kind(get_string(L, t, "kind"));
    ts.drive = tools::parse_drive(get_string(L, t, "drive"));
    push_field(L, t, "path");
    ts.path = to_path(L, -1);
    lua_pop(L, 1);
    ts.radius = get_number(L, t, "radius", ts.radius);
    if (push_field(L, t, "force") != LUA_TNIL) ts.force = to_ramp(L, -1);
    lua_pop(L, 1);
    ts.direction = get_vec3(L, t, "direction", Eigen::Vector3d::Zero());
    ts.stiffness = get_number(L, t, "stiffness", 0.0);
    ts.start = get_number(L, t, "start", 0.0);
    ts.stop = get_number(L, t, "stop", std::numeric_limits<double>::infinity());
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
    out.where = printable(get_string(L, o, "where"), 2000);
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
      rs.style = sim::parse_render_style(get_string(L, r, "style", "clinical"));
      const bool debug = rs.style == sim::RenderSettings::Style::debug;
      rs.show_forces = get_bool(L, r, "show_forces", debug);
      rs.show_loads = get_bool(L, r, "show_loads", debug);
      rs.background = get_vec3(L, r, "background", rs.background);
      rs.tissue_colors = get_vec3s(L, r, "tissue_colors");
      rs.cut_color = get_vec3(L, r, "cut_color", rs.cut_color);
      rs.show_inclusions = get_bool(L, r, "show_inclusions", rs.show_inclusions);
      rs.depth = get_bool(L, r, "depth", false);
      rs.labels = get_bool(L, r, "labels", false);
      if (has_field(L, r, "record"))
        rs.record = get_bool(L, r, "record", true) ? sim::RenderSettings::Record::on : sim::RenderSettings::Record::off;
    }
    lua_pop(L, 1);
    if (get_bool(L, o, "video", false)) out.render.enabled = out.render.video = true;
  }
  lua_pop(L, 1);

  if (push_field(L, s, "_camera") == LUA_TTABLE) {
    const int c = lua_gettop(L);
    sim::CameraSpec& cam = spec.outputs.camera;
    cam.where = get_string(L, c, "where");
    cam.kind = sim::parse_camera_kind(get_string(L, c, "kind"));
    if (push_field(L, c, "eye") == LUA_TTABLE) cam.eye = to_path(L, -1);
    lua_pop(L, 1);
    if (push_field(L, c, "target") == LUA_TTABLE) {
      cam.target_path = to_path(L, -1);
      cam.target_moves = true;
    }
    lua_pop(L, 1);
    cam.follow = get_string(L, c, "follow");
    cam.distance = get_number(L, c, "distance", cam.distance);
    cam.offset = get_number(L, c, "offset", cam.offset);
    cam.lead = get_number(L, c, "lead", cam.lead);
    cam.up = get_vec3(L, c, "up", cam.up);
    cam.fov_deg = get_number(L, c, "fov", 0.0);
  }
  lua_pop(L, 1);

  if (push_field(L, s, "_solver") == LUA_TTABLE) {
    const int v = lua_gettop(L);
    spec.solver.cg_tolerance = get_number(L, v, "tolerance", spec.solver.cg_tolerance);
    spec.solver.cg_max_iterations = get_int(L, v, "max_iterations", 0);
    spec.solver.backend = backend::parse_backend(get_string(L, v, "backend", "auto"));
    spec.solver.mode = hybrid::parse_storage(get_string(L, v, "mode", "auto"));
    spec.solver.gpu_fp64 = get_bool(L, v, "gpu_fp64", spec.solver.gpu_fp64);
    spec.solver.newton.tolerance = get_number(L, v, "newton_tolerance", spec.solver.newton.tolerance);
    spec.solver.newton.max_iterations = get_int(L, v, "newton_max_iterations", spec.solver.newton.max_iterations);
    spec.solver.whole_body = get_bool(L, v, "whole_body", spec.solver.whole_body);
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

}  // namespace

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

}  // namespace softcut::lua
