-- Issue #16 item 5: a force-driven scalpel pressed into the top of a bar held
-- at both ends, its path going straight down through the whole section. The
-- force ramps up over `ramp` s (0: full force at once), so the blade may sink
-- in below its cut_pressure before it reaches it; it must then cut from where
-- it entered, all the way through. A path that starts inside the tissue, or a
-- blade that sinks in without ever reaching cut_pressure and loses contact,
-- is refused with a message instead of cutting nothing.
--   softcut run press_in.lua --no-render --set z0=0.04 --set ramp=0.3
local P = softcut.params{
  z0 = 0.04,     -- m, blade height at t = 0 (top surface at 0.04)
  force = 0.05,  -- N, pressing force after the ramp (cut_pressure needs 0.012 N)
  ramp = 0,      -- s, time the force takes to grow from 0 (0: constant)
  fps = 20,
  length = 0.06,  -- m, blade edge (the bar is 0.04 wide)
}
local s = softcut.scenario{ name = "press_in", duration = 1.0, fps = P.fps }
s:mesh{ generate = "box", options = { min = { 0, 0, 0 }, max = { 0.1, 0.04, 0.04 }, nx = 10, ny = 4, nz = 4 } }
s:material{ young = 5e3, poisson = 0.4 }
s:fix{ nodes = softcut.select.box{ min = { -1, -1, -1 }, max = { 0, 1, 1 } }
              + softcut.select.box{ min = { 0.1, -1, -1 }, max = { 1, 1, 1 } } }
s:operational{ box = { min = { 0.02, -1, -1 }, max = { 0.08, 1, 1 } } }
s:scalpel{
  name = "blade", axis = { 0, 1, 0 }, length = P.length, radius = 0.001, cut_pressure = 100,
  force = P.ramp > 0 and softcut.ramp.linear{ t1 = P.ramp, to = P.force } or P.force,
  path = softcut.path.polyline{ times = { 0, 0.9 }, points = { { 0.05, 0.02, P.z0 }, { 0.05, 0.02, 0 } } },
}
s:expect{ name = "cut through: two anchored pieces", at = 1.0, check = function(f)
  local c = f:cutting()
  return c.components == 2 and c.detached == 0,
         ("%d piece(s), %d detached, after %d cut events"):format(c.components, c.detached, c.events)
end }
return s
