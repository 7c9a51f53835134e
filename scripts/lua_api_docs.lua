-- Renders the API description (lua/api.lua) as docs/lua-api.md and as LuaLS
-- annotations docs/softcut.d.lua. A tool, not part of the embedded library:
-- test_lua loads it from here, compares both files with these renderings,
-- and SOFTCUT_WRITE_DOCS=1 test_lua rewrites them.
local api = require("api")

local docs = {}

local intro = [[
# softcut Lua API

<!-- Generated from lua/api.lua by scripts/lua_api_docs.lua; do not edit. Regenerate with
     `SOFTCUT_WRITE_DOCS=1 build/tests/test_lua`. -->

A scenario is a Lua 5.4 script run by `softcut run SCENARIO.lua` (or `softcut check`). It builds
a `Scenario` with the `softcut` library and returns it. Units are SI throughout: m, s, N, Pa, Hz,
rad. Node ids are 0-based positions in the mesh file (the same ids as in `displacements.csv`).

```lua
local P = softcut.params{ force = 0.1 }                       -- softcut run ... --set force=0.2
local s = softcut.scenario{ duration = 1.0, fps = 30 }
local m = s:mesh{ generate = "box", options = { min = {0, 0, 0}, max = {0.1, 0.04, 0.04}, nx = 10, ny = 4, nz = 4 } }
s:material{ tissue = "liver" }
s:fix{ nodes = softcut.select.box{ min = {0, 0, 0}, max = {0, 0.04, 0.04} } }
local tip = softcut.select.box{ min = {0.1, 0, 0}, max = {0.1, 0.04, 0.04} }
s:load{ name = "pull", nodes = tip, force = {0, 0, -P.force}, ramp = softcut.ramp.smoothstep{ t1 = 1 } }
s:expect{ at = 1.0, nodes = tip, component = "z", min = -0.03, max = -0.01 }
s:on_frame(function(f) if f:max_displacement(tip) > 0.04 then f:stop() end end)
return s
```

Every function takes a table of named fields (or the positional arguments listed). Misuse is an
error at the scenario's line, e.g. `liver.lua:12: material: unknown field 'youngs' (did you mean
'young'?)`, and so is a misspelled method or function: `liver.lua:14: Scenario has no method 'grasp'
(did you mean 'grasper'?)`. Runtime errors carry a traceback of the script's own frames.

**Sandbox.** Scenarios run with the safe standard libraries only (base without `dofile`/`loadfile`,
`load` of text only; `string`, `table`, `math`, `utf8`, `coroutine`; `os.clock/time/date`;
`io.open`, `io.lines`, `io.write`, no reading from stdin). Files are read below the scenario's folder
and written below the output folder, never through a symbolic link, and only regular files; `file:seek`
cannot move past the end. An instruction budget per call (the main chunk, each on_frame) also charges
work inside the C library (bytes allocated, elements moved: `string.rep`, `table.concat`, `load`, ...)
and the engine (loading meshes, evaluating selections), and each such call may use at most 10 s of CPU
time (what one instruction does in C, e.g. comparing huge strings, is seen by no count; generating the
mesh is not counted); once either runs out, or Ctrl-C or the run's `--timeout` strikes, every later
instruction fails and `pcall`/`xpcall`/coroutines re-raise it.
`setmetatable` refuses `__gc` (finalizers would run outside the budget). A memory budget covers the Lua
heap, the meshes the script holds and what its numbers make the engine allocate; meshes have at most
2,000,000 tetrahedra (`--max-tets N` changes it). What the script writes counts towards the run's
`--max-output`.
`require "name"` loads the embedded library first (`softcut`, `scenario`, `check`, `api`: a module of yours
needs another name), then `name.lua` below the scenario's
folder (dots are folders: `require "lib.organs"` loads `lib/organs.lua`): text only, through the same
checked open (no link, no `..`), its reading and parsing charged like `load`'s, run once with `(name, file)`
inside the same budgets and cached; a module that requires itself is an error. Under `softcut check DIR` such modules are skipped (`SKIP`).
`--trust` lifts all of it (`require` then also searches `package.path`, the scenario's folder first).
]]

local function type_text(t)
  local map = { vec3 = "vec3 {x, y, z}", ["vec3[]"] = "list of vec3", Ramp = "Ramp or number", Path = "Path or vec3" }
  return map[t] or t
end

local function range_text(f)
  local parts = {}
  if f.gt then parts[#parts + 1] = "> " .. tostring(f.gt) end
  if f.ge then parts[#parts + 1] = ">= " .. tostring(f.ge) end
  if f.lt then parts[#parts + 1] = "< " .. tostring(f.lt) end
  if f.le then parts[#parts + 1] = "<= " .. tostring(f.le) end
  if f.nonzero then parts[#parts + 1] = "nonzero" end
  if f.values then parts[#parts + 1] = "one of " .. table.concat(f.values, ", ") end
  return table.concat(parts, ", ")
end

local function value_text(v)
  if v == nil then return "" end
  if type(v) == "table" then
    local out = {}
    for i, x in ipairs(v) do out[i] = tostring(x) end
    return "{" .. table.concat(out, ", ") .. "}"
  end
  if type(v) == "string" then return '"' .. v .. '"' end
  return tostring(v)
end

local function field_table(lines, fields)
  lines[#lines + 1] = "| field | type | unit | range | default | description |"
  lines[#lines + 1] = "|---|---|---|---|---|---|"
  for _, f in ipairs(fields) do
    lines[#lines + 1] = ("| `%s`%s | %s | %s | %s | %s | %s |"):format(f.name, f.required and " (required)" or "",
      type_text(f.type), f.unit or "", range_text(f), value_text(f.default), (f.doc or ""):gsub("|", "\\|"))
  end
end

local function signature(fn)
  local call = fn.name
  if fn.positional then
    local args = {}
    for _, p in ipairs(fn.positional) do args[#args + 1] = p.name end
    if #fn.fields > 0 then args[#args + 1] = "{...}" end
    return call .. "(" .. table.concat(args, ", ") .. ")"
  end
  return call .. "{...}"
end

function docs.markdown()
  local lines = { intro }
  local section
  local sections = { softcut = "Library", Scenario = "Scenario methods", Selection = "Selections",
                     Ramp = "Ramps", Path = "Paths", Frame = "Frame (argument of on_frame and expect checks)" }
  for _, fn in ipairs(api.functions) do
    local head = fn.name:match("^(%u%w*):") or (fn.name:match("^softcut%.(%w+)%.") and fn.name:match("^softcut%.(%w+)%."):gsub("^%l", string.upper)) or "softcut"
    local title = sections[head] or (head == "Select" and "Selections") or (head == "Vec" and "Vector helpers") or head
    if title ~= section then
      section = title
      lines[#lines + 1] = "## " .. title .. "\n"
      if head == "Frame" then
        lines[#lines + 1] = "A Frame's fields (read them, do not change them):\n"
        field_table(lines, api.frame_fields)
        lines[#lines + 1] = ""
      end
    end
    lines[#lines + 1] = ("### `%s`%s\n"):format(signature(fn), fn.returns and (" -> " .. fn.returns) or "")
    lines[#lines + 1] = fn.summary .. "\n"
    if fn.positional and #fn.positional > 0 then
      lines[#lines + 1] = "Arguments:\n"
      field_table(lines, fn.positional)
      lines[#lines + 1] = ""
    end
    if #fn.fields > 0 then
      field_table(lines, fn.fields)
      lines[#lines + 1] = ""
    end
    if fn.free_fields then lines[#lines + 1] = "Fields: any names, " .. fn.free_fields .. ".\n" end
    for _, g in ipairs(fn.one_of or {}) do lines[#lines + 1] = "Give exactly one of " .. table.concat(g, ", ") .. ".\n" end
    for _, g in ipairs(fn.at_most_one_of or {}) do lines[#lines + 1] = "Give at most one of " .. table.concat(g, ", ") .. ".\n" end
    for _, g in ipairs(fn.ordered or {}) do
      lines[#lines + 1] = g.strict and ("`" .. g[2] .. "` must be after `" .. g[1] .. "`.\n")
                                    or ("`" .. g[1] .. "` must not exceed `" .. g[2] .. "`.\n")
    end
    lines[#lines + 1] = "```lua\n" .. fn.example .. "\n```\n"
  end
  lines[#lines + 1] = "## Field tables\n"
  for _, st in ipairs(api.structs) do
    lines[#lines + 1] = ("### %s\n\n%s\n"):format(st.name, st.summary)
    field_table(lines, st.fields)
    lines[#lines + 1] = ""
  end
  lines[#lines + 1] = "## Values\n"
  for _, v in ipairs(api.values) do lines[#lines + 1] = ("### `%s`\n\n%s\n"):format(v.name, v.summary) end
  return table.concat(lines, "\n")
end

local function ls_type(t, optional)
  local map = { vec3 = "number[]", ["vec3[]"] = "number[][]", ["number[]"] = "number[]", ["integer[]"] = "integer[]",
                Ramp = "Ramp|number", Path = "Path|number[]", ["function"] = "function", table = "table" }
  return (map[t] or t) .. (optional and "?" or "")
end

local function doc_line(f)
  return ((f.doc or "") .. (f.unit and (" (" .. f.unit .. ")") or "")):gsub("\n", " ")
end

function docs.annotations()
  local out = { "---@meta softcut", "-- Generated from lua/api.lua by scripts/lua_api_docs.lua; do not edit.",
                "-- Editor annotations (lua-language-server) for softcut scenarios.", "" }
  local classes = { "Scenario", "Selection", "Ramp", "Path", "Frame" }
  for _, c in ipairs(classes) do out[#out + 1] = ("---@class %s\nlocal %s = {}\n"):format(c, c) end
  out[#out + 1] = "---@class Mesh\n---@field num_nodes integer\n---@field num_tets integer\n---@field labels integer[]\n"
    .. "---@field min number[]\n---@field max number[]\n---@field center number[]\n---@field size number[]\n---@field sets string[]\n---@field surface_nodes integer[]\n"
  local frame = { "---@class Frame" }
  for _, f in ipairs(api.frame_fields) do frame[#frame + 1] = ("---@field %s %s %s"):format(f.name, ls_type(f.type), doc_line(f)) end
  out[#out + 1] = table.concat(frame, "\n") .. "\n"
  for _, st in ipairs(api.structs) do
    out[#out + 1] = ("---@class %s %s"):format(st.name, st.summary)
    for _, f in ipairs(st.fields) do
      out[#out + 1] = ("---@field %s %s %s"):format(f.name .. (f.required and "" or "?"), ls_type(f.type), doc_line(f))
    end
    out[#out + 1] = ""
  end
  out[#out + 1] = "softcut = {}\nsoftcut.select = {}\nsoftcut.ramp = {}\nsoftcut.path = {}\nsoftcut.vec = {}"
  out[#out + 1] = "---@type table<string, {young: number, poisson: number, source: string}>\nsoftcut.tissues = {}"
  out[#out + 1] = "---@type string\nsoftcut.version = \"\"\n"
  for _, fn in ipairs(api.functions) do
    local argclass = fn.name:gsub("[.:]", "_") .. "_args"
    if #fn.fields > 0 then
      out[#out + 1] = "---@class " .. argclass
      for _, f in ipairs(fn.fields) do
        out[#out + 1] = ("---@field %s %s %s"):format(f.name .. (f.required and "" or "?"), ls_type(f.type), doc_line(f))
      end
    end
    out[#out + 1] = "---" .. fn.summary:gsub("\n", " ")
    local params = {}
    for _, p in ipairs(fn.positional or {}) do
      out[#out + 1] = ("---@param %s %s %s"):format(p.name, ls_type(p.type, not p.required), doc_line(p))
      params[#params + 1] = p.name
    end
    if #fn.fields > 0 or fn.free_fields then
      out[#out + 1] = ("---@param args %s"):format(#fn.fields > 0 and argclass or "table")
      params[#params + 1] = "args"
    end
    if fn.returns then out[#out + 1] = "---@return " .. ls_type(fn.returns) end
    out[#out + 1] = ("function %s(%s) end\n"):format(fn.name, table.concat(params, ", "))
  end
  return table.concat(out, "\n")
end

-- Every function reachable from the `softcut` table and the method tables,
-- by qualified name (for the documentation test).
function docs.registered(softcut, methods)
  local names = {}
  local function walk(t, prefix, seen)
    for k, v in pairs(t) do
      if type(k) == "string" and k:sub(1, 1) ~= "_" then
        if type(v) == "function" then names[#names + 1] = prefix .. "." .. k
        elseif type(v) == "table" and not seen[v] then
          seen[v] = true
          walk(v, prefix .. "." .. k, seen)
        end
      end
    end
  end
  walk(softcut, "softcut", {})
  for cls, t in pairs(methods) do
    for k, v in pairs(t) do
      if type(v) == "function" and k:sub(1, 2) ~= "__" then names[#names + 1] = cls .. ":" .. k end
    end
  end
  table.sort(names)
  return names
end

return docs
