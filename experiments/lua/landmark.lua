-- Gather at the landmark, with the omnidirectional camera. A robot wanders
-- (a random walk, turning away from obstacles) until its camera sees the
-- green landmark, or a red robot: one that got there first. It then drives
-- to the nearest of them (the landmark first) and stops within
-- STOP_DISTANCE of the landmark, or where its way is blocked within TOUCH
-- of the landmark or of a red robot, and lights red itself. So the gathering grows
-- around the landmark and is seen from farther away. Searching robots are
-- blue; the landmark is told from the robots by its colour.
local swarm_math = require("swarm_math")

VELOCITY = 10        -- cm/s
STOP_DISTANCE = 30   -- cm from the landmark's axis
TOUCH = 40           -- cm: a blocked robot this near its target stops
BLOCKED = 0.1        -- proximity vector length at which the way counts as blocked

local arrived = false

local function is_green(c) return c.green > 200 and c.red < 50 and c.blue < 50 end
local function is_red(c) return c.red > 200 and c.green < 50 and c.blue < 50 end

-- The nearest blob of the colour `is_colour` accepts, or nil.
local function nearest(blobs, is_colour)
   local best = nil
   for _, blob in ipairs(blobs) do
      if is_colour(blob.color) and (best == nil or blob.distance < best.distance) then
         best = blob
      end
   end
   return best
end

local function arrive()
   arrived = true
   robot.leds.set_all_colors("red")
   robot.wheels.set_velocity(0, 0)
end

function init()
   robot.colored_blob_omnidirectional_camera.enable()
   robot.leds.set_all_colors("blue")
end

function step()
   if arrived then return end
   local ox, oy = swarm_math.obstacle_vector(robot.proximity)
   local obstacle = math.atan(oy, ox)
   local obstacle_ahead = math.sqrt(ox * ox + oy * oy) > BLOCKED
                          and math.abs(obstacle) < math.pi / 2
   local blobs = robot.colored_blob_omnidirectional_camera
   local landmark = nearest(blobs, is_green)
   local red = nearest(blobs, is_red)
   local target = landmark or red
   if landmark and landmark.distance < STOP_DISTANCE then
      arrive()
   elseif obstacle_ahead and ((landmark and landmark.distance < TOUCH)
                              or (red and red.distance < TOUCH)) then
      arrive()
   elseif obstacle_ahead then
      if obstacle > 0 then
         robot.wheels.set_velocity(VELOCITY, -VELOCITY)
      else
         robot.wheels.set_velocity(-VELOCITY, VELOCITY)
      end
   elseif target then
      robot.wheels.set_velocity(swarm_math.steer(target.angle, VELOCITY))
   elseif robot.random.bernoulli(0.05) then
      -- A random walk: mostly straight, now and then a turn.
      local turn = robot.random.uniform(-VELOCITY, VELOCITY)
      robot.wheels.set_velocity(VELOCITY + turn, VELOCITY - turn)
   else
      robot.wheels.set_velocity(VELOCITY, VELOCITY)
   end
end

function reset()
   arrived = false
   robot.leds.set_all_colors("blue")
end

function destroy()
end
