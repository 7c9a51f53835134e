-- A kidney brought as surfaces, as a segmentation tool exports them: an STL
-- of the organ and an OBJ of a stiff lesion inside it, in millimetres (written
-- by numpy and meshio: meshes/make_kidney_surfaces.py). Held at its hilum
-- (the renal pedicle), the kidney is pressed on its convex side over the
-- lesion, as a palpating probe would.
--   softcut run scenarios/kidney_surface.lua --set press=0.6
-- The mesh (labels 1: kidney, 2: lesion) was made from the surfaces by
--   softcut mesh generate surface scenarios/meshes/kidney_mm.stl scenarios/meshes/kidney_lesion_mm.obj \
--     --unit mm --target-tets 5000 --fine-center 0.025,-0.03,0 --fine-radius 0.02 --fine-ratio 0.5 \
--     scenarios/meshes/kidney_surface.vtu
-- (shipped as a file so that the reference log holds on every build: docs/meshing.md). Meshing
-- while the scenario runs is one line instead:
--   s:mesh{ generate = "surface", options = { file = { "meshes/kidney_mm.stl", "meshes/kidney_lesion_mm.obj" },
--           unit = "mm", target_tets = 5000 } }
local P = softcut.params{
  press = 0.3,         -- N, total force pressing the convex side
  lesion_young = 1e5,  -- Pa, lesion stiffness (kidney tissue: 20.7 kPa)
}

local s = softcut.scenario{
  name = "kidney_surface", duration = 1.0, fps = 20, tolerance = 1e-6,
  description = "a kidney meshed from STL/OBJ surfaces, held at its hilum, pressed over a stiff lesion",
}
local m = s:mesh{ file = "meshes/kidney_surface.vtu" }  -- long axis x, 110 mm; the hilum faces +y

s:material{ tissue = "kidney" }
s:material{ label = 2, young = P.lesion_young, poisson = 0.45 }

-- The renal pedicle: the hilum's surface, the concave middle of the +y side.
local hilum = softcut.select.surface() * softcut.select.box{ min = { -0.015, 0.012, -0.012 }, max = { 0.015, 1, 0.012 } }
s:fix{ nodes = hilum }

-- The pressed patch on the convex (-y) side, over the lesion (7 mm at (25, -5, 2) mm).
local over = { 0.025, -0.028, 0.002 }
local patch = softcut.select.surface() * softcut.select.sphere{ center = over, radius = 0.008 }
  * softcut.select.halfspace{ point = { 0, -0.02, 0 }, normal = { 0, -1, 0 } }
s:operational{ sphere = { center = { 0.025, -0.02, 0 }, radius = 0.025 } }
s:load{ name = "press", nodes = patch, normal = -P.press, ramp = softcut.ramp.smoothstep{ t0 = 0, t1 = 0.6 } }

local lesion = softcut.select.label(2)
local far_pole = softcut.select.box{ min = { -1, -1, -1 }, max = { -0.045, 1, 1 } }
s:output{ log = patch + lesion + far_pole * softcut.select.surface() }

s:expect{ name = "the patch is pressed in", at = 1.0, nodes = patch, component = "y", min = 0.0008, max = 0.004 }
s:expect{ name = "the hilum is held", at = 1.0, nodes = hilum, measure = "max", max = 0 }
-- Held only at its hilum, the kidney turns about it like a lever: pressed
-- toward +y on one side of the hilum, its far pole swings toward -y, less far.
s:expect{ name = "the kidney turns about its hilum", at = 1.0, check = function(f)
  local u_far, u_patch = f:mean_displacement(far_pole * softcut.select.surface())[2], f:mean_displacement(patch)[2]
  return u_far < 0 and -u_far < u_patch, ("far pole %.3f mm, patch %.3f mm along +y"):format(1000 * u_far, 1000 * u_patch)
end }
s:expect{ name = "the stiff lesion moves less than the tissue pressed over it", at = 1.0, check = function(f)
  local u_lesion, u_patch = f:mean_displacement(lesion)[2], f:mean_displacement(patch)[2]
  return u_lesion > 0 and u_lesion < u_patch,
    ("lesion %.3f mm, patch %.3f mm along +y"):format(1000 * u_lesion, 1000 * u_patch)
end }

return s
