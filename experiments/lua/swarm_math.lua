-- Helpers shared by the swarm scripts, found by require("swarm_math")
-- beside them.
local swarm_math = {}

-- The robot's heading (rad, counter-clockwise from the arena's x axis) from
-- robot.positioning.orientation, a quaternion: its rotation about the
-- vertical axis.
function swarm_math.yaw(orientation)
   local angle, axis = orientation:toangleaxis()
   if axis.z < 0 then angle = -angle end
   return angle
end

-- Wheel speeds (cm/s) that turn towards `angle` (rad, robot frame, 0 ahead)
-- while driving at up to `speed`: full speed when the target is ahead,
-- slowing as it moves aside, turning on the spot when it is beside or behind.
function swarm_math.steer(angle, speed)
   angle = math.atan(math.sin(angle), math.cos(angle))  -- into [-pi, pi]
   local forward = speed * math.max(0, math.cos(angle))
   local turn = speed * math.max(-1, math.min(1, angle / (math.pi / 2)))
   return forward - turn, forward + turn
end

-- The proximity ring as one vector (robot frame): each reading along its
-- sensor's direction, summed.
function swarm_math.obstacle_vector(proximity)
   local x, y = 0, 0
   for _, reading in ipairs(proximity) do
      if reading.value > 0 then
         x = x + reading.value * math.cos(reading.angle)
         y = y + reading.value * math.sin(reading.angle)
      end
   end
   return x, y
end

-- A unit-vector component as a byte (127 = 1, -127 = -1), and back.
function swarm_math.encode(v)
   local b = math.floor(math.max(-1, math.min(1, v)) * 127 + 0.5)
   if b < 0 then b = b + 256 end
   return b
end

function swarm_math.decode(b)
   if b > 127 then b = b - 256 end
   return b / 127
end

return swarm_math
