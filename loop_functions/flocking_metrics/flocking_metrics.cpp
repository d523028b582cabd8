// flocking_metrics: how ordered and how together a flock is, every tick, in
// metrics.csv:
//   robots                  robots alive
//   polarisation            |mean of the robots' heading unit vectors|: 1 = all
//                           aligned, about 1/sqrt(N) for random headings
//   mean_nn_distance        mean distance from each robot to its nearest
//                           neighbour, centre to centre (m)
//   groups                  groups of robots: robots closer than group_distance
//                           are in the same group (transitively); a lone robot
//                           is a group of one
//   largest_group_fraction  robots in the largest group / robots
// params: group_distance (m, 1)
#include <cmath>

#include "core/loop_functions.h"
#include "core/simulation.h"
#include "loop_functions/common/groups.h"

namespace colony {
namespace {

class FlockingMetrics : public LoopFunctions {
 public:
  void Init(const Params& params) override {
    group_distance_ = params.GetDouble("group_distance", 1.0, 1e-3, 1e6);
    Record();
  }

  void PostStep() override { Record(); }

 private:
  void Record() {
    // At Init the arena is built but its grid may not be yet.
    if (sim().space().index_dirty()) sim().space().UpdateIndex();
    const Space& space = sim().space();
    double x = 0, y = 0;
    size_t robots = 0;
    for (uint32_t i = 0; i < space.slots(); ++i) {
      if (!space.alive(i) || !(space.flags(i) & kRobot)) continue;
      const double yaw = YawOf(space.pose(i).orientation);
      x += std::cos(yaw);
      y += std::sin(yaw);
      ++robots;
    }
    const swarm::GroupStats groups = finder_.Find(space, group_distance_, 1, true);
    Metrics& m = sim().metrics();
    m.Set("robots", static_cast<double>(robots));
    m.Set("polarisation", robots ? std::hypot(x, y) / static_cast<double>(robots) : 0.0);
    m.Set("mean_nn_distance", groups.mean_nearest);
    m.Set("groups", static_cast<double>(groups.groups));
    m.Set("largest_group_fraction",
          robots ? static_cast<double>(groups.largest) / static_cast<double>(robots) : 0.0);
  }

  double group_distance_ = 1.0;
  swarm::GroupFinder finder_;
};

COLONY_REGISTER_LOOP_FUNCTIONS(
    FlockingMetrics, "flocking_metrics",
    "records robots, polarisation, mean_nn_distance, groups and "
    "largest_group_fraction every tick",
    {{"group_distance", "a number in [0.001, 1e6] (m)", "1",
      "robots closer than this (centre to centre) are in the same group"}});

}  // namespace
}  // namespace colony
