// diffusion_metrics: per-tick metrics of a wandering swarm, written to
// metrics.csv:
//   robots             robots alive
//   mean_displacement  mean straight-line distance from where each robot started (m)
//   mean_path_length   mean distance each robot has driven so far (m)
//   in_contact         fraction of robots blocked by an obstacle or a robot this tick
//   contact_ticks      robot-ticks spent blocked since the start
#include <cmath>
#include <vector>

#include "core/loop_functions.h"
#include "core/simulation.h"

namespace colony {
namespace {

class DiffusionMetrics : public LoopFunctions {
 public:
  void Init(const Params& params) override {
    (void)params;
    const Space& space = sim().space();
    start_.assign(space.slots(), Vec2::Zero());
    last_.assign(space.slots(), Vec2::Zero());
    path_.assign(space.slots(), 0.0);
    for (uint32_t i = 0; i < space.slots(); ++i) {
      if (space.alive(i)) start_[i] = last_[i] = space.pose(i).position.head<2>();
    }
    Record();
  }

  void PostStep() override { Record(); }

 private:
  void Record() {
    const Space& space = sim().space();
    if (start_.size() < space.slots()) {
      // Robots added while running start where they appear.
      for (uint32_t i = static_cast<uint32_t>(start_.size()); i < space.slots(); ++i) {
        const Vec2 p = space.alive(i) ? Vec2(space.pose(i).position.head<2>()) : Vec2::Zero();
        start_.push_back(p);
        last_.push_back(p);
        path_.push_back(0.0);
      }
    }
    double displacement = 0, path = 0;
    size_t robots = 0, contacts = 0;
    for (uint32_t i = 0; i < space.slots(); ++i) {
      if (!space.alive(i) || !(space.flags(i) & kRobot)) continue;
      const Vec2 p = space.pose(i).position.head<2>();
      path_[i] += (p - last_[i]).norm();
      last_[i] = p;
      displacement += (p - start_[i]).norm();
      path += path_[i];
      contacts += space.in_contact(i);
      ++robots;
    }
    contact_ticks_ += contacts;
    Metrics& m = sim().metrics();
    m.Set("robots", static_cast<double>(robots));
    m.Set("mean_displacement", robots ? displacement / robots : 0.0);
    m.Set("mean_path_length", robots ? path / robots : 0.0);
    m.Set("in_contact", robots ? static_cast<double>(contacts) / robots : 0.0);
    m.Set("contact_ticks", static_cast<double>(contact_ticks_));
  }

  std::vector<Vec2> start_, last_;
  std::vector<double> path_;
  uint64_t contact_ticks_ = 0;
};

COLONY_REGISTER_LOOP_FUNCTIONS(
    DiffusionMetrics, "diffusion_metrics",
    "records robots, mean_displacement, mean_path_length, in_contact and "
    "contact_ticks every tick",
    {});

}  // namespace
}  // namespace colony
