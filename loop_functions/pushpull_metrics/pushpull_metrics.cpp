// pushpull_metrics: the Push-Pull experiment's measures (seed 003, 6.2.3;
// experiments/pushpull.xml), from ground truth.
//   params: object (id, default "object"), lift_height (m, 0.1: how far off
//           the floor the object must be), max_tilt (rad, 0.1: how far from
//           upright every hand-bot and the object may lean then), stop
//           ("true": end the run on success; default true)
//   success: the object's base lift_height - 1 cm above the floor, held by
//            two hand-bots or more, it and every hand-bot within max_tilt of
//            upright.
//   metrics: success (0/1), completion_tick (-1 until then), lift_attempts
//            (hand-bot grippers closing on the object), connections
//            (foot-bot grippers closing on a hand-bot), footbot_still_s
//            (foot-bot seconds standing still while holding nothing: paused,
//            waiting, lining up), object_z (m)
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "actuators/gripper/gripper_state.h"
#include "actuators/handbot_arms/handbot_arms_state.h"
#include "core/loop_functions.h"
#include "core/simulation.h"

namespace colony {
namespace {

class PushPullMetrics : public LoopFunctions {
 public:
  void Init(const Params& params) override {
    Space& space = sim().space();
    const std::string id = params.GetString("object", "object");
    object_ = space.Find(id);
    if (!object_.valid())
      throw ParamError("object", id, "parameter 'object': no entity '" + id + "' in the arena");
    if (!(space.flags(object_.index) & kMovable))
      throw ParamError("object", id,
                       "parameter 'object': '" + id + "' is fixed; it must be movable");
    lift_height_ = params.GetDouble("lift_height", 0.1, 0.001, 10);
    max_tilt_ = params.GetDouble("max_tilt", 0.1, 0.001, 1.5);
    stop_ = params.GetBool("stop", true);
    for (uint32_t s = 0; s < space.slots(); ++s) {
      if (!space.alive(s)) continue;
      if (space.Get<HandbotArmsState>(s))
        handbots_.push_back(space.HandleOf(s));
      else if (space.Get<GripperState>(s))
        footbots_.push_back(space.HandleOf(s));
    }
    if (handbots_.size() < 2)
      throw ParamError("object", id, "parameter 'object': the arena needs two hand-bots or more");
    hand_held_.assign(handbots_.size() * 2, false);
    foot_held_.assign(footbots_.size(), false);
    PostStep();
  }

  void PostStep() override {
    const Space& space = sim().space();
    Metrics& m = sim().metrics();
    const double floor_z = space.arena_min().z();
    const double object_z = space.pose(object_.index).position.z() - floor_z;
    int holding = 0;
    bool level = Tilt(object_.index) <= max_tilt_;
    for (size_t i = 0; i < handbots_.size(); ++i) {
      const uint32_t h = handbots_[i].index;
      const HandbotArmsState& arms = *space.Get<HandbotArmsState>(h);
      bool holds = false;
      for (int k = 0; k < 2; ++k) {
        const bool on = arms.claws[k].held == object_.index;
        if (on && !hand_held_[2 * i + k] && !(k == 1 && arms.claws[0].held == object_.index))
          ++attempts_;
        hand_held_[2 * i + k] = on;
        holds = holds || on;
      }
      holding += holds;
      level = level && Tilt(h) <= max_tilt_;
    }
    for (size_t i = 0; i < footbots_.size(); ++i) {
      const uint32_t f = footbots_[i].index;
      const GripperState& g = *space.Get<GripperState>(f);
      bool on_handbot = false;
      for (const EntityHandle& h : handbots_) on_handbot = on_handbot || g.held == h.index;
      if (on_handbot && !foot_held_[i]) ++connections_;
      foot_held_[i] = on_handbot;
      if (!g.holding() && space.twist(f).linear.norm() < 0.001) still_ += sim().dt();
    }
    if (!success_ && holding >= 2 && level && object_z >= lift_height_ - 0.01) {
      success_ = true;
      tick_ = static_cast<double>(sim().tick());
    }
    m.Set("success", success_ ? 1 : 0);
    m.Set("completion_tick", tick_);
    m.Set("lift_attempts", attempts_);
    m.Set("connections", connections_);
    m.Set("footbot_still_s", still_);
    m.Set("object_z", object_z);
  }

  bool IsExperimentFinished() override { return stop_ && success_; }

 private:
  double Tilt(uint32_t s) const {
    const Vec3 up = sim().space().pose(s).orientation * Vec3::UnitZ();
    return std::acos(std::clamp(up.z(), -1.0, 1.0));
  }

  EntityHandle object_;
  std::vector<EntityHandle> handbots_, footbots_;
  std::vector<bool> hand_held_, foot_held_;
  double lift_height_ = 0.1, max_tilt_ = 0.1, tick_ = -1, still_ = 0;
  int attempts_ = 0, connections_ = 0;
  bool stop_ = true, success_ = false;
};

COLONY_REGISTER_LOOP_FUNCTIONS(
    PushPullMetrics, "pushpull_metrics",
    "success, completion tick, lift attempts, foot-bot connections and still time of Push-Pull",
    {{"object", "an entity id", "object", "the movable object the hand-bots must lift"},
     {"lift_height", "a number > 0 (m)", "0.1", "how far off the floor the object must be"},
     {"max_tilt", "a number in (0, 1.5] (rad)", "0.1",
      "how far from upright it and the hand-bots may lean"},
     {"stop", "true, false", "true", "end the run on success"}});

}  // namespace
}  // namespace colony
