-- Diffusion: wander and avoid obstacles with the proximity ring, the Lua
-- twin of the C++ controller controllers/diffusion. The readings, summed as
-- vectors along their sensors' directions, point at what is near. Drive
-- straight while that vector is short and within ALPHA of the heading (or
-- points behind), otherwise turn on the spot away from it.

-- Defaults; <params alpha="7.5" delta="0.1" velocity="5"/> overrides them.
local ALPHA = math.rad(7.5)  -- half-width of the cone "ahead" (rad)
local DELTA = 0.1            -- vector length from which an obstacle counts
local VELOCITY = 5           -- wheel speed (cm/s)

-- Kept in locals: step() runs every tick on every robot, and a local costs
-- less than a global or a table field.
local atan, sqrt, abs, pi = math.atan, math.sqrt, math.abs, math.pi
local proximity, wheels
-- The sensors' directions never change: their unit vectors, once.
local cos_angle, sin_angle = {}, {}

function init()
   if robot.params.alpha then ALPHA = math.rad(tonumber(robot.params.alpha)) end
   if robot.params.delta then DELTA = tonumber(robot.params.delta) end
   if robot.params.velocity then VELOCITY = tonumber(robot.params.velocity) end
   proximity, wheels = robot.proximity, robot.wheels
   for i = 1, #proximity do
      cos_angle[i] = math.cos(proximity[i].angle)
      sin_angle[i] = math.sin(proximity[i].angle)
   end
end

function step()
   local n = #proximity
   local x, y = 0, 0
   for i = 1, n do
      local value = proximity[i].value
      if value > 0 then
         x = x + value * cos_angle[i]
         y = y + value * sin_angle[i]
      end
   end
   x, y = x / n, y / n
   local angle = atan(y, x)
   local length = sqrt(x * x + y * y)
   if (abs(angle) <= ALPHA and length < DELTA) or abs(angle) > pi / 2 then
      wheels.set_velocity(VELOCITY, VELOCITY)
   elseif angle > 0 then
      wheels.set_velocity(VELOCITY, -VELOCITY)  -- obstacle on the left: turn right
   else
      wheels.set_velocity(-VELOCITY, VELOCITY)  -- obstacle on the right: turn left
   end
end

function reset()
end

function destroy()
end
