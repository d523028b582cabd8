// foraging (loop functions): the items and the rules of the foraging
// experiment, built into the controller's library (libforaging.so) because
// they tell each robot's controller what it carries.
//
// `items` items lie at random points of the `source` rectangle (uniform, from
// the loop functions' own random stream). Every tick, before the robots'
// control step, in slot order:
//   - a robot that carries nothing and whose centre is within pickup_distance
//     of an item picks it up (ForagingController::SetCarrying(true)); the item
//     reappears at a new random point of the source, so there are always
//     `items` items to find;
//   - a robot that carries an item and whose centre is inside the `nest`
//     rectangle delivers it: items_returned grows by one.
// Items are not entities (nothing collides with them and the floor does not
// show them); a robot's LEDs show whether it carries one (red) or not (green).
// params: nest "x0,y0,x1,y1" (m), source "x0,y0,x1,y1" (m), items (10),
//         pickup_distance (m, 0.1)
// metrics: items_returned (since the start), carrying (robots carrying now)
#include <cstdio>
#include <string>
#include <vector>

#include "controllers/foraging/foraging.h"
#include "core/loop_functions.h"
#include "core/simulation.h"

namespace colony::foraging {
namespace {

struct Rect {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  bool Contains(double x, double y) const { return x >= x0 && x <= x1 && y >= y0 && y <= y1; }
};

Rect ParseRect(const Params& params, const char* key) {
  const std::string text = params.GetString(key);
  Rect r;
  char extra = 0;
  if (std::sscanf(text.c_str(), "%lf,%lf,%lf,%lf%c", &r.x0, &r.y0, &r.x1, &r.y1, &extra) != 4 ||
      !(r.x0 < r.x1) || !(r.y0 < r.y1)) {
    throw ParamError(key, text,
                     std::string("parameter '") + key + "': '" + text +
                         "' is not a rectangle \"x0,y0,x1,y1\" (m) with x0 < x1 and y0 < y1");
  }
  return r;
}

class ForagingLoopFunctions : public LoopFunctions {
 public:
  void Init(const Params& params) override {
    nest_ = ParseRect(params, "nest");
    source_ = ParseRect(params, "source");
    pickup_ = params.GetDouble("pickup_distance", 0.1, 1e-3, 100);
    items_.resize(static_cast<size_t>(params.GetInt("items", 10, 1, 1000000)));
    for (Vec2& item : items_) item = RandomPointInSource();
    Record();
  }

  void PreStep() override {
    const Space& space = sim().space();
    for (uint32_t i = 0; i < space.slots(); ++i) {
      if (!space.alive(i) || !(space.flags(i) & kRobot)) continue;
      auto* robot = dynamic_cast<ForagingController*>(sim().ControllerOf(space.HandleOf(i)));
      if (!robot) continue;
      const Vec2 p = space.pose(i).position.head<2>();
      if (robot->carrying()) {
        if (nest_.Contains(p.x(), p.y())) {
          robot->SetCarrying(false);
          ++returned_;
        }
        continue;
      }
      for (Vec2& item : items_) {
        if ((item - p).squaredNorm() >= pickup_ * pickup_) continue;
        robot->SetCarrying(true);
        item = RandomPointInSource();
        break;
      }
    }
  }

  void PostStep() override { Record(); }

 private:
  Vec2 RandomPointInSource() {
    const double x = sim().rng().Uniform(source_.x0, source_.x1);
    const double y = sim().rng().Uniform(source_.y0, source_.y1);
    return {x, y};
  }

  void Record() {
    const Space& space = sim().space();
    size_t carrying = 0;
    for (uint32_t i = 0; i < space.slots(); ++i) {
      if (!space.alive(i) || !(space.flags(i) & kRobot)) continue;
      const auto* robot =
          dynamic_cast<const ForagingController*>(sim().ControllerOf(space.HandleOf(i)));
      carrying += robot && robot->carrying();
    }
    Metrics& m = sim().metrics();
    m.Set("items_returned", static_cast<double>(returned_));
    m.Set("carrying", static_cast<double>(carrying));
  }

  Rect nest_, source_;
  double pickup_ = 0.1;
  std::vector<Vec2> items_;
  uint64_t returned_ = 0;
};

COLONY_REGISTER_LOOP_FUNCTIONS(
    ForagingLoopFunctions, "foraging",
    "items in a source area, picked up by foraging robots passing over them and counted when "
    "delivered to the nest; records items_returned and carrying every tick",
    {{"nest", "\"x0,y0,x1,y1\" (m), x0 < x1, y0 < y1", "",
      "the nest: a carrying robot whose centre enters it delivers its item"},
     {"source", "\"x0,y0,x1,y1\" (m), x0 < x1, y0 < y1", "",
      "where items lie (uniformly at random)"},
     {"items", "a whole number >= 1", "10", "items lying in the source at any time"},
     {"pickup_distance", "a number in [0.001, 100] (m)", "0.1",
      "a robot picks up an item when its centre comes this close"}});

}  // namespace
}  // namespace colony::foraging
