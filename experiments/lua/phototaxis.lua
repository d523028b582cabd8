-- Phototaxis: drive towards the light. The light ring's readings, summed as
-- vectors along their sensors' directions, point at the light; the robot
-- turns towards that direction while driving, and turns away from whatever
-- its proximity ring sees ahead first. With no light in sight (hidden
-- behind other robots or the box) it wanders until it sees it again.

VELOCITY = 10     -- top wheel speed (cm/s)
AVOID = 0.05      -- proximity vector length from which an obstacle ahead is avoided

local function sum_of(ring)
   local x, y = 0, 0
   for i = 1, #ring do
      x = x + ring[i].value * math.cos(ring[i].angle)
      y = y + ring[i].value * math.sin(ring[i].angle)
   end
   return x, y
end

-- Wheel speeds that turn towards `angle` (rad, 0 ahead) while driving:
-- full speed when it is ahead, turning on the spot when it is beside or behind.
local function steer(angle)
   local forward = VELOCITY * math.max(0, math.cos(angle))
   local turn = VELOCITY * math.max(-1, math.min(1, angle / (math.pi / 2)))
   robot.wheels.set_velocity(forward - turn, forward + turn)
end

function init()
   robot.leds.set_all_colors("yellow")
end

function step()
   local ox, oy = sum_of(robot.proximity)
   local obstacle = math.atan2(oy, ox)   -- Lua 5.2's atan2, as many ARGoS scripts use
   if math.sqrt(ox * ox + oy * oy) > AVOID and math.abs(obstacle) < math.pi / 2 then
      -- Something ahead: turn on the spot away from it.
      if obstacle > 0 then
         robot.wheels.set_velocity(VELOCITY, -VELOCITY)
      else
         robot.wheels.set_velocity(-VELOCITY, VELOCITY)
      end
      return
   end
   local lx, ly = sum_of(robot.light)
   if lx == 0 and ly == 0 then
      local turn = robot.random.uniform(-0.5, 0.5) * VELOCITY
      robot.wheels.set_velocity(VELOCITY - turn, VELOCITY + turn)
   else
      steer(math.atan(ly, lx))
   end
end

function reset()
end

function destroy()
end
