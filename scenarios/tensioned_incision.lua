-- An incision that opens under tension (#17, paper Sec. 5 "initial strains"):
-- a layer of skin-like tissue is stretched over a frame, held on its four
-- sides. Its initial strain eps0 = -4 % in the plane means the tissue would
-- shrink by 4 % if it were freed, so held in place it is under tension; its
-- thickness strain is the one that leaves the free faces without traction
-- (zz = -2 nu / (1 - nu) x the in-plane value), so the held layer rests
-- exactly in its mesh shape, in biaxial tension. A scalpel cuts a 24 mm
-- incision through the whole layer; the cut releases the tension across it
-- and the lips pull apart: the incision gapes, as real incisions do.
--   softcut run scenarios/tensioned_incision.lua --set tension=-0.08
local P = softcut.params{
  tension = -0.04,      -- initial in-plane strain (negative: under tension when held)
  press = 0.6,          -- N, blade force at full ramp
  cut_pressure = 6e3,   -- Pa
  model = "corotational",  -- the lips turn by 5 deg as they part
}

local s = softcut.scenario{
  name = "tensioned_incision", duration = 1.6, fps = 20, tolerance = 1e-6,
  description = "an incision through a tensioned tissue layer held on a frame gapes open (initial strain)",
}
local w, d, h = 0.06, 0.04, 0.006
s:mesh{ generate = "box", options = { min = { 0, 0, 0 }, max = { w, d, h }, nx = 12, ny = 8, nz = 3 } }
local E, nu = 2e4, 0.45  -- dermis-like at small strain
s:material{ young = E, poisson = nu, model = P.model }
s:prestress{ tensor = { xx = P.tension, yy = P.tension, zz = -2 * nu / (1 - nu) * P.tension } }
local frame = softcut.select.box{ min = { -1, -1, -1 }, max = { 0, 1, 1 } } + softcut.select.box{ min = { w, -1, -1 }, max = { 1, 1, 1 } }
            + softcut.select.box{ min = { -1, -1, -1 }, max = { 1, 0, 1 } } + softcut.select.box{ min = { -1, d, -1 }, max = { 1, 1, 1 } }
s:fix{ nodes = frame }
s:operational{ box = { min = { 0.01, 0.01, -1 }, max = { 0.05, 0.03, 1 } } }

-- The incision plane y = yc lies 1.5 mm off a node plane, so the blade splits tets.
local yc, xc = 0.0215, 0.03
s:scalpel{
  name = "blade", length = 0.024, axis = { 1, 0, 0 }, radius = 0.001, cut_pressure = P.cut_pressure,
  path = softcut.path.polyline{
    times = { 0, 0.2, 0.4, 0.9, 1.1 },
    points = { { xc, yc, h + 0.01 }, { xc, yc, h + 0.0005 }, { xc, yc, h + 0.0005 },
               { xc, yc, -0.002 }, { xc, yc, h + 0.012 } } },
  force = softcut.ramp.linear{ t0 = 0.2, t1 = 0.4, to = P.press }, direction = { 0, 0, -1 }, stop = 1.15,
}

-- The lips: top-face nodes beside the middle of the incision, 1.5 mm on the
-- -y side and 3.5 mm on the +y side (rest positions).
local function lip(y) return softcut.select.box{ min = { xc - 0.006, y - 1e-4, h }, max = { xc + 0.006, y + 1e-4, h } } end
local minus, plus = lip(0.02), lip(0.025)

s:output{ log = softcut.select.surface() * softcut.select.box{ min = { 0.01, 0.01, h }, max = { 0.05, 0.03, h } },
          render = { width = 960, height = 600, azimuth = -60, elevation = 50, fov = 24, every = 2 } }

local function gap(f) return f:mean_displacement(plus)[2] - f:mean_displacement(minus)[2] end
s:expect{ name = "before the cut the tension moves nothing", at = 0.15, check = function(f)
  local m = f:max_displacement(softcut.select.surface())
  return m < 1e-12, ("largest surface displacement %.3g m before the cut"):format(m)
end }
s:expect{ name = "the blade cut through", at = 1.2, check = function(f)
  local c = f:cutting()
  return c.events > 0 and c.nodes_added > 10 and c.components == 1,
    ("%d cut events, %d nodes added, %d pieces"):format(c.events, c.nodes_added, c.components)
end }
-- A 24 mm slit in an endless sheet under the same tension opens by at most
-- 4 (sigma / E) a = 4 |tension| / (1 - nu) x 12 mm = 3.5 mm at its middle;
-- the frame 8 mm from the cut's ends holds the lips back, so less here.
local bound = 4 * math.abs(P.tension) / (1 - nu) * 0.012
s:expect{ name = "the incision gapes", at = 1.6, check = function(f)
  local g = gap(f)
  return g > 0.25 * bound and g < bound, ("lips %.2f mm further apart than at rest (sheet bound %.2f mm)"):format(1e3 * g, 1e3 * bound)
end }

return s
