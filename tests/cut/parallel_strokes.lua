-- Issue #40 item 9: eight strokes 0.6 mm apart, each lifted out 8 mm above
-- the bottom of a 20 mm bar, on 10 mm cells whose snap distance (1.5 mm)
-- spans several strokes. The strokes merge into one cut on this mesh and
-- their bottoms meet, so a strip between them comes free that no blade
-- closed (docs/cutting.md "Known limits"). The run must say so: the piece's
-- warning names the strokes whose cuts bound it and why strokes can do that.
--   softcut run parallel_strokes.lua --no-render
local P = softcut.params{ gap = 0.0006, depth = 0.008, strokes = 8, x0 = 0.0503 }
local s = softcut.scenario{ name = "parallel_strokes", duration = 0.1 * P.strokes + 0.1, fps = 100 }
s:mesh{ generate = "box", options = { min = { 0, 0, 0 }, max = { 0.1, 0.02, 0.02 }, nx = 10, ny = 4, nz = 4 } }
s:material{ young = 5e3, poisson = 0.4 }
s:fix{ nodes = softcut.select.box{ min = { -1, -1, -1 }, max = { 0, 1, 1 } }
              + softcut.select.box{ min = { 0.1, -1, -1 }, max = { 1, 1, 1 } } }
s:operational{ box = { min = { 0.003, -1, -1 }, max = { 0.097, 1, 1 } } }
local times, points = {}, {}
for k = 0, P.strokes - 1 do  -- down and out again, then 0.6 mm on
  local x, t = P.x0 + P.gap * k, 0.1 * k
  times[#times + 1] = t;        points[#points + 1] = { x, 0.01, 0.025 }
  times[#times + 1] = t + 0.04; points[#points + 1] = { x, 0.01, P.depth }
  times[#times + 1] = t + 0.08; points[#points + 1] = { x, 0.01, 0.025 }
end
s:scalpel{ name = "blade", length = 0.04, axis = { 0, 1, 0 }, radius = 0.0005, cut_pressure = 1e3, force = 0.2,
           direction = { 0, 0, -1 }, path = softcut.path.polyline{ times = times, points = points } }
s:output{ csv = false }
return s
