-- Argument checking driven by the API description in api.lua: every public
-- function checks its table of named fields here, so misuse reads like
--   liver.lua:12: material: unknown field 'youngs' (did you mean 'young'?)
-- Errors are tables {softcut_api_error = true, message = ...}: the runtime
-- shows them as one line (no traceback), pointing at the user's file:line.
local _, internal = ...
local api = require("api")

local check = {}

local ApiError = {}
ApiError.__index = ApiError
ApiError.__tostring = function(e) return e.message end

-- The scenario's file:line of the call being checked.
function check.where()
  local w = internal.where()
  if w == "?" then return internal.scenario_file or "?" end  -- e.g. a tail call from the main chunk
  return w
end

-- Raises an API error at the user's line: "<where>: <fname>: <msg>".
function check.fail(fname, fmt, ...)
  local msg = select("#", ...) > 0 and fmt:format(...) or fmt
  local prefix = fname and (fname .. ": ") or ""
  error(setmetatable({ softcut_api_error = true, message = check.where() .. ": " .. prefix .. msg }, ApiError), 0)
end

-- Raises an engine message as an API error: verbatim when it already starts
-- with the user's file:line, else prefixed with it and `fname`.
function check.raise(fname, msg)
  local w = check.where()
  if msg:sub(1, #w + 1) == w .. ":" then
    error(setmetatable({ softcut_api_error = true, message = msg }, ApiError), 0)
  end
  check.fail(fname, "%s", msg)
end

local function distance(a, b)
  local la, lb = #a, #b
  if math.abs(la - lb) > 3 then return 99 end
  local prev, prevprev = {}, {}
  for j = 0, lb do prev[j] = j end
  for i = 1, la do
    local cur = { [0] = i }
    for j = 1, lb do
      local cost = a:sub(i, i) == b:sub(j, j) and 0 or 1
      cur[j] = math.min(prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + cost)
      if i > 1 and j > 1 and a:sub(i, i) == b:sub(j - 1, j - 1) and a:sub(i - 1, i - 1) == b:sub(j, j) then
        cur[j] = math.min(cur[j], prevprev[j - 2] + 1)  -- transposition
      end
    end
    prevprev, prev = prev, cur
  end
  return prev[lb]
end

-- " (did you mean 'x'?)" for the closest of `names`, or a list of them.
function check.suggest(word, names)
  local best, bestd = nil, math.huge
  local sorted = {}
  for _, n in ipairs(names) do sorted[#sorted + 1] = n end
  table.sort(sorted)
  for _, n in ipairs(sorted) do
    local d = distance(word:lower(), n:lower())
    if n:lower():sub(1, #word) == word:lower() or word:lower():sub(1, #n) == n:lower() then d = math.min(d, 1) end
    if d < bestd then best, bestd = n, d end
  end
  if best and bestd <= math.max(1, #word // 3) then
    return (" (did you mean '%s'?)"):format(best)
  end
  return " (valid: " .. table.concat(sorted, ", ") .. ")"
end

-- A method or function looked up on a softcut object or namespace that has
-- no such name. Reading it stays nil (scripts may test fields of their own),
-- but when the miss is then called ("attempt to call a nil value (method
-- 'grasp')"), the runtime's message handler (lua/runtime.cpp) asks
-- explain_call for the did-you-mean that fields get.
local last_miss

-- An __index for `class` (a method table) named `owner` in messages;
-- `data` lists the object's own optional fields (a nil there is no miss).
function check.recording_index(class, owner, data)
  return function(_, k)
    local v = rawget(class, k)
    if v == nil and type(k) == "string" and k:sub(1, 1) ~= "_" and not (data and data[k]) then
      last_miss = { owner = owner, key = k, class = class, where = internal.where() }
    end
    return v
  end
end

-- "Scenario has no method 'grasp' (did you mean 'grasper'?)" when the last
-- miss was `key`, looked up at `where`; else nil.
function check.explain_call(kind, key, where)
  local m = last_miss
  last_miss = nil
  if not m or m.key ~= key or m.where ~= where then return nil end
  local names = {}
  for n, v in pairs(m.class) do
    if type(n) == "string" and n:sub(1, 2) ~= "__" and type(v) == "function" then names[#names + 1] = n end
  end
  return ("%s has no %s '%s'%s"):format(m.owner, kind == "method" and "method" or "function", key,
    check.suggest(key, names))
end
internal.explain_call = check.explain_call

local function finite(x) return x == x and x ~= math.huge and x ~= -math.huge end

local function describe(v)
  local t = type(v)
  if t == "table" then
    local mt = getmetatable(v)
    if mt and mt.__name then return mt.__name end
    return "table"
  end
  if t == "number" then return ("number %s"):format(tostring(v)) end
  if t == "string" then return ("string '%s'"):format(v) end
  return t
end

local function is_vec3(v)
  return type(v) == "table" and #v == 3 and type(v[1]) == "number" and type(v[2]) == "number"
     and type(v[3]) == "number" and finite(v[1]) and finite(v[2]) and finite(v[3])
end

-- type name -> predicate(value) and the phrase used in messages.
local types = {
  number = { function(v) return type(v) == "number" and finite(v) end, "a finite number" },
  integer = { function(v) return math.type(v) == "integer" or (type(v) == "number" and finite(v) and v == math.floor(v)) end, "an integer" },
  string = { function(v) return type(v) == "string" end, "a string" },
  boolean = { function(v) return type(v) == "boolean" end, "a boolean" },
  ["function"] = { function(v) return type(v) == "function" end, "a function" },
  table = { function(v) return type(v) == "table" end, "a table" },
  vec3 = { is_vec3, "a 3-vector {x, y, z} of finite numbers" },
  ["vec3[]"] = { function(v)
      if type(v) ~= "table" or #v == 0 then return false end
      for _, p in ipairs(v) do if not is_vec3(p) then return false end end
      return true
    end, "a non-empty list of 3-vectors {{x, y, z}, ...}" },
  ["number[]"] = { function(v)
      if type(v) ~= "table" or #v == 0 then return false end
      for _, x in ipairs(v) do if type(x) ~= "number" or not finite(x) then return false end end
      return true
    end, "a non-empty list of finite numbers" },
  ["integer[]"] = { function(v)
      if type(v) ~= "table" or #v == 0 then return false end
      for _, x in ipairs(v) do if math.type(x) ~= "integer" and not (type(x) == "number" and x == math.floor(x)) then return false end end
      return true
    end, "a non-empty list of integers" },
  Selection = { function(v) return getmetatable(v) == check.Selection end, "a node selection (softcut.select.*)" },
  Ramp = { function(v) return getmetatable(v) == check.Ramp or (type(v) == "number" and finite(v)) end, "a ramp (softcut.ramp.*) or a number" },
  Path = { function(v) return getmetatable(v) == check.Path or is_vec3(v) end, "a path (softcut.path.*) or a fixed point {x, y, z}" },
}
check.types = types

local function check_range(fname, f, v)
  local unit = f.unit and (" " .. f.unit) or ""
  local function bad(rel, bound)
    check.fail(fname, "field '%s' = %s%s is out of range: must be %s %s%s%s", f.name, tostring(v), unit, rel,
      tostring(bound), unit, f.why and (" (" .. f.why .. ")") or "")
  end
  if f.gt and not (v > f.gt) then bad(">", f.gt) end
  if f.ge and not (v >= f.ge) then bad(">=", f.ge) end
  if f.lt and not (v < f.lt) then bad("<", f.lt) end
  if f.le and not (v <= f.le) then bad("<=", f.le) end
end

-- Checks one value against field description `f`; returns it (with the
-- default filled in when nil).
function check.value(fname, f, v)
  if v == nil then
    if f.required then
      check.fail(fname, "missing field '%s' (%s%s)", f.name, f.doc or f.type, f.unit and (", " .. f.unit) or "")
    end
    return f.default
  end
  local struct = api.by_name[f.type]
  if struct and struct.is_struct then
    if type(v) ~= "table" or getmetatable(v) ~= nil then
      check.fail(fname, "field '%s' must be a table %s{ %s = ... }, got %s", f.name, f.type, struct.fields[1].name, describe(v))
    end
    return check.args(f.type, v, fname .. ": field '" .. f.name .. "'")
  end
  local ty = types[f.type]
  assert(ty, "api.lua: unknown type " .. tostring(f.type))
  if not ty[1](v) then
    check.fail(fname, "field '%s' must be %s%s, got %s", f.name, ty[2], f.unit and (" (" .. f.unit .. ")") or "",
      describe(v))
  end
  if f.values then
    local ok = false
    for _, x in ipairs(f.values) do if x == v then ok = true end end
    if not ok then
      check.fail(fname, "field '%s': unknown value '%s'%s", f.name, tostring(v), check.suggest(tostring(v), f.values))
    end
  end
  if type(v) == "number" then check_range(fname, f, v) end
  if f.nonzero and v[1] == 0 and v[2] == 0 and v[3] == 0 then
    check.fail(fname, "field '%s' must be a nonzero vector (any length > 0; leave it out for the default), got {0, 0, 0}",
      f.name)
  end
  if f.type == "number[]" or f.type == "integer[]" then
    for _, x in ipairs(v) do check_range(fname, f, x) end
  end
  return v
end

-- Checks table `args` against the fields of api function `qname`
-- ("Scenario:material"); returns a new table with defaults filled in.
function check.args(qname, args, context)
  local spec = api.by_name[qname]
  assert(spec, "api.lua: no entry for " .. qname)
  local fname = context or spec.short
  if type(args) ~= "table" or getmetatable(args) ~= nil then
    check.fail(fname, "expects a table of named fields, e.g. %s{ %s = ... }, got %s", fname,
      spec.fields[1] and spec.fields[1].name or "...", describe(args))
  end
  local known = {}
  for _, f in ipairs(spec.fields) do known[f.name] = f end
  for k, _ in pairs(args) do
    if type(k) ~= "string" then
      check.fail(fname, "expects named fields only (found positional value [%s])", tostring(k))
    end
    if not known[k] then
      local names = {}
      for _, f in ipairs(spec.fields) do names[#names + 1] = f.name end
      check.fail(fname, "unknown field '%s'%s", k, check.suggest(k, names))
    end
  end
  local out = {}
  for _, f in ipairs(spec.fields) do out[f.name] = check.value(fname, f, args[f.name]) end
  for _, group in ipairs(spec.one_of or {}) do
    local given = {}
    for _, n in ipairs(group) do if args[n] ~= nil then given[#given + 1] = n end end
    if #given ~= 1 then
      check.fail(fname, "give exactly one of %s (got %s)", table.concat(group, ", "),
        #given == 0 and "none" or table.concat(given, " and "))
    end
  end
  for _, group in ipairs(spec.at_most_one_of or {}) do
    local given = {}
    for _, n in ipairs(group) do if args[n] ~= nil then given[#given + 1] = n end end
    if #given > 1 then
      check.fail(fname, "fields %s exclude each other (got %s)", table.concat(group, ", "), table.concat(given, " and "))
    end
  end
  -- ordered = { { "a", "b", strict = true } }: b after a (b > a), else b not below a (defaults included).
  for _, pair in ipairs(spec.ordered or {}) do
    local lo, hi = out[pair[1]], out[pair[2]]
    if type(lo) == "number" and type(hi) == "number" then
      if pair.strict and not (hi > lo) then
        check.fail(fname, "%s = %g must be after %s = %g", pair[2], hi, pair[1], lo)
      elseif not pair.strict and lo > hi then
        check.fail(fname, "%s = %g > %s = %g", pair[1], lo, pair[2], hi)
      end
    end
  end
  return out
end

-- Checks positional argument i of api function `qname`; returns it (or its
-- default).
function check.positional(qname, i, v)
  local spec = api.by_name[qname]
  assert(spec and spec.positional, "api.lua: no positional entry for " .. qname)
  local f = spec.positional[i]
  local fake = {}
  for k, x in pairs(f) do fake[k] = x end
  fake.name = f.name
  if v == nil and f.required then
    check.fail(spec.short, "missing argument %d '%s' (%s)", i, f.name, types[f.type] and types[f.type][2] or f.type)
  end
  return check.value(spec.short, fake, v)
end

-- Metatables of the value objects, shared with softcut.lua (so type checks
-- above recognise them).
check.Selection = { __name = "Selection" }
check.Ramp = { __name = "Ramp" }
check.Path = { __name = "Path" }

return check
