// aggregation_metrics: how aggregated a swarm is, every tick, in metrics.csv.
// Robots closer than cluster_distance (centre to centre) are in the same
// cluster, transitively; a cluster counts from min_cluster_size robots.
//   robots                    robots alive
//   clusters                  number of clusters
//   largest_cluster_fraction  robots in the largest cluster / robots (0 if none)
//   clustered_fraction        robots in a cluster / robots
//   moving_fraction           robots whose wheels turned during the last tick
//                             (0 before the first tick)
// params: cluster_distance (m, 0.5), min_cluster_size (2)
#include <cmath>

#include "core/loop_functions.h"
#include "core/simulation.h"
#include "loop_functions/common/groups.h"

namespace colony {
namespace {

class AggregationMetrics : public LoopFunctions {
 public:
  void Init(const Params& params) override {
    cluster_distance_ = params.GetDouble("cluster_distance", 0.5, 1e-3, 1e6);
    min_size_ = static_cast<size_t>(params.GetInt("min_cluster_size", 2, 1, 1000000000));
    Record();
  }

  void PostStep() override { Record(); }

 private:
  void Record() {
    // At Init the arena is built but its grid may not be yet.
    if (sim().space().index_dirty()) sim().space().UpdateIndex();
    const Space& space = sim().space();
    const swarm::GroupStats s = finder_.Find(space, cluster_distance_, min_size_, false);
    size_t moving = 0;
    for (uint32_t i = 0; i < space.slots(); ++i) {
      if (!space.alive(i) || !(space.flags(i) & kRobot)) continue;
      const DriveState* drive = space.drive(i);
      moving += drive && (drive->travelled_left != 0 || drive->travelled_right != 0);
    }
    const double robots = static_cast<double>(s.robots);
    Metrics& m = sim().metrics();
    m.Set("robots", robots);
    m.Set("clusters", static_cast<double>(s.groups));
    m.Set("largest_cluster_fraction", s.robots ? static_cast<double>(s.largest) / robots : 0.0);
    m.Set("clustered_fraction", s.robots ? static_cast<double>(s.grouped) / robots : 0.0);
    m.Set("moving_fraction", s.robots ? static_cast<double>(moving) / robots : 0.0);
  }

  double cluster_distance_ = 0.5;
  size_t min_size_ = 2;
  swarm::GroupFinder finder_;
};

COLONY_REGISTER_LOOP_FUNCTIONS(
    AggregationMetrics, "aggregation_metrics",
    "records robots, clusters, largest_cluster_fraction, clustered_fraction and moving_fraction "
    "every tick",
    {{"cluster_distance", "a number in [0.001, 1e6] (m)", "0.5",
      "robots closer than this (centre to centre) are in the same cluster"},
     {"min_cluster_size", "a whole number >= 1", "2", "robots a cluster needs to count"}});

}  // namespace
}  // namespace colony
