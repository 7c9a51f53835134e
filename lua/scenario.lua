-- Scenario builder and the per-frame glue. A Scenario collects checked,
-- plain-table descriptions (each with the file:line of its call); the C++
-- side (lua/spec_from_lua.cpp) turns them into sim::ScenarioSpec. The mesh
-- is loaded at s:mesh{} so every selection is evaluated, and an empty one
-- refused, at the line that made it.
local _, internal = ...
local check = require("check")

local M = {}
local Scenario = { __name = "Scenario" }
Scenario.__index = check.recording_index(Scenario, "Scenario",
  { name = true, duration = true, fps = true, tolerance = true, description = true, where = true })
M.Scenario = Scenario

function M.new(args)
  local a = check.args("softcut.scenario", args)
  local s = setmetatable({
    name = a.name or internal.scenario_stem or "scenario",
    duration = a.duration, fps = a.fps, tolerance = a.tolerance, description = a.description, gravity = a.gravity,
    where = check.where(),
    _materials = {}, _prestress = {}, _fixed = {}, _loads = {}, _tools = {}, _expect = {}, _on_frame = {},
    _output = { csv = true, vtu = false, vtu_every = 1 },
  }, Scenario)
  if not s.name:match("^[%w_%-%.]+$") or s.name:match("^%.") then
    check.fail("scenario", "name '%s' must be a plain folder name (letters, digits, _ - .)", s.name)
  end
  internal.last_scenario = s
  return s
end

-- Builder calls describe the scenario before it runs; during the run the
-- Frame methods are the way to change it.
local function editable(s, fname)
  if s._running then
    check.fail(fname, "the scenario is already running; change it from on_frame with f:set_load, "
      .. "f:move_tool or f:enable_tool")
  end
end

local function need_mesh(s, fname)
  if not s._mesh then check.fail(fname, "call s:mesh{...} first (selections and labels need the mesh)") end
  return s._mesh
end

-- Evaluates `sel` on the mesh (cached in the selection); empty -> error.
local function resolve(s, fname, sel, what)
  local m = need_mesh(s, fname)
  if not sel._ids then
    local ids, err = internal.select_nodes(m.handle, sel, fname)
    if not ids then check.raise(fname, err) end
    sel._ids = ids
  end
  if #sel._ids == 0 then
    check.fail(fname, "%s selection is empty: %s selects no node of the mesh (%d nodes, bounds %s .. %s)",
      what or "the", internal.describe_selection(sel), m.info.num_nodes,
      internal.format_vec(m.info.min), internal.format_vec(m.info.max))
  end
  return sel._ids
end
M.resolve = resolve

function Scenario:mesh(args)
  editable(self, "mesh")
  local a = check.args("Scenario:mesh", args)
  if self._mesh then check.fail("mesh", "the scenario already has a mesh (from line %s)", self._mesh.where) end
  local ok, handle, info = pcall(internal.mesh_load, a, internal.scenario_dir or ".")
  if not ok then check.raise("mesh", tostring(handle)) end
  self._mesh = { file = a.file and info.file, generate = a.generate, options = info.options, handle = handle,
                 info = info, where = check.where() }
  return info
end

