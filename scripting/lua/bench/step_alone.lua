-- The step of a Lua controller alone, without the simulator, on any Lua
-- interpreter (5.3, 5.4, LuaJIT): N robots, each with a `robot` table shaped
-- as the host makes it (24 proximity readings {value, angle}, wheels with a
-- set_velocity that does nothing) and an environment of its own in one state,
-- as the host's shared states give (scripting/lua/README.md, "Lua states").
-- Every robot runs the script's top level and init(), then step() is called
-- for every robot, TICKS times; the readings never change (4 of the 24 see
-- something), so every step does the same work. Prints the time per step.
--
--   lua5.3 scripting/lua/bench/step_alone.lua SCRIPT N [TICKS]
--
-- Run by scripting/lua/bench/interpreters.py (BENCHMARK-NOTES.md, "Is any
-- interpreter fast enough?").
local script, n, ticks = arg[1], tonumber(arg[2]), tonumber(arg[3] or 200)
if not (script and n) then
  io.stderr:write("usage: step_alone.lua SCRIPT N [TICKS]\n")
  os.exit(2)
end
local file = assert(io.open(script))
local source = file:read("*a")
file:close()

-- The script is compiled once and run once per robot with the robot's
-- environment, as the host does: every robot's step() is a closure of the same
-- compiled function. Lua 5.2 and later take the environment as the chunk's
-- _ENV (declared on its first line, so line numbers stay); LuaJIT (5.1) from
-- the running function when step() is made, set with setfenv. LuaJIT's
-- math.atan takes one argument: the robots get atan2 as math.atan.
local run_as
if setfenv then
  local chunk = assert(loadstring(source, "=" .. script))
  run_as = function(env)
    setfenv(chunk, env)
    chunk()
  end
else
  local chunk = assert(load("local _ENV = ...; " .. source, "=" .. script))
  run_as = function(env) chunk(env) end
end
local robot_math = math
if setfenv then robot_math = setmetatable({atan = math.atan2}, {__index = math}) end
local function set_velocity(left, right) end

local steps = {}
for r = 1, n do
  local proximity = {}
  for i = 1, 24 do
    proximity[i] = {angle = (i - 0.5) * 2 * math.pi / 24, value = (i % 7 == 1) and 0.2 or 0}
  end
  local env = setmetatable({math = robot_math}, {__index = _G})
  env.robot = {id = "fb" .. r, params = {}, proximity = proximity,
               wheels = {set_velocity = set_velocity}}
  run_as(env)
  if env.init then env.init() end
  steps[r] = env.step
end

local clock = os.clock
local start = clock()
for _ = 1, ticks do
  for r = 1, n do steps[r]() end
end
local seconds = clock() - start
print(string.format("ns_per_step=%.0f", seconds / ticks / n * 1e9))
