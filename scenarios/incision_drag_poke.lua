-- Cutting with dragging and poking (Wu & Heng 2005, Fig. 11) on a liver: a
-- scalpel presses the dome of the right lobe, cuts an incision into the
-- operational region once its contact pressure passes the threshold, and is
-- lifted out. The liver's outer layer is under tension (an initial strain,
-- paper Sec. 5, held by the tissue beneath it), so the incision gapes; its
-- floor reaches a stiff lesion. A grasper then takes one lip over its jaw's
-- area and drags it open while a probe pokes the other side. The liver is
-- held at its underside; the incision is partial, so it stays one piece.
--   softcut run scenarios/incision_drag_poke.lua --set depth=0.006
local P = softcut.params{
  depth = 0.011,        -- m, incision depth (the lesion's top is 9 mm down)
  press = 0.6,          -- N, blade force at full ramp
  cut_pressure = 6e3,   -- Pa: reached at 0.29 N over the 24 mm x 2 mm contact strip
  drag = 0.014,         -- m, how far the grasper pulls the lip (+y)
  poke = 0.25,          -- N, probe force on the other lip
  tension = -0.04,      -- initial in-plane strain of the outer layer (negative: under tension when held)
  layer = 0.01,         -- m, thickness of the tensioned layer
  model = "neohookean", -- the dragged lip stretches by half and turns by 50 deg: "linear" (the paper's law) smears it
}

local s = softcut.scenario{
  name = "incision_drag_poke", duration = 2.4, fps = 20, tolerance = 1e-6,
  description = "scalpel incision over a lesion in a liver under tension, then one lip dragged open and the other poked (Fig. 11)",
}
-- The incision site: the right lobe's dome, meshed finer than the rest
-- (CGAL Mesh_3, graded: the operational region fine, the condensed rest coarse).
-- The mesh ships as a file because CGAL's result depends on the compiler and
-- its flags, and the reference log must not; it was made with
--   softcut mesh generate liver --target-tets 6000 --fine-center 0.03,0,0.045 --fine-radius 0.022
--     --fine-ratio 0.3 --lesion-center 0.03,0.004,0.027 --lesion-radius 0.007 scenarios/meshes/liver.vtu
-- (in a scenario: s:mesh{ generate = "liver", options = { target_tets = 6000, ... } }).
local xc, yc = 0.03, 0.0
local m = s:mesh{ file = "meshes/liver.vtu" }  -- 1260 nodes, 5979 tets; labels 1 (liver), 2 (lesion)
local top = m.max[3]  -- the dome's top, m
s:material{ tissue = "liver", model = P.model }
s:material{ label = 2, young = 3e4, poisson = 0.45, model = P.model }  -- the lesion: stiffer
-- The outer layer of the dome would shrink by 4 % in its plane if freed (with
-- the vertical strain that leaves its top free of traction); the tissue below
-- holds it, so it is under tension and an incision gapes.
local nu = 0.45
s:prestress{ halfspace = { point = { 0, 0, top - P.layer }, normal = { 0, 0, 1 } },
             tensor = { xx = P.tension, yy = P.tension, zz = -2 * nu / (1 - nu) * P.tension } }
local base = softcut.select.box{ min = { -1, -1, -1 }, max = { 1, 1, -0.019 } }  -- the flattened underside
s:fix{ nodes = base }
s:operational{ sphere = { center = { xc, yc, top }, radius = 0.02 } }

-- Blade: a 24 mm edge along x over the dome.
s:scalpel{
  name = "blade", length = 0.024, axis = { 1, 0, 0 }, radius = 0.001, cut_pressure = P.cut_pressure,
  path = softcut.path.polyline{
    times = { 0, 0.2, 0.4, 0.9, 1.1 },
    points = { { xc, yc, top + 0.01 }, { xc, yc, top + 0.0005 }, { xc, yc, top + 0.0005 },
               { xc, yc, top - P.depth }, { xc, yc, top + 0.012 } } },
  force = softcut.ramp.linear{ t0 = 0.2, t1 = 0.4, to = P.press }, direction = { 0, 0, -1 }, stop = 1.15,
}
-- Grasper on the +y lip, 4 mm off the cut, dragging it open.
s:grasper{
  name = "jaw", radius = 0.002, stiffness = 400, start = 1.2, shaft = { 0.2, 0.7, 1 },  -- drawn in from a port beyond the lip
  path = softcut.path.polyline{ times = { 1.2, 2.0 }, points = { { xc, yc + 0.004, top }, { xc, yc + 0.004 + P.drag, top + 0.004 } } },
}
-- Probe pressing the -y lip down over its contact circle. A force-driven
-- probe acts only where its sphere reaches the surface, so its path follows
-- the dent it makes (4 mm over the ramp).
s:probe{
  name = "tip", radius = 0.003, start = 1.6, force = softcut.ramp.smoothstep{ t0 = 1.6, t1 = 2.1, to = P.poke },
  shaft = { 0.7, -0.1, 1 },  -- drawn in from a second port
  path = softcut.path.polyline{ times = { 1.6, 2.1 },
    points = { { xc - 0.006, yc - 0.0065, top + 0.001 }, { xc - 0.006, yc - 0.0065, top - 0.004 } } },
}

local site = softcut.select.surface() * softcut.select.sphere{ center = { xc, yc, top }, radius = 0.02 }
s:output{ log = site,
          render = { width = 960, height = 600, eye = { xc - 0.05, yc - 0.065, top + 0.13 }, target = { xc - 0.012, yc + 0.004, top - 0.01 },
                     fov = 34, every = 2, show_interface = false } }

s:expect{ name = "the blade cut an incision", at = 1.2, check = function(f)
  local c = f:cutting()
  return c.events > 0 and c.nodes_added > 10, ("%d cut events, %d nodes added"):format(c.events, c.nodes_added)
end }
s:expect{ name = "partial cut: still one piece", at = 2.4, check = function(f)
  local c = f:cutting()
  return c.components == 1, ("%d connected pieces"):format(c.components)
end }
-- The lips: surface nodes in 3 mm bands either side of the cut, near the top.
local function lip(y)
  return softcut.select.surface() * softcut.select.box{ min = { xc - 0.008, y - 0.0015, top - 0.003 }, max = { xc + 0.008, y + 0.0015, top + 0.001 } }
end
local function gap(f) return f:mean_displacement(lip(yc + 0.004))[2] - f:mean_displacement(lip(yc - 0.004))[2] end
local before
s:expect{ name = "under tension before the cut, the lips draw together", at = 0.15, check = function(f)
  before = gap(f)
  return before < 0, ("lips %.3f mm apart from rest before the blade touches"):format(1e3 * before)
end }
-- Without the tension (--set tension=0) the lips do not move apart: 0.000 mm.
s:expect{ name = "the incision gapes", at = 1.15, check = function(f)
  local opened = gap(f) - before
  return opened > 3e-4, ("lips %.2f mm further apart than before the cut, before anything pulls them"):format(1e3 * opened)
end }
s:expect{ name = "the probe presses to the end", at = 2.4, check = function(f) return f:tool("tip").engaged end,
          message = "the probe lost contact" }
s:expect{ name = "the grasper holds the lip", at = 2.0, check = function(f) return f:tool("jaw").engaged end,
          message = "grasper let go" }
s:expect{ name = "base fixed", at = 2.4, nodes = base, measure = "max", max = 0 }

return s
