-- Seeds for the fuzzer's search around the sandbox's sticky stops (#13):
-- errors caught by pcall / xpcall / coroutines around endless loops.
local n = 0
while n < 3 do
  n = n + 1
  pcall(function() local i = 0 while i < 10 do i = i + 1 end end)
  xpcall(function() error("x") end, function(m) return m end)
  coroutine.resume(coroutine.create(function() coroutine.yield(1) end))
  local co = coroutine.wrap(function() return 1 end) co()
end
local ok = pcall(setmetatable, {}, { __gc = function() end })
local t <close> = setmetatable({}, { __close = function() end })
local s = softcut.scenario{ name = "fuzz_catch", duration = 0.1, fps = 10 }
s:mesh{ generate = "box", options = { min = {0, 0, 0}, max = {0.1, 0.04, 0.04}, nx = 2, ny = 1, nz = 1 } }
s:fix{ nodes = softcut.select.box{ min = {0, 0, 0}, max = {0, 0.04, 0.04} } }
return s
