// construction_metrics: success and time of the construction experiments
// (EXPERIMENTS.md E3), from the ground-truth poses of the cubes and the robot.
//   params: task ("bridge", "tower" or "remote"), robot (id; default: the only robot),
//           tolerance (m, default 0.015: how far a cube may sit off the one
//           below it and still count as stacked), stop ("true": end the run
//           on success or failure; default true)
//   bridge: success when two cubes lie in a ditch (centres inside it, tops
//           within 1.5 cm of the floor) and the robot stands on the floor
//           on the other side of that ditch from where it started.
//   tower:  success when three cubes stand on each other, each within
//           `tolerance` of the one below and level with it.
//   remote: success when both hold at once: two cubes in a ditch and a
//           tower of three (built from the cubes across the ditch: the
//           robot has crossed the bridge to build it).
//   failure: the robot fell (its base more than 2 cm below the floor).
//   metrics: success (0/1), failed (0/1), outcome_time (s of success or failure,
//            -1 while running), cubes_in_ditch, tower_height, robot_z,
//            cubes_tilted (cubes with no face within 5 degrees of level: jammed
//            across the ditch's edge or half on another cube; a cube lying on
//            its side is level)
#include <algorithm>
#include <cmath>
#include <vector>

#include "core/loop_functions.h"
#include "core/simulation.h"
#include "loop_functions/common/measured_entity.h"

namespace colony {
namespace {

class ConstructionMetrics : public LoopFunctions {
 public:
  void Init(const Params& params) override {
    Space& space = sim().space();
    task_ = params.GetString("task");
    if (task_ != "bridge" && task_ != "tower" && task_ != "remote") {
      throw ParamError(
          "task", task_,
          "parameter 'task': '" + task_ + "' is not accepted; accepted: bridge, tower, remote");
    }
    tolerance_ = params.GetDouble("tolerance", 0.015, 1e-6, 1.0);
    stop_ = params.GetBool("stop", true);
    robot_ = FindMeasured(space, params, "robot", "robot",
                          [&](uint32_t s) { return (space.flags(s) & kRobot) != 0; });
    cube_type_ = space.TypeId("cube");
    if (space.OfType(cube_type_).empty()) {
      throw ParamError("task", task_, "parameter 'task': the arena has no <cube> to build with");
    }
    if (task_ != "tower") {
      if (space.floor().ditches().empty()) {
        throw ParamError(
            "task", task_,
            "parameter 'task': a " + task_ + " needs a <ditch> in the arena's <floor>");
      }
      const Vec3& p = space.pose(robot_.index).position;
      for (const Ditch& d : space.floor().ditches()) start_side_.push_back(SideOf(d, p.x(), p.y()));
    }
    PostStep();
  }

  void PostStep() override {
    const Space& space = sim().space();
    Metrics& m = sim().metrics();
    if (!space.IsAlive(robot_)) return;
    const Vec3& rp = space.pose(robot_.index).position;
    const double floor_z = space.arena_min().z();
    int in_ditch = 0;
    bool bridged = false;
    if (task_ != "tower") {
      const auto& ditches = space.floor().ditches();
      for (size_t i = 0; i < ditches.size(); ++i) {
        const Ditch& d = ditches[i];
        int here = 0;
        for (uint32_t c : space.OfType(cube_type_)) {
          const Vec3 cp = Centre(c);
          const double top = cp.z() + 0.5 * space.geometry(c).height();
          if (d.Contains(cp.x(), cp.y()) && std::abs(top - floor_z) < 0.015) ++here;
        }
        in_ditch += here;
        const int side = SideOf(d, rp.x(), rp.y());
        const bool on_floor = rp.z() > floor_z - 0.01 && !d.Contains(rp.x(), rp.y());
        if (here >= 2 && side != 0 && side != start_side_[i] && on_floor &&
            Beyond(d, rp.x(), rp.y())) {
          bridged = true;
        }
      }
    }
    const int height = TowerHeight();
    m.Set("success", success_ ? 1 : 0);
    m.Set("failed", failed_ ? 1 : 0);
    if (!success_ && !failed_) {
      const bool done = task_ == "bridge"  ? bridged
                        : task_ == "tower" ? height >= 3
                                           : in_ditch >= 2 && height >= 3;
      if (done) {
        success_ = true;
        time_ = sim().time();
      } else if (rp.z() < floor_z - 0.02) {
        failed_ = true;
        time_ = sim().time();
      }
    }
    m.Set("success", success_ ? 1 : 0);
    m.Set("failed", failed_ ? 1 : 0);
    m.Set("outcome_time", time_);
    m.Set("cubes_in_ditch", in_ditch);
    m.Set("tower_height", height);
    m.Set("robot_z", rp.z() - floor_z);
    int tilted = 0;
    for (uint32_t c : space.OfType(cube_type_)) tilted += Level(c) ? 0 : 1;
    m.Set("cubes_tilted", tilted);
  }

