-- Issue #16 item 1: a blade swept through the whole section of a bar held at
-- both ends while a load moves the tissue (4 mN x (1 + amp sin 2 pi hz t)).
-- The cut must go through (two pieces, each still anchored) whatever the load
-- does between frames; ctest runs it with the parameters below.
--   path 0: an N-shaped path whose poses land on mesh edges at 40 and 80 fps
--   path 1: a straight path whose poses lie on node planes
local P = softcut.params{ hz = 3, amp = 0.5, fz = -0.004, fps = 40, path = 0 }
local s = softcut.scenario{ name = "moving_tissue", duration = 1.0, fps = P.fps }
s:mesh{ generate = "box", options = { min = { 0, 0, 0 }, max = { 0.1, 0.04, 0.04 }, nx = 10, ny = 4, nz = 4 } }
s:material{ young = 5e3, poisson = 0.4 }
s:fix{ nodes = softcut.select.box{ min = { -1, -1, -1 }, max = { 0, 1, 1 } }
             + softcut.select.box{ min = { 0.1, -1, -1 }, max = { 1, 1, 1 } } }
s:operational{ box = { min = { 0.02, -1, -1 }, max = { 0.08, 1, 1 } } }
s:load{ name = "wobble", force = { 0, 0, P.fz },
        nodes = softcut.select.surface() * softcut.select.box{ min = { 0.021, -1, 0.04 }, max = { 0.039, 1, 1 } },
        ramp = softcut.ramp.sine{ offset = 1, amplitude = P.amp, frequency = P.hz } }
local times, points = { 0.1, 0.35, 0.6, 0.85 },
  { { 0.05, -0.0005, 0.02 }, { 0.055, 0.015, 0.02 }, { 0.045, 0.03, 0.02 }, { 0.05, 0.045, 0.02 } }
if P.path == 1 then times, points = { 0.1, 0.6 }, { { 0.045, -0.005, 0.02 }, { 0.045, 0.045, 0.02 } } end
s:scalpel{ name = "blade", axis = { 0, 0, 1 }, length = 0.06, radius = 0.001, cut_pressure = 1, force = 0.05,
           direction = { 0, 1, 0 }, path = softcut.path.polyline{ times = times, points = points } }
s:expect{ name = "cut through: two anchored pieces", at = 1.0, check = function(f)
  local c = f:cutting()
  return c.components == 2 and c.pieces == 2 and c.detached == 0,
    ("%d piece(s) (%d rigid, %d detached) after %d cut events"):format(c.components, c.pieces, c.detached, c.events)
end }
return s
