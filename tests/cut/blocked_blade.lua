-- Issue #16 item 4: a blade over tissue it may not cut. A bar held at both
-- ends, operational between x = 0.02 and 0.06; a long blade (across the whole
-- height) is drawn across its width at x from x0 to x1. Over the
-- nonoperational part (x > 0.06), or along the interface plane itself, it
-- reaches only tissue that cannot be cut: the run must say so, with the blade
-- and the time (before, it cut nothing and said nothing).
--   softcut run blocked_blade.lua --no-render --set x0=0.08 --set x1=0.09
local P = softcut.params{ x0 = 0.08, x1 = 0.09 }
local s = softcut.scenario{ name = "blocked_blade", duration = 1.0, fps = 20 }
s:mesh{ generate = "box", options = { min = { 0, 0, 0 }, max = { 0.1, 0.04, 0.04 }, nx = 10, ny = 4, nz = 4 } }
s:material{ young = 5e3, poisson = 0.4 }
s:fix{ nodes = softcut.select.box{ min = { -1, -1, -1 }, max = { 0, 1, 1 } }
              + softcut.select.box{ min = { 0.1, -1, -1 }, max = { 1, 1, 1 } } }
s:operational{ box = { min = { 0.02, -1, -1 }, max = { 0.06, 1, 1 } } }
s:scalpel{
  name = "blade", axis = { 0, 0, 1 }, length = 0.06, radius = 0.001, cut_pressure = 1, force = 0.05,
  direction = { 0, 1, 0 },
  path = softcut.path.polyline{ times = { 0.1, 0.9 }, points = { { P.x0, -0.0005, 0.02 }, { P.x1, 0.045, 0.02 } } },
}
s:expect{ name = "nothing separated", at = 1.0, check = function(f)
  local c = f:cutting()
  return c.faces_separated == 0 and c.components == 1, ("%d faces separated"):format(c.faces_separated)
end }
return s