  bool IsExperimentFinished() override { return stop_ && (success_ || failed_); }

 private:
  // Which side of the ditch (x, y) is on across its width: -1, +1, or 0 over it.
  static int SideOf(const Ditch& d, double x, double y) {
    const bool along_y =
        (d.max_y - d.min_y) >= (d.max_x - d.min_x);  // trench runs along y: sides are in x
    const double v = along_y ? x : y;
    const double lo = along_y ? d.min_x : d.min_y, hi = along_y ? d.max_x : d.max_y;
    if (v < lo) return -1;
    if (v > hi) return 1;
    return 0;
  }
  // Whether (x, y) is fully past the ditch (the robot's body clear of it).
  static bool Beyond(const Ditch& d, double x, double y) {
    const bool along_y = (d.max_y - d.min_y) >= (d.max_x - d.min_x);
    const double clear = 0.09;  // a marXbot's radius and a little
    return along_y ? (x < d.min_x - clear || x > d.max_x + clear)
                   : (y < d.min_y - clear || y > d.max_y + clear);
  }

  // Cubes in the tallest stack: a chain of cubes each resting level on the
  // one below (base on its top, centres within `tolerance`), from the floor.
  int TowerHeight() const {
    const Space& space = sim().space();
    const auto& cubes = space.OfType(cube_type_);
    const double floor_z = space.arena_min().z();
    int best = 0;
    for (uint32_t base : cubes) {
      const Vec3 bp = Centre(base);
      if (std::abs(bp.z() - 0.5 * space.geometry(base).height() - floor_z) > 0.005 ||
          !Level(base)) {
        continue;
      }
      int height = 1;
      uint32_t below = base;
      for (bool found = true; found;) {
        found = false;
        const Vec3 lp = Centre(below);
        const double top = lp.z() + 0.5 * space.geometry(below).height();
        for (uint32_t c : cubes) {
          if (c == below) continue;
          const Vec3 cp = Centre(c);
          if (std::abs(cp.z() - 0.5 * space.geometry(c).height() - top) < 0.005 &&
              std::hypot(cp.x() - lp.x(), cp.y() - lp.y()) < tolerance_ && Level(c)) {
            below = c;
            ++height;
            found = true;
            break;
          }
        }
      }
      best = std::max(best, height);
    }
    return best;
  }
  // Level within about 5 degrees: one of its faces up (a cube on its side
  // is as level as an upright one).
  bool Level(uint32_t c) const {
    const Quat& q = sim().space().pose(c).orientation;
    const double most =
        std::max({std::abs((q * Vec3::UnitX()).z()), std::abs((q * Vec3::UnitY()).z()),
                  std::abs((q * Vec3::UnitZ()).z())});
    return most > std::cos(5.0 * M_PI / 180.0);
  }
  // A cube's centre (its pose is its base's centre, in its own frame).
  Vec3 Centre(uint32_t c) const {
    const Space& space = sim().space();
    const Pose& p = space.pose(c);
    return p.position + p.orientation * Vec3(0, 0, 0.5 * space.geometry(c).height());
  }

  std::string task_;
  double tolerance_ = 0.015;
  bool stop_ = true;
  EntityHandle robot_;
  uint16_t cube_type_ = 0;
  std::vector<int> start_side_;
  bool success_ = false, failed_ = false;
  double time_ = -1;
};

COLONY_REGISTER_LOOP_FUNCTIONS(
    ConstructionMetrics, "construction_metrics",
    "success and time of the bridge and tower construction experiments, from ground truth",
    {{"task", "bridge, tower, remote", "", "what counts as success"},
     {"robot", "an entity id", "the only robot", "the robot that must cross the bridge"},
     {"tolerance", "a number > 0 (m)", "0.015",
      "how far a cube may sit off the one below it in a tower"},
     {"stop", "true, false", "true", "end the run on success or failure"}});

}  // namespace
}  // namespace colony
