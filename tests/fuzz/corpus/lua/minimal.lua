local P = softcut.params{ force = 0.05 }
local s = softcut.scenario{ name = "fuzz_minimal", duration = 0.5, fps = 10 }
s:mesh{ generate = "box", options = { min = {0, 0, 0}, max = {0.1, 0.04, 0.04}, nx = 4, ny = 2, nz = 2 } }
s:material{ tissue = "liver" }
s:fix{ nodes = softcut.select.box{ min = {0, 0, 0}, max = {0, 0.04, 0.04} } }
local tip = softcut.select.box{ min = {0.1, 0, 0}, max = {0.1, 0.04, 0.04} }
s:load{ name = "pull", nodes = tip, force = {0, 0, -P.force}, ramp = softcut.ramp.linear{ t1 = 0.5 } }
s:expect{ name = "down", at = 0.5, nodes = tip, component = "z", max = 0 }
return s
