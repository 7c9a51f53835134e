-- The `softcut` library a scenario sees: params, scenario builder, node
-- selections, ramps, paths, vector helpers, tissue presets. Functions only
-- check arguments (check.lua, against api.lua) and build plain tables; the
-- engine (via internal C bindings) loads meshes, evaluates selections, ramps
-- and paths, and runs the frames.
local _, internal = ...
local check = require("check")
local scenario = require("scenario")

local softcut = {}
softcut.version = internal.version
softcut.scenario = scenario.new

-- Parameters ---------------------------------------------------------------

local function convert_override(key, text, default)
  local t = type(default)
  if t == "number" then
    local v = tonumber(text)
    if not v then check.fail("params", "--set %s=%s: '%s' is not a number (the default is %s)", key, text, text, tostring(default)) end
    return v
  elseif t == "boolean" then
    local map = { ["true"] = true, ["1"] = true, yes = true, on = true, ["false"] = false, ["0"] = false, no = false, off = false }
    if map[text] == nil then check.fail("params", "--set %s=%s: expected true or false", key, text) end
    return map[text]
  end
  return text
end

function softcut.params(defaults)
  if type(defaults) ~= "table" then
    check.fail("params", "expects a table of name = default, e.g. params{ force = 0.5 }")
  end
  local names, out = {}, {}
  for k, v in pairs(defaults) do
    if type(k) ~= "string" then check.fail("params", "parameter names must be strings (found [%s])", tostring(k)) end
    -- Names are typed after --set and become columns of a sweep's CSV.
    if #k > 64 or not k:match("^[%a_][%w_%.%-]*$") then
      check.fail("params", "parameter name '%s': use at most 64 letters, digits, '_', '.' or '-', starting with a letter or '_'", k)
    end
    if #names == 1000 then check.fail("params", "at most 1000 parameters") end
    local t = type(v)
    if t ~= "number" and t ~= "boolean" and t ~= "string" then
      check.fail("params", "parameter '%s' must default to a number, boolean or string, got %s", k, t)
    end
    names[#names + 1] = k
    out[k] = v
  end
  local overrides = internal.overrides or {}
  local keys = {}
  for k in pairs(overrides) do keys[#keys + 1] = k end
  table.sort(keys)
  for _, k in ipairs(keys) do
    if defaults[k] == nil then
      check.fail("params", "--set %s: the scenario has no parameter '%s'%s", k, k, check.suggest(k, names))
    end
    out[k] = convert_override(k, overrides[k], defaults[k])
  end
  internal.params_declared = true
  -- For summary.json: every parameter as the script sees it, by name.
  table.sort(names)
  local effective = {}
  for i, k in ipairs(names) do effective[i] = { k, tostring(out[k]) } end
  internal.params_effective = effective
  return out
end

-- Node selections -------------------------------------------------------------

local Selection = check.Selection
Selection.__index = check.recording_index(Selection, "Selection", { kind = true, children = true, where = true,
  label = true, center = true, radius = true, min = true, max = true, point = true, normal = true, ids = true, name = true })

local function selection(t)
  t.where = check.where()
  return setmetatable(t, Selection)
end

local function combine(kind, qname, a, b)
  check.positional(qname, 1, b)
  return selection({ kind = kind, children = { a, b } })
end
function Selection:union(other) return combine("union_of", "Selection:union", self, other) end
function Selection:intersection(other) return combine("intersection", "Selection:intersection", self, other) end
function Selection:difference(other) return combine("difference", "Selection:difference", self, other) end
Selection.__add = function(a, b) return combine("union_of", "Selection:union", a, b) end
Selection.__mul = function(a, b) return combine("intersection", "Selection:intersection", a, b) end
Selection.__sub = function(a, b) return combine("difference", "Selection:difference", a, b) end
Selection.__tostring = function(s) return "Selection(" .. s.kind .. ")" end

softcut.select = {}
function softcut.select.all() return selection({ kind = "all" }) end
function softcut.select.label(label)
  return selection({ kind = "label", label = check.positional("softcut.select.label", 1, label) })
end
function softcut.select.surface(label)
  return selection({ kind = "surface", label = check.positional("softcut.select.surface", 1, label) or -1 })
end
function softcut.select.sphere(args)
  local a = check.args("softcut.select.sphere", args)
  return selection({ kind = "sphere", center = a.center, radius = a.radius })
end
function softcut.select.box(args)
  local a = check.args("softcut.select.box", args)
  for i = 1, 3 do
    if a.min[i] > a.max[i] then check.fail("select.box", "min[%d] = %g > max[%d] = %g", i, a.min[i], i, a.max[i]) end
  end
  return selection({ kind = "box", min = a.min, max = a.max })
end
function softcut.select.halfspace(args)
  local a = check.args("softcut.select.halfspace", args)
  if a.normal[1] == 0 and a.normal[2] == 0 and a.normal[3] == 0 then check.fail("select.halfspace", "normal is zero") end
  return selection({ kind = "halfspace", point = a.point, normal = a.normal })
end
function softcut.select.nodes(ids)
  return selection({ kind = "nodes", ids = check.positional("softcut.select.nodes", 1, ids) })
end
function softcut.select.named(name)
  return selection({ kind = "named", name = check.positional("softcut.select.named", 1, name) })
end

-- Ramps ------------------------------------------------------------------------

local Ramp = check.Ramp
Ramp.__index = check.recording_index(Ramp, "Ramp", { kind = true, to = true, from = true, t0 = true, t1 = true,
  times = true, values = true, amplitude = true, frequency = true, phase = true, offset = true, where = true })
Ramp.__tostring = function(r) return "Ramp(" .. r.kind .. ")" end

local function ramp(t)
  t.where = check.where()
  setmetatable(t, Ramp)
  local err = internal.ramp_check(t)
  if err then check.raise("ramp." .. t.kind, err) end
  return t
end
function Ramp:at(t) return internal.ramp_at(self, check.positional("Ramp:at", 1, t)) end

softcut.ramp = {}
function softcut.ramp.constant(v)
  return ramp({ kind = "constant", to = check.positional("softcut.ramp.constant", 1, v) })
end
for _, kind in ipairs({ "linear", "smoothstep" }) do
  softcut.ramp[kind] = function(args)
    local a = check.args("softcut.ramp." .. kind, args)
    if not (a.t1 > a.t0) then check.fail("ramp." .. kind, "t1 = %g must be > t0 = %g", a.t1, a.t0) end
    return ramp({ kind = kind, t0 = a.t0, t1 = a.t1, from = a.from, to = a.to })
  end
end
function softcut.ramp.keyframes(args)
  local a = check.args("softcut.ramp.keyframes", args)
  if #a.times ~= #a.values then
    check.fail("ramp.keyframes", "%d times but %d values (give one value per time)", #a.times, #a.values)
  end
  return ramp({ kind = "keyframes", times = a.times, values = a.values })
end
function softcut.ramp.sine(args)
  local a = check.args("softcut.ramp.sine", args)
  return ramp({ kind = "sine", amplitude = a.amplitude, frequency = a.frequency, phase = a.phase, offset = a.offset, t0 = a.t0 })
end

-- A number becomes a constant ramp; a ramp is copied with its values times k.
function scenario.scaled_ramp(r, k)
  if type(r) == "number" then return setmetatable({ kind = "constant", to = r * k }, Ramp) end
  local out = {}
  for key, v in pairs(r) do out[key] = v end
  for _, key in ipairs({ "from", "to", "offset", "amplitude" }) do
    if out[key] then out[key] = out[key] * k end
  end
  if out.values then
    local vals = {}
    for i, v in ipairs(out.values) do vals[i] = v * k end
    out.values = vals
  end
  return setmetatable(out, Ramp)
end

-- Paths ------------------------------------------------------------------------

local Path = check.Path
Path.__index = check.recording_index(Path, "Path", { kind = true, times = true, points = true, center = true,
  axis = true, start = true, sweep = true, t0 = true, t1 = true, where = true })
Path.__tostring = function(p) return "Path(" .. p.kind .. ")" end

local function path(t)
  t.where = check.where()
  setmetatable(t, Path)
  local err = internal.path_check(t)
  if err then check.raise("path." .. t.kind, err) end
  return t
end
function Path:at(t) return internal.path_at(self, check.positional("Path:at", 1, t)) end

softcut.path = {}
function softcut.path.fixed(p)
  return path({ kind = "fixed", times = { 0 }, points = { check.positional("softcut.path.fixed", 1, p) } })
end
for _, kind in ipairs({ "polyline", "catmull_rom" }) do
  softcut.path[kind] = function(args)
    local a = check.args("softcut.path." .. kind, args)
    if #a.times ~= #a.points then
      check.fail("path." .. kind, "%d times but %d points (give one point per time)", #a.times, #a.points)
    end
    return path({ kind = kind, times = a.times, points = a.points })
  end
end
function softcut.path.arc(args)
  local a = check.args("softcut.path.arc", args)
  if not (a.t1 > a.t0) then check.fail("path.arc", "t1 = %g must be > t0 = %g", a.t1, a.t0) end
  return path({ kind = "arc", center = a.center, axis = a.axis, start = a.start, sweep = a.sweep, t0 = a.t0, t1 = a.t1 })
end

function scenario.as_path(p)
  if getmetatable(p) == Path then return p end
  return path({ kind = "fixed", times = { 0 }, points = { p } })
end

-- Vectors ------------------------------------------------------------------------

local function v3(q, i, v) return check.positional(q, i, v) end
softcut.vec = {}
function softcut.vec.add(a, b)
  a, b = v3("softcut.vec.add", 1, a), v3("softcut.vec.add", 2, b)
  return { a[1] + b[1], a[2] + b[2], a[3] + b[3] }
end
function softcut.vec.sub(a, b)
  a, b = v3("softcut.vec.sub", 1, a), v3("softcut.vec.sub", 2, b)
  return { a[1] - b[1], a[2] - b[2], a[3] - b[3] }
end
function softcut.vec.scale(a, k)
  a, k = v3("softcut.vec.scale", 1, a), v3("softcut.vec.scale", 2, k)
  return { a[1] * k, a[2] * k, a[3] * k }
end
function softcut.vec.dot(a, b)
  a, b = v3("softcut.vec.dot", 1, a), v3("softcut.vec.dot", 2, b)
  return a[1] * b[1] + a[2] * b[2] + a[3] * b[3]
end
function softcut.vec.cross(a, b)
  a, b = v3("softcut.vec.cross", 1, a), v3("softcut.vec.cross", 2, b)
  return { a[2] * b[3] - a[3] * b[2], a[3] * b[1] - a[1] * b[3], a[1] * b[2] - a[2] * b[1] }
end
function softcut.vec.length(a)
  a = v3("softcut.vec.length", 1, a)
  return math.sqrt(a[1] * a[1] + a[2] * a[2] + a[3] * a[3])
end
function softcut.vec.lerp(a, b, s)
  a, b, s = v3("softcut.vec.lerp", 1, a), v3("softcut.vec.lerp", 2, b), v3("softcut.vec.lerp", 3, s)
  return { a[1] + s * (b[1] - a[1]), a[2] + s * (b[2] - a[2]), a[3] + s * (b[3] - a[3]) }
end

-- Tissue presets (from the engine's table) -----------------------------------------

softcut.tissues = {}
for _, p in ipairs(internal.tissue_presets()) do
  softcut.tissues[p.name] = { young = p.young, poisson = p.poisson, source = p.source }
end

-- softcut.select.sphre{...} gets a did-you-mean too (check.recording_index).
for name, t in pairs({ softcut = softcut, ["softcut.select"] = softcut.select, ["softcut.ramp"] = softcut.ramp,
                        ["softcut.path"] = softcut.path, ["softcut.vec"] = softcut.vec }) do
  setmetatable(t, { __index = check.recording_index(t, name) })
end

return softcut
