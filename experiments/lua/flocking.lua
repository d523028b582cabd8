-- Flocking with range-and-bearing, the Lua twin of the C++ controller
-- controllers/flocking. Every step a robot broadcasts its heading (from the
-- positioning sensor, used as a compass) as a unit vector in two bytes, and
-- steers towards the sum of
--   alignment: the mean heading of itself and the neighbours it hears;
--   cohesion:  GAIN x the mean, over neighbours, of a Lennard-Jones-like pull
--              beyond TARGET_DISTANCE and push within it, along their bearing;
--   avoidance: -AVOIDANCE x the proximity ring's vector.
local swarm_math = require("swarm_math")

VELOCITY = 10          -- cm/s
TARGET_DISTANCE = 40   -- cm
GAIN = 1
MAX_REPULSION = 4
ALIGNMENT = 1
AVOIDANCE = 5

-- > 0 attracts (the neighbour is farther than the target distance).
local function lennard_jones(d)
   local s = (TARGET_DISTANCE / d) ^ 2
   return math.max(s - s * s, -MAX_REPULSION)
end

function init()
   robot.leds.set_all_colors("cyan")
end

function step()
   local yaw = swarm_math.yaw(robot.positioning.orientation)
   local c, s = math.cos(yaw), math.sin(yaw)
   robot.range_and_bearing.set_data(1, swarm_math.encode(c))
   robot.range_and_bearing.set_data(2, swarm_math.encode(s))

   -- Neighbours' headings summed in the arena's frame; cohesion in the robot's.
   local hx, hy, cx, cy, neighbours = 0, 0, 0, 0, 0
   for _, message in ipairs(robot.range_and_bearing) do
      if message.range > 0 then
         hx = hx + swarm_math.decode(message.data[1])
         hy = hy + swarm_math.decode(message.data[2])
         local f = lennard_jones(message.range)
         cx = cx + f * math.cos(message.horizontal_bearing)
         cy = cy + f * math.sin(message.horizontal_bearing)
         neighbours = neighbours + 1
      end
   end
   -- Its own heading plus its neighbours', turned into its own frame.
   local ax, ay = 1 + hx * c + hy * s, hy * c - hx * s
   local dx, dy = 0, 0
   local length = math.sqrt(ax * ax + ay * ay)
   if length > 1e-9 then
      dx, dy = ax * ALIGNMENT / length, ay * ALIGNMENT / length
   end
   if neighbours > 0 then
      dx = dx + cx * GAIN / neighbours
      dy = dy + cy * GAIN / neighbours
   end
   local ox, oy = swarm_math.obstacle_vector(robot.proximity)
   dx, dy = dx - AVOIDANCE * ox, dy - AVOIDANCE * oy
   robot.wheels.set_velocity(swarm_math.steer(math.atan(dy, dx), VELOCITY))
end

function reset()
end

function destroy()
end