local function region(s, fname, a)
  local r
  if a.label then
    r = { kind = "label", label = a.label }
    local known = false
    for _, l in ipairs(need_mesh(s, fname).info.labels) do if l == a.label then known = true end end
    if not known then
      local ls = {}
      for _, l in ipairs(s._mesh.info.labels) do ls[#ls + 1] = tostring(l) end
      check.fail(fname, "unknown label %d (the mesh has labels %s)", a.label, table.concat(ls, ", "))
    end
  elseif a.sphere then r = { kind = "sphere", center = a.sphere.center, radius = a.sphere.radius }
  elseif a.box then r = { kind = "box", min = a.box.min, max = a.box.max }
  elseif a.halfspace then r = { kind = "halfspace", point = a.halfspace.point, normal = a.halfspace.normal }
  elseif a.tets then r = { kind = "tets", ids = a.tets }
  else return { kind = "all", where = check.where() } end
  r.where = check.where()
  local n, err = internal.count_tets(need_mesh(s, fname).handle, r, fname)
  if not n then check.raise(fname, err) end
  if n == 0 then check.fail(fname, "region is empty: %s contains no tet centroid", internal.describe_selection(r)) end
  return r
end

function Scenario:material(args)
  editable(self, "material")
  local a = check.args("Scenario:material", args)
  if not a.tissue and not (a.young and a.poisson) then
    check.fail("material", "give a tissue preset (tissue = \"liver\") or both young and poisson")
  end
  if a.tissue and not internal.tissue_known(a.tissue) then
    local names = {}
    for _, p in ipairs(internal.tissue_presets()) do names[#names + 1] = p.name end
    check.fail("material", "unknown tissue '%s'%s", a.tissue, check.suggest(a.tissue, names))
  end
  local r = region(self, "material", a)
  self._materials[#self._materials + 1] = { name = a.name or ("material" .. (#self._materials + 1)), where = r.where,
    region = r, tissue = a.tissue, young = a.young, poisson = a.poisson, model = a.model, density = a.density, color = a.color }
end

function Scenario:prestress(args)
  editable(self, "prestress")
  local a = check.args("Scenario:prestress", args)
  local r = region(self, "prestress", a)
  local t = a.tensor
  if a.strain then t = { xx = a.strain, yy = a.strain, zz = a.strain, yz = 0, zx = 0, xy = 0 } end
  self._prestress[#self._prestress + 1] = { name = a.name or ("prestress" .. (#self._prestress + 1)), where = r.where,
    region = r, xx = t.xx, yy = t.yy, zz = t.zz, yz = t.yz, zx = t.zx, xy = t.xy }
end

function Scenario:operational(args)
  editable(self, "operational")
  local a = check.args("Scenario:operational", args)
  if self._operational then check.fail("operational", "already set at %s", self._operational.where) end
  self._operational = region(self, "operational", a)
end

function Scenario:fix(args)
  editable(self, "fix")
  local a = check.args("Scenario:fix", args)
  resolve(self, "fix", a.nodes)
  local path = a.path
  if a.displacement then path = M.as_path(a.displacement) end
  local moves = 0
  for _, f in ipairs(self._fixed) do if f.path then moves = moves + 1 end end
  self._fixed[#self._fixed + 1] = { sel = a.nodes, where = check.where(), path = path,
    name = path and (a.name or ("motion" .. (moves + 1))) or nil }
end

-- The largest |value| a ramp (or a number) takes.
local function ramp_peak(r)
  if type(r) == "number" then return math.abs(r) end
  local p = 0
  for _, key in ipairs({ "to", "from", "offset" }) do
    if type(r[key]) == "number" then p = math.max(p, math.abs(r[key])) end
  end
  if type(r.amplitude) == "number" then p = math.abs(r.offset or 0) + math.abs(r.amplitude) end
  if type(r.values) == "table" then
    for _, v in ipairs(r.values) do if type(v) == "number" then p = math.max(p, math.abs(v)) end end
  end
  return p
end

-- Forces past this are a mistake (units, a misplaced exponent), and past
-- ~1e154 N their squares overflow inside the solver: refused naming the
-- fields the script wrote.
M.max_force = 1e6

local function check_force(fname, what, peak)
  if not (peak <= M.max_force) then
    check.fail(fname, "%s reaches %g N, over softcut's bound of %g N on a force (a mistake in units or a misplaced "
      .. "exponent?)", what, peak, M.max_force)
  end
end

function Scenario:load(args)
  editable(self, "load")
  local a = check.args("Scenario:load", args)
  resolve(self, "load", a.nodes)
  local l = { name = a.name or ("load" .. (#self._loads + 1)),
              where = check.where(), nodes = a.nodes, per_node = a.per_node }
  local ramp = args.ramp ~= nil and (" times field 'ramp' (up to %g)"):format(ramp_peak(a.ramp)) or ""
  if a.force then
    local f = a.force
    local len = math.sqrt(f[1] ^ 2 + f[2] ^ 2 + f[3] ^ 2)
    local big = math.max(math.abs(f[1]), math.abs(f[2]), math.abs(f[3]))
    if len == math.huge or (len == 0 and big > 0) then
      -- Its square over- or underflowed ({0, 0, -1e300} has a length): scaled. Only
      -- then, so that every other force keeps its bits.
      len = big * math.sqrt((f[1] / big) ^ 2 + (f[2] / big) ^ 2 + (f[3] / big) ^ 2)
    end
    check_force("load", ("field 'force' (length %g N)%s"):format(len, ramp), len * ramp_peak(a.ramp))
    l.kind, l.direction = "world", len > 0 and { f[1] / len, f[2] / len, f[3] / len } or { 0, 0, -1 }
    l.magnitude = M.scaled_ramp(a.ramp, len)
  else
    check_force("load", ("field 'normal' (%g N)%s"):format(a.normal, ramp), math.abs(a.normal) * ramp_peak(a.ramp))
    l.kind, l.direction = "normal", { 0, 0, 0 }
    l.magnitude = M.scaled_ramp(a.ramp, a.normal)
    local err = internal.check_on_surface(self._mesh.handle, a.nodes._ids)
    if err then check.fail("load", "normal loads need surface nodes: %s", err) end
  end
  self._loads[#self._loads + 1] = l
end

local function tool(s, kind, args)
  editable(s, kind)
  local a = check.args("Scenario:" .. kind, args)
  if a.force then check_force(kind, "field 'force'", ramp_peak(a.force)) end
  local t = { name = a.name, where = check.where(), kind = kind,
              drive = a.stiffness and "spring" or "force", path = M.as_path(a.path), radius = a.radius,
              force = a.force and M.scaled_ramp(a.force, 1) or nil, direction = a.direction, stiffness = a.stiffness,
              start = a.start, stop = a.stop, implicit = a.implicit, shaft = a.shaft }
  s._tools[#s._tools + 1] = t
end
function Scenario:probe(args) tool(self, "probe", args) end
function Scenario:scalpel(args)
  editable(self, "scalpel")
  local a = check.args("Scenario:scalpel", args)
  if a.force then check_force("scalpel", "field 'force'", ramp_peak(a.force)) end
  local t = { name = a.name, where = check.where(), kind = "scalpel",
              drive = a.stiffness and "spring" or "force", path = M.as_path(a.path), radius = a.radius,
              force = a.force and M.scaled_ramp(a.force, 1) or nil, direction = a.direction, stiffness = a.stiffness,
              start = a.start, stop = a.stop, length = a.length, axis = a.axis, cut_pressure = a.cut_pressure,
              back = a.back, shaft = a.shaft }
  self._tools[#self._tools + 1] = t
end
function Scenario:cutting(args)
  editable(self, "cutting")
  self._cutting = check.args("Scenario:cutting", args)
end
function Scenario:grasper(args) tool(self, "grasper", args) end

function Scenario:output(args)
  editable(self, "output")
  local a = check.args("Scenario:output", args)
  if a.log then resolve(self, "output", a.log, "the log") end
  self._output = { log = a.log, csv = a.csv, vtu = a.vtu, vtu_every = a.vtu_every, render = a.render, video = a.video,
                   where = check.where() }
end

function Scenario:camera(args)
  editable(self, "camera")
  local a = check.args("Scenario:camera", args)
  if self._camera then check.fail("camera", "already set at %s", self._camera.where) end
  if a.path and not a.target then check.fail("camera", "a camera on a path needs a target (a point or a path)") end
  if a.follow and a.target then check.fail("camera", "a camera following a tool looks at its tip: drop target (or use lead)") end
  if a.follow then
    local known = {}
    for _, t in ipairs(self._tools) do
      if t.name == a.follow then known = nil break end
      known[#known + 1] = t.name
    end
    if known then
      check.fail("camera", "follows tool '%s', which is not defined yet%s (define the tool before s:camera)", a.follow,
        check.suggest(a.follow, known))
    end
  end
  self._camera = { kind = a.path and "path" or "follow", eye = a.path and M.as_path(a.path) or nil,
                   target = a.target and M.as_path(a.target) or nil, follow = a.follow, distance = a.distance,
                   offset = a.offset, lead = a.lead, up = a.up, fov = a.fov, where = check.where() }
end

function Scenario:solver(args)
  editable(self, "solver")
  self._solver = check.args("Scenario:solver", args)
end

function Scenario:expect(args)
  editable(self, "expect")
  local a = check.args("Scenario:expect", args)
  if a.nodes then resolve(self, "expect", a.nodes) end
  a.where = check.where()
  a.name = a.name or ("expect" .. (#self._expect + 1))
  self._expect[#self._expect + 1] = a
end

function Scenario:on_frame(fn)
  editable(self, "on_frame")
  fn = check.positional("Scenario:on_frame", 1, fn)
  self._on_frame[#self._on_frame + 1] = fn
end

function Scenario:select(sel)
  sel = check.positional("Scenario:select", 1, sel)
  local ids = resolve(self, "select", sel)
  local out = {}
  for i, v in ipairs(ids) do out[i] = v end
  return out
end

-- Frames -------------------------------------------------------------------------

local Frame = { __name = "Frame" }
Frame.__index = check.recording_index(Frame, "Frame", { frame = true, time = true })
M.Frame = Frame

local function node_arg(f, q, node)
  node = check.positional(q, 1, node)
  if node >= f._num_nodes then
    check.fail(q:gsub("^Frame:", ""), "node %d out of range (the mesh has %d nodes, ids 0..%d)", node, f._num_nodes, f._num_nodes - 1)
  end
  return node
end
function Frame:displacement(node) return internal.frame_displacement(self._ctx, node_arg(self, "Frame:displacement", node)) end
function Frame:position(node) return internal.frame_position(self._ctx, node_arg(self, "Frame:position", node)) end
function Frame:mean_displacement(sel)
  sel = check.positional("Frame:mean_displacement", 1, sel)
  return internal.frame_mean_displacement(self._ctx, resolve(self._scenario, "mean_displacement", sel))
end
function Frame:max_displacement(sel)
  sel = check.positional("Frame:max_displacement", 1, sel)
  return internal.frame_max_displacement(self._ctx, resolve(self._scenario, "max_displacement", sel))
end
local function tool_index(f, q, name)
  name = check.positional(q, 1, name)
  for i, t in ipairs(f._scenario._tools) do if t.name == name then return i - 1 end end
  local names = {}
  for _, t in ipairs(f._scenario._tools) do names[#names + 1] = t.name end
  check.fail(q:gsub("^Frame:", ""), "no tool '%s'%s", name, #names > 0 and check.suggest(name, names) or " (the scenario has no tools)")
end
function Frame:tool(name) return internal.frame_tool(self._ctx, tool_index(self, "Frame:tool", name)) end
function Frame:move_tool(name, point)
  local i = tool_index(self, "Frame:move_tool", name)
  internal.frame_move_tool(self._ctx, i, check.positional("Frame:move_tool", 2, point))
end
function Frame:enable_tool(name, on)
  local i = tool_index(self, "Frame:enable_tool", name)
  internal.frame_enable_tool(self._ctx, i, check.positional("Frame:enable_tool", 2, on))
end
function Frame:set_load(name, args)
  name = check.positional("Frame:set_load", 1, name)
  local a = check.args("Frame:set_load", args)
  for i, l in ipairs(self._scenario._loads) do
    if l.name == name then return internal.frame_set_load(self._ctx, i - 1, a.scale, a.enabled) end
  end
  local names = {}
  for _, l in ipairs(self._scenario._loads) do names[#names + 1] = l.name end
  check.fail("set_load", "no load '%s'%s", name, #names > 0 and check.suggest(name, names) or " (the scenario has no loads)")
end
function Frame:stop() internal.frame_stop(self._ctx) end
function Frame:record(name, value)
  name = check.positional("Frame:record", 1, name)
  internal.frame_record(self._ctx, name, check.positional("Frame:record", 2, value))
end
function Frame:cutting() return internal.frame_cutting(self._ctx) end

-- Called by the C++ run loop after every frame with a context handle (after
-- the engine checked the due expectations); runs the on_frame functions.
-- Returns false to stop.
function M.after_frame(s, ctx, frame, time, dt, num_nodes)
  s._running = true
  local f = setmetatable({ frame = frame, time = time, _ctx = ctx, _scenario = s, _num_nodes = num_nodes }, Frame)
  for _, fn in ipairs(s._on_frame) do fn(f) end
  return true
end

-- The check functions of the expectations, taken when the run starts (the
-- engine holds its own copy of the expectations: rewriting s._expect later
-- changes nothing).
function M.checks_of(s)
  local c = { scenario = s }
  for i, e in ipairs(s._expect) do
    if type(e) == "table" and e.check then c[i] = { fn = e.check, message = e.message } end
  end
  return c
end

-- Called by the C++ run loop when expectation `index` (a check function) is
-- due, with the table checks_of made: returns ok, message.
function M.run_check(c, ctx, frame, time, dt, num_nodes, index)
  local s = c.scenario
  local f = setmetatable({ frame = frame, time = time, _ctx = ctx, _scenario = s, _num_nodes = num_nodes }, Frame)
  local e = c[index]
  if not e then error(("expectation #%d has no check function"):format(index), 0) end
  local ok, msg = e.fn(f)
  ok = ok and true or false
  if not ok then msg = msg or e.message or "check returned false" end
  if msg ~= nil and type(msg) ~= "string" then msg = tostring(msg) end
  return ok, msg
end

return M
