// Loop functions of seed 000's event experiments (docs/events.md).
//
// wall_distance (experiments/e4_latency.xml): the gap between a robot's
// body and the face of a wall it drives towards along +x, every tick; the
// run ends once the robot, having moved, stands still.
//   params: robot (id), wall (id of a box)
//   metrics: stop_distance (m), stopped (0/1)
//
// environment (experiments/e4_bandwidth.xml): picks one of the arenas the
// file describes by removing, in Init, the entities of the others: those
// whose id starts with "walls_" unless env="walls", "clutter_" unless
// env="cluttered"; env="open" keeps neither.
#include <string>
#include <vector>

#include "core/loop_functions.h"
#include "core/simulation.h"

namespace colony {
namespace {

class WallDistance : public LoopFunctions {
 public:
  void Init(const Params& params) override {
    robot_ = Require(params, "robot");
    wall_ = Require(params, "wall");
    const Geometry& g = sim().space().geometry(wall_.index);
    if (g.shape != ShapeKind::kBox)
      throw ParamError("wall", params.GetString("wall"), "parameter 'wall': not a box");
    sim().metrics().Set("stopped", 0);
    PostStep();
  }
  void PostStep() override {
    const Space& space = sim().space();
    const Pose& wall = space.pose(wall_.index);
    const double face =
        wall.position.x() - FootprintHalfExtents(space.geometry(wall_.index), wall.orientation).x();
    const double front =
        space.pose(robot_.index).position.x() + space.geometry(robot_.index).BoundingRadius();
    sim().metrics().Set("stop_distance", face - front);
    const double speed = space.twist(robot_.index).linear.norm();
    moved_ = moved_ || speed > 0;
    stopped_ = moved_ && speed == 0;
    sim().metrics().Set("stopped", stopped_ ? 1 : 0);
  }
  bool IsExperimentFinished() override { return stopped_; }

 private:
  EntityHandle Require(const Params& params, const char* key) {
    const std::string id = params.GetString(key);
    const EntityHandle h = sim().space().Find(id);
    if (!h.valid())
      throw ParamError(key, id,
                       "parameter '" + std::string(key) + "': no entity '" + id + "' in the arena");
    return h;
  }
  EntityHandle robot_, wall_;
  bool moved_ = false, stopped_ = false;
};

class Environment : public LoopFunctions {
 public:
  void Init(const Params& params) override {
    const std::string env = params.GetString("env", "open");
    if (env != "open" && env != "walls" && env != "cluttered")
      throw ParamError("env", env, "parameter 'env': accepted: open, walls, cluttered");
    Space& space = sim().space();
    std::vector<EntityHandle> gone;
    for (uint32_t s = 0; s < space.slots(); ++s) {
      if (!space.alive(s)) continue;
      const std::string& id = space.id(s);
      const bool walls = id.rfind("walls_", 0) == 0, clutter = id.rfind("clutter_", 0) == 0;
      if ((walls && env != "walls") || (clutter && env != "cluttered"))
        gone.push_back(space.HandleOf(s));
    }
    for (EntityHandle h : gone) sim().RemoveEntity(h);
  }
};

COLONY_REGISTER_LOOP_FUNCTIONS(WallDistance, "wall_distance",
                               "the gap between a robot and a wall ahead; ends when it stopped",
                               {{"robot", "an entity id", "", "the robot"},
                                {"wall", "a box id", "", "the wall it drives towards along +x"}});
COLONY_REGISTER_LOOP_FUNCTIONS(Environment, "environment",
                               "keeps one of the arenas an experiment file describes",
                               {{"env", "open, walls, cluttered", "open",
                                 "which arena: open (none of the walls_ and clutter_ entities), "
                                 "walls (the walls_ ones), cluttered (the clutter_ ones)"}});

}  // namespace
}  // namespace colony
