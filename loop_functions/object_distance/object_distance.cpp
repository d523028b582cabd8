// object_distance: how far an entity is from a target point, every tick.
//   params: entity (id), target ("x,y")
//   metrics: distance (m), x, y
#include <cmath>
#include <cstdio>

#include "core/loop_functions.h"
#include "core/simulation.h"

namespace colony {
namespace {

class ObjectDistance : public LoopFunctions {
 public:
  void Init(const Params& params) override {
    const std::string id = params.GetString("entity");
    entity_ = sim().space().Find(id);
    if (!entity_.valid())
      throw ParamError("entity", id, "parameter 'entity': no entity '" + id + "' in the arena");
    const std::string target = params.GetString("target");
    char extra = 0;
    if (std::sscanf(target.c_str(), "%lf,%lf%c", &x_, &y_, &extra) != 2) {
      throw ParamError("target", target, "parameter 'target': '" + target + "' is not \"x,y\"");
    }
    PostStep();
  }
  void PostStep() override {
    const Space& space = sim().space();
    Metrics& m = sim().metrics();
    if (!space.IsAlive(entity_)) return;
    const Vec3& p = space.pose(entity_.index).position;
    m.Set("distance", std::hypot(p.x() - x_, p.y() - y_));
    m.Set("x", p.x());
    m.Set("y", p.y());
  }

 private:
  EntityHandle entity_;
  double x_ = 0, y_ = 0;
};

COLONY_REGISTER_LOOP_FUNCTIONS(ObjectDistance, "object_distance",
                               "records the distance of one entity to a target point",
                               {{"entity", "an entity id", "", "the entity to follow"},
                                {"target", "\"x,y\" (m)", "", "the point"}});

}  // namespace
}  // namespace colony
