-- The paper's second experiment (Wu & Heng 2005, Sec. 5, Figs. 5, 9, 10): a
-- small portion of the upper leg, soft tissue around the thighbone. The nodes
-- on the bone's surface (the hole) are fixed. The operational region (where
-- cutting happens) is on the front; in the NONoperational region a probe pokes
-- the side and a grasper drags the back, as in Fig. 10.
--   softcut run scenarios/upper_leg.lua --set poke_force=0.3
local P = softcut.params{
  poke_force = 0.5,      -- N, peak probe force
  drag = 0.01,           -- m, grasper travel along the leg
  stiffness = 80,        -- N/m, grasper spring (total); explicit springs need k x compliance < 1
}

local s = softcut.scenario{
  name = "upper_leg", duration = 2.0, fps = 30, tolerance = 1e-6,
  description = "upper leg: bone fixed, probe pokes and grasper drags the nonoperational region",
}
-- The paper's model size: about 785 nodes and 2550 tets (tube preset: inner
-- radius 12 mm = the bone, outer 24 mm, 30 mm long, axis +z).
local m = s:mesh{ generate = "upper_leg", options = { radial = 2, around = 12, layers = 3 } }  -- explicit cells: the resolution search is slow under ASan
s:material{ tissue = "muscle" }
s:fix{ nodes = softcut.select.named("hole") }
s:operational{ sphere = { center = { 0.024, 0, 0.015 }, radius = 0.011 } }

-- Probe on the -x side: approaches, pushes with a smooth force, withdraws.
local side = { -0.024, 0, 0.015 }
s:probe{
  name = "probe", radius = 0.004,
  path = softcut.path.polyline{ times = { 0, 0.4, 1.6, 2.0 },
                                points = { { -0.032, 0, 0.015 }, { -0.0255, 0, 0.015 }, { -0.0255, 0, 0.015 }, { -0.032, 0, 0.015 } } },
  force = softcut.ramp.keyframes{ times = { 0.3, 0.9, 1.4, 1.8 }, values = { 0, P.poke_force, P.poke_force, 0 } },
}

-- Grasper on the -y side: grasps at 0.2 s and drags along the leg (+z).
local back = { 0, -0.0265, 0.012 }
s:grasper{
  name = "grasper", radius = 0.004, stiffness = P.stiffness, start = 0.2,
  path = softcut.path.catmull_rom{ times = { 0, 0.5, 1.5, 2.0 },
    points = { back, back, softcut.vec.add(back, { 0, 0, 0.8 * P.drag }), softcut.vec.add(back, { 0, 0, P.drag }) } },
}

local poked = softcut.select.sphere{ center = side, radius = 0.005 } * softcut.select.surface()
local grasped = softcut.select.sphere{ center = { 0, -0.024, 0.012 }, radius = 0.005 } * softcut.select.surface()
local bone = softcut.select.named("hole")
-- Log the outer surface at mid-length (keeps the reference log small).
s:output{ log = softcut.select.surface() * softcut.select.box{ min = { -1, -1, 0.01 }, max = { 1, 1, 0.02 } } - bone }

-- Peak indentation over the run, tracked frame by frame.
local peak = 0
s:on_frame(function(f)
  peak = math.max(peak, f:mean_displacement(poked)[1])
end)

s:expect{ name = "probe indents", at = 1.2, nodes = poked, component = "x", min = 0.0015, max = 0.0028 }
s:expect{ name = "tissue springs back", at = 2.0, nodes = poked, component = "x", min = -1e-4, max = 1e-4 }
s:expect{ name = "grasper drags along the leg", at = 2.0, nodes = grasped, component = "z", min = 0.3 * P.drag, max = 0.6 * P.drag }
s:expect{ name = "bone stays fixed", at = 2.0, nodes = bone, measure = "max", max = 0 }
s:expect{ name = "peak indentation", at = 2.0, check = function(f)
  return peak > 0.0015 and peak < 0.003, ("peak indentation %.3f mm"):format(1000 * peak)
end }
s:expect{ name = "grasper holds", at = 1.0, check = function(f) return f:tool("grasper").engaged end,
          message = "the grasper let go before t = 1 s" }

return s
