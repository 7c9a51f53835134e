-- A through-cut that separates a piece: a bar of soft tissue held at both
-- ends is cut through its whole section by a scalpel in its operational
-- middle slab. Each piece keeps its fixed end, so both stay elastic (a piece
-- cut free of every fixed node would be held where it was when it separated,
-- see docs/cutting.md). After the cut a probe pushes the right piece near
-- the cut: it moves freely, as a cantilever, while the left piece stays put.
local P = softcut.params{
  push = 0.05,          -- N, probe force on the right piece after the cut
  cut_pressure = 1e3,   -- Pa
  model = "corotational",  -- each piece bends as a cantilever, its root turning by 20 deg
}

local s = softcut.scenario{
  name = "through_cut", duration = 1.5, fps = 20, tolerance = 1e-6,
  description = "a bar held at both ends cut through; the right piece then pushed (two pieces, decoupled)",
}
s:mesh{ generate = "box", options = { min = { 0, 0, 0 }, max = { 0.1, 0.02, 0.02 }, nx = 10, ny = 4, nz = 4 } }
s:material{ young = 5e3, poisson = 0.4, model = P.model }
local left = softcut.select.box{ min = { -1, -1, -1 }, max = { 0, 1, 1 } }
local right = softcut.select.box{ min = { 0.1, -1, -1 }, max = { 1, 1, 1 } }
s:fix{ nodes = left + right }
-- Operational but for the held ends: a cut piece bends as a cantilever from
-- its held end, and a condensed (linear) root would turn by 20 deg, past the
-- 10 deg softcut warns at (condensed_rotation, docs/fidelity.md).
s:operational{ box = { min = { 0.003, -1, -1 }, max = { 0.097, 1, 1 } } }

-- Blade: a 40 mm edge along y (wider than the bar), pressing the top at
-- x = 51.2 mm, then down through the 20 mm section.
local xc = 0.0512
s:scalpel{
  name = "blade", length = 0.04, axis = { 0, 1, 0 }, radius = 0.0015, cut_pressure = P.cut_pressure,
  path = softcut.path.polyline{ times = { 0, 0.2, 0.8 }, points = { { xc, 0.01, 0.0205 }, { xc, 0.01, 0.0205 }, { xc, 0.01, -0.004 } } },
  force = softcut.ramp.linear{ t1 = 0.2, to = 0.2 }, direction = { 0, 0, -1 }, stop = 0.85,
}
-- After the cut: push the right piece down 5 mm from the cut.
local near_right = softcut.select.surface() * softcut.select.box{ min = { 0.058, -1, 0.02 }, max = { 0.062, 1, 1 } }
local near_left = softcut.select.surface() * softcut.select.box{ min = { 0.038, -1, 0.02 }, max = { 0.042, 1, 1 } }
s:load{ name = "push", nodes = near_right, force = { 0, 0, -P.push }, ramp = softcut.ramp.smoothstep{ t0 = 0.9, t1 = 1.3 } }

s:output{ log = near_left + near_right,
          render = { width = 960, height = 540, azimuth = -70, elevation = 25, every = 2, show_interface = false } }

s:expect{ name = "cut through: two pieces", at = 0.9, check = function(f)
  local c = f:cutting()
  return c.components == 2, ("%d connected pieces after %d cut events"):format(c.components, c.events)
end }
s:expect{ name = "the pushed piece moves", at = 1.5, nodes = near_right, component = "z", max = -0.002 }
s:expect{ name = "the other piece does not", at = 1.5, nodes = near_left, measure = "max", max = 1e-12 }

return s
