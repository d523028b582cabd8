// Entity types (plugin kind "entity"): marxbot, box, cylinder, light... An
// entity type reads its XML element into an EntityDesc; the simulation adds
// it to the space and hands it to an engine and, for robots, to a controller.
#pragma once

#include <deque>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/config.h"
#include "core/registry.h"
#include "core/space.h"

namespace colony {

// Devices evenly spaced on a ring around a robot's vertical axis: proximity
// sensors, ground sensors, LEDs. Sensors read this when attached.
struct RingMount {
  int count = 0;
  double radius = 0;       // from the robot's axis (m)
  double elevation = 0;    // above the robot's base (m)
  double start_angle = 0;  // of the first device, counter-clockwise from the front (rad)
  double range = 0;        // nominal range where it applies (m)
  double AngleOf(int i) const { return start_angle + 2.0 * M_PI * i / count; }
};

// Unit vectors (robot frame, in the horizontal plane) of the devices of
// ring mounts, computed once per mount and shared by every robot carrying
// it: a private copy per robot would cost count x 16 bytes each. The
// returned pointers stay valid for the owner's lifetime.
class RingDirections {
 public:
  const Vec2* Of(const RingMount& mount) {
    for (const auto& [ring, directions] : table_) {
      if (ring == &mount) return directions.data();
    }
    std::vector<Vec2> directions;
    for (int i = 0; i < mount.count; ++i) {
      const double a = mount.AngleOf(i);
      directions.emplace_back(std::cos(a), std::sin(a));
    }
    table_.emplace_back(&mount, std::move(directions));
    return table_.back().second.data();
  }

 private:
  std::deque<std::pair<const RingMount*, std::vector<Vec2>>>
      table_;  // a deque keeps the tables in place
};

// Where a robot type carries its devices, by name ("proximity", "ground", "leds").
struct DeviceMounts {
  std::map<std::string, RingMount, std::less<>> rings;
  const RingMount* Ring(std::string_view name) const {
    auto it = rings.find(name);
    return it == rings.end() ? nullptr : &it->second;
  }
};

// What one entity is: read from the experiment file (or an XML element), or
// made by a program, and handed to the simulation (Simulation::AddEntity).
// A plain value: copy it to make more of the same entity.
struct EntityDesc {
  std::string type;  // the entity type's label or an alias ("marxbot", "foot-bot", "box")
  Space::EntityInit
      init;  // id, pose, geometry, flags, colour, mass, components; init.type is set when added
  std::string controller;  // robots: the id of the controller configuration
  int line = 0;  // of its element in the experiment file, for messages; 0: not from the file
};

class EntityType {
 public:
  virtual ~EntityType() = default;
  // Reads the type's own attributes of `node` into `desc` (id, pose and the
  // <controller> child are read by the caller).
  virtual void Build(const ConfigNode& node, EntityDesc& desc) const = 0;
  // Whether its pose comes from a <body position orientation> child (ARGoS
  // style); otherwise from `position`/`orientation` attributes on the element.
  virtual bool has_body() const { return true; }
  // Whether it carries a controller.
  virtual bool is_robot() const { return false; }
  // How to give an entity of this type the component called `name` when it
  // lacks it (e.g. "declare the marxbot with manipulator=\"true\""), for
  // messages; "" if there is no way.
  virtual std::string ComponentHint(std::string_view name) const {
    (void)name;
    return "";
  }
  // Called after entities of this type were added to `space`: once after
  // the arena is built (before loop functions start), and after each one a
  // program adds while running. Pockets settle onto what is under them.
  virtual void Placed(Space& space) const { (void)space; }
  virtual const DeviceMounts& mounts() const {
    static const DeviceMounts kNone;
    return kNone;
  }
};

}  // namespace colony
