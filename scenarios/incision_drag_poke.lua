-- Cutting with dragging and poking (Wu & Heng 2005, Fig. 11): a scalpel
-- presses a block of liver tissue, cuts an incision into the operational
-- region once its contact pressure passes the threshold, and is lifted out;
-- the tissue is under tension (an initial strain, paper Sec. 5), so the
-- incision gapes; a grasper then takes one lip over its jaw's area and drags
-- it open while a probe pokes the other side. The incision is partial, so
-- the body stays one piece, held at its base and sides.
--   softcut run scenarios/incision_drag_poke.lua --set depth=0.015
local P = softcut.params{
  depth = 0.008,        -- m, incision depth
  press = 0.6,          -- N, blade force at full ramp
  cut_pressure = 6e3,   -- Pa: reached at 0.29 N over the 24 mm x 2 mm contact strip
  drag = 0.014,         -- m, how far the grasper pulls the lip (+y)
  poke = 0.25,          -- N, probe force on the other lip
  tension = -0.04,      -- initial horizontal strain (negative: under tension when held)
}

local s = softcut.scenario{
  name = "incision_drag_poke", duration = 2.4, fps = 20, tolerance = 1e-6,
  description = "scalpel incision in a liver block, then one lip dragged open and the other poked (Fig. 11)",
}
local m = s:mesh{ generate = "box", options = { min = { 0, 0, 0 }, max = { 0.06, 0.04, 0.024 }, nx = 12, ny = 8, nz = 5 } }
s:material{ tissue = "liver" }
-- Tissue in place is under tension: held at its base and sides, it would
-- shrink by 4 % in the horizontal plane if freed (with the vertical strain
-- that leaves its top free of traction), so the incision gapes.
local nu = 0.45
s:prestress{ tensor = { xx = P.tension, yy = P.tension, zz = -2 * nu / (1 - nu) * P.tension } }
local held = softcut.select.box{ min = { -1, -1, 0 }, max = { 1, 1, 0 } }                                -- base
  + softcut.select.box{ min = { -1, -1, -1 }, max = { 0, 1, 1 } } + softcut.select.box{ min = { 0.06, -1, -1 }, max = { 1, 1, 1 } }
  + softcut.select.box{ min = { -1, -1, -1 }, max = { 1, 0, 1 } } + softcut.select.box{ min = { -1, 0.04, -1 }, max = { 1, 1, 1 } }
s:fix{ nodes = held }
s:operational{ box = { min = { 0.008, 0.008, 0.008 }, max = { 0.052, 0.032, 0.025 } } }

-- The incision plane y = yc lies 1.5 mm off a node plane, so the blade splits tets.
local top, yc, xc = 0.024, 0.0215, 0.03
-- Blade: a 24 mm edge along x over the middle of the top face.
s:scalpel{
  name = "blade", length = 0.024, axis = { 1, 0, 0 }, radius = 0.001, cut_pressure = P.cut_pressure,
  path = softcut.path.polyline{
    times = { 0, 0.2, 0.4, 0.9, 1.1 },
    points = { { xc, yc, top + 0.01 }, { xc, yc, top + 0.0005 }, { xc, yc, top + 0.0005 },
               { xc, yc, top - P.depth }, { xc, yc, top + 0.012 } } },
  force = softcut.ramp.linear{ t0 = 0.2, t1 = 0.4, to = P.press }, direction = { 0, 0, -1 }, stop = 1.15,
}
-- Grasper on the +y lip (the row of nodes 3.5 mm off the cut), dragging it open.
s:grasper{
  name = "jaw", radius = 0.002, stiffness = 400, start = 1.2,
  path = softcut.path.polyline{ times = { 1.2, 2.0 }, points = { { xc, yc + 0.0035, top }, { xc, yc + 0.0035 + P.drag, top + 0.004 } } },
}
-- Probe pressing the -y lip down over its contact circle. A force-driven
-- probe acts only where its sphere reaches the surface, so its path follows
-- the dent it makes (4 mm over the ramp).
s:probe{
  name = "tip", radius = 0.003, start = 1.6, force = softcut.ramp.smoothstep{ t0 = 1.6, t1 = 2.1, to = P.poke },
  path = softcut.path.polyline{ times = { 1.6, 2.1 },
    points = { { xc - 0.008, yc - 0.0065, top + 0.001 }, { xc - 0.008, yc - 0.0065, top - 0.004 } } },
}

s:output{ log = softcut.select.surface() * softcut.select.box{ min = { 0.015, 0.012, 0.015 }, max = { 0.045, 0.031, 0.025 } },
          render = { width = 960, height = 600, azimuth = -60, elevation = 40, fov = 22, every = 2, show_interface = false } }

s:expect{ name = "the blade cut an incision", at = 1.2, check = function(f)
  local c = f:cutting()
  return c.events > 0 and c.nodes_added > 10, ("%d cut events, %d nodes added"):format(c.events, c.nodes_added)
end }
s:expect{ name = "partial cut: still one piece", at = 2.4, check = function(f)
  local c = f:cutting()
  return c.components == 1, ("%d connected pieces"):format(c.components)
end }
local function lip(y) return softcut.select.box{ min = { xc - 0.006, y - 1e-4, top }, max = { xc + 0.006, y + 1e-4, top } } end
local function gap(f) return f:mean_displacement(lip(0.025))[2] - f:mean_displacement(lip(0.02))[2] end
s:expect{ name = "held in place, the tension moves nothing", at = 0.15, check = function(f)
  local m = f:max_displacement(softcut.select.surface())
  return m < 1e-12, ("largest surface displacement %.3g m before the blade touches"):format(m)
end }
-- Without the tension (--set tension=0) the lips stay where they were: 0.000 mm.
s:expect{ name = "the incision gapes", at = 1.15, check = function(f)
  return gap(f) > 3e-4, ("lips %.2f mm further apart than at rest, before anything pulls them"):format(1e3 * gap(f))
end }
s:expect{ name = "the probe presses to the end", at = 2.4, check = function(f) return f:tool("tip").engaged end,
          message = "the probe lost contact" }
s:expect{ name = "the grasper holds the lip", at = 2.0, check = function(f) return f:tool("jaw").engaged end,
          message = "grasper let go" }
s:expect{ name = "base fixed", at = 2.4, nodes = softcut.select.box{ min = { -1, -1, 0 }, max = { 1, 1, 0 } }, measure = "max", max = 0 }

return s
