-- A piece cut free (docs/cutting.md "Pieces cut free"): a bar held at one end
-- only is cut through near its free end. The end piece has no fixed node; it
-- is held where it was when it separated (no rigid-body motion), loads and the
-- probe on it are ignored with a warning, and the attached part goes on
-- deforming under its load. Checked by ctest through `softcut check`.
local s = softcut.scenario{
  name = "cut_free", duration = 1.3, fps = 20, tolerance = 1e-6,
  description = "a cantilever bar cut through near its free end; the end piece is held",
}
s:mesh{ generate = "box", options = { min = { 0, 0, 0 }, max = { 0.1, 0.02, 0.02 }, nx = 10, ny = 4, nz = 4 } }
s:material{ young = 5e5, poisson = 0.4 }
s:fix{ nodes = softcut.select.box{ min = { -1, -1, -1 }, max = { 0, 1, 1 } } }
s:operational{ box = { min = { 0.03, -1, -1 }, max = { 0.1, 1, 1 } } }

local top = softcut.select.box{ min = { 0.015, -1, 0.02 }, max = { 0.095, 1, 1 } }
s:load{ name = "top", nodes = top, force = { 0, 0, -0.002 }, ramp = softcut.ramp.linear{ t1 = 1.2 } }

-- Blade: a 40 mm edge along y, pressing the top at x = 81.2 mm, then down
-- through the 20 mm section (0.012 N = 100 Pa over 40 mm x 3 mm).
local xc = 0.0812
s:scalpel{
  name = "blade", length = 0.04, axis = { 0, 1, 0 }, radius = 0.0015, cut_pressure = 100,
  path = softcut.path.polyline{ times = { 0, 0.3, 1.0 }, points = { { xc, 0.01, 0.0205 }, { xc, 0.01, 0.0205 }, { xc, 0.01, -0.004 } } },
  force = softcut.ramp.linear{ t1 = 0.2, to = 0.02 }, direction = { 0, 0, -1 },
}
-- After the cut a probe pokes the free end: ignored (the piece is held).
s:probe{ name = "probe", path = { 0.1, 0.01, 0.02 }, radius = 0.0045, force = 0.001, start = 1.05 }

local free_end = softcut.select.box{ min = { 0.1, -1, -1 }, max = { 1, 1, 1 } }
local middle = softcut.select.box{ min = { 0.05, -1, 0.02 }, max = { 0.05, 1, 1 } }
s:output{ log = free_end + middle }

local held_z, middle_z
s:expect{ name = "cut through: the end piece is free", at = 1.0, check = function(f)
  local c = f:cutting()
  held_z = f:mean_displacement(free_end)[3]
  middle_z = f:mean_displacement(middle)[3]
  return c.components == 2, ("%d connected pieces after %d cut events"):format(c.components, c.events)
end }
s:expect{ name = "the end piece stays where it separated", at = 1.3, check = function(f)
  local z = f:mean_displacement(free_end)[3]
  return z == held_z, ("free end z moved from %.17g to %.17g"):format(held_z, z)
end }
s:expect{ name = "the attached part goes on deforming", at = 1.3, check = function(f)
  local z = f:mean_displacement(middle)[3]
  return z < middle_z, ("middle z %.17g, at the cut %.17g"):format(z, middle_z)
end }

return s
