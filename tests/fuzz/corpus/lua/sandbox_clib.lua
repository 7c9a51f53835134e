-- Seeds around C library work charged by size and the sandboxed io (#13).
local t = {}
for i = 1, 100 do t[i] = tostring(i) end
local s1 = string.rep("ab", 100, ",")
local s2 = table.concat(t, " ", 1, #t)
table.move(t, 1, 50, 51)
table.insert(t, 1, "x") table.remove(t, 1)
table.sort(t)
local a, b = table.unpack(t, 1, 2)
local n = utf8.len(s2)
local f = load("return " .. string.rep("1+", 10) .. "1")
collectgarbage("step", 10)
local ok, e = pcall(io.open, "../outside.txt")
local h = io.open("missing.txt")
local s = softcut.scenario{ name = "fuzz_clib", duration = 0.1, fps = 10 }
s:mesh{ generate = "box", options = { min = {0, 0, 0}, max = {0.1, 0.04, 0.04}, nx = 2, ny = 1, nz = 1 } }
s:fix{ nodes = softcut.select.box{ min = {0, 0, 0}, max = {0, 0.04, 0.04} } }
return s
