-- String patterns in the sandbox: every call is bounded before it runs.
local name = ("liver_left-lobe.v2"):gsub("[^%w_]", "_")
local k, v = ("  force = 0.05  # N"):match("^%s*([%w_]+)%s*=%s*(.-)%s*#")
local fields = {}
for f in ("node,12,0.25,-3e-4,,tip"):gmatch("([^,]*)") do fields[#fields + 1] = f end
local inner = ("f(a, g(b, c), d)"):match("%b()")
local q = ('say "hi"'):match("([\"'])(.-)%1")
local n = select(2, ("the cut, the tool"):gsub("%f[%w]the%f[%W]", "a"))
local at = string.find("a.b*c(d", "*c(", 1, true)
local ok = pcall(string.match, ("a"):rep(40), ("a*"):rep(40) .. "b")
local s = softcut.scenario{ name = name, duration = tonumber(v) * 10, fps = 10 }
s:mesh{ generate = "box", options = { min = {0, 0, 0}, max = {0.1, 0.04, 0.04}, nx = #fields - 2, ny = 2, nz = 2 } }
s:material{ tissue = "liver" }
s:fix{ nodes = softcut.select.box{ min = {0, 0, 0}, max = {0, 0.04, 0.04} } }
return s
