// eyebot_guidance: when the eye-bots mark the target and when the foot-bots
// reach it (experiments/eyebot_guidance.xml), from ground truth.
//   params: target (id, default "target"), mark_radius (m, 0.2: a laser spot
//           this close to the target's axis marks it), reach_radius (m, 0.6:
//           a foot-bot whose centre is this close has reached it), k (how
//           many foot-bots must reach it, 5), stop ("true": end the run when
//           k have reached it; default true)
//   metrics: marked (0/1: a laser spot marks the target now), mark_time (s,
//            the first time it was marked; -1 until then), reached (foot-bots
//            within reach_radius now), reach_time (s, the first time k were;
//            -1 until then), success (0/1)
//   drawn (LoopFunctions::Draw, in the viewer and rendered frames): the
//           reach circle (a green disc), the mark circle (yellow; red once
//           marked), a line from the target to each foot-bot within reach,
//           and "reached N/k" above the target
#include <cmath>
#include <string>
#include <vector>

#include "core/loop_functions.h"
#include "core/simulation.h"
#include "entities/eyebot/eyebot.h"

namespace colony {
namespace {

class EyebotGuidance : public LoopFunctions {
 public:
  void Init(const Params& params) override {
    Space& space = sim().space();
    const std::string target = params.GetString("target", "target");
    target_ = space.Find(target);
    if (!target_.valid()) {
      throw ParamError("target", target,
                       "parameter 'target': no entity '" + target + "' in the arena");
    }
    mark_radius_ = params.GetDouble("mark_radius", 0.2, 0, 1e6);
    reach_radius_ = params.GetDouble("reach_radius", 0.6, 0, 1e6);
    k_ = static_cast<int>(params.GetInt("k", 5, 1, 1000000000));
    stop_ = params.GetBool("stop", true);
    int footbots = 0;
    for (uint32_t s = 0; s < space.slots(); ++s) {
      if (!space.alive(s) || !(space.flags(s) & kRobot)) continue;
      if (space.Get<PanTiltState>(s)) {
        eyebots_.push_back(s);
      } else if (space.drive(s)) {
        footbots_.push_back(s);
        ++footbots;
      }
    }
    if (eyebots_.empty()) {
      throw ParamError("", "", "the arena has no eye-bot (an entity with a pan-tilt head)");
    }
    if (k_ > footbots) {
      throw ParamError("k", std::to_string(k_),
                       "parameter 'k': " + std::to_string(k_) +
                           " foot-bots must reach the "
                           "target, but the arena has " +
                           std::to_string(footbots));
    }
    PostStep();
  }

  void PostStep() override {
    const Space& space = sim().space();
    Metrics& m = sim().metrics();
    const Vec2 target = space.pose(target_.index).position.head<2>();
    bool marked = false;
    for (uint32_t s : eyebots_) {
      if (!space.alive(s)) continue;
      const auto spot = CastLaser(space, s);
      if (spot && (spot->point.head<2>() - target).norm() <= mark_radius_) marked = true;
    }
    marked_ = marked;
    if (marked && mark_time_ < 0) mark_time_ = sim().time();
    int reached = 0;
    for (uint32_t s : footbots_) {
      if (space.alive(s) && (space.pose(s).position.head<2>() - target).norm() <= reach_radius_)
        ++reached;
    }
    if (reached >= k_ && reach_time_ < 0) reach_time_ = sim().time();
    m.Set("marked", marked ? 1 : 0);
    m.Set("mark_time", mark_time_);
    m.Set("reached", reached);
    m.Set("reach_time", reach_time_);
    m.Set("success", reach_time_ >= 0 ? 1 : 0);
  }

  bool IsExperimentFinished() override { return stop_ && reach_time_ >= 0; }

  void Draw(DrawList& list) const override {
    const Space& space = sim().space();
    const Vec3 target = space.pose(target_.index).position;
    list.AddCircle(target, reach_radius_, Color{40, 200, 60, 90}, /*filled=*/true);
    list.AddCircle(target, mark_radius_,
                   marked_ ? Color{255, 30, 30, 255} : Color{255, 220, 0, 255});
    int reached = 0;
    for (uint32_t s : footbots_) {
      if (!space.alive(s)) continue;
      const Vec3& p = space.pose(s).position;
      if ((p.head<2>() - target.head<2>()).norm() > reach_radius_) continue;
      list.AddSegment(target, p, Color{40, 200, 60, 255});
      ++reached;
    }
    list.AddText(target + Vec3(0, 0, 0.3),
                 "reached " + std::to_string(reached) + "/" + std::to_string(k_), Color::White());
  }

 private:
  EntityHandle target_;
  std::vector<uint32_t> eyebots_, footbots_;
  double mark_radius_ = 0, reach_radius_ = 0, mark_time_ = -1, reach_time_ = -1;
  int k_ = 0;
  bool stop_ = true, marked_ = false;
};

COLONY_REGISTER_LOOP_FUNCTIONS(
    EyebotGuidance, "eyebot_guidance",
    "when the eye-bots' lasers mark the target and when k foot-bots reach it, from ground truth",
    {{"target", "an entity id", "target", "what the eye-bots look for"},
     {"mark_radius", "a number >= 0 (m)", "0.2", "a laser spot this close to the target marks it"},
     {"reach_radius", "a number >= 0 (m)", "0.6", "a foot-bot this close has reached it"},
     {"k", "a whole number >= 1", "5", "how many foot-bots must reach it"},
     {"stop", "true, false", "true", "end the run when k foot-bots have reached it"}});

}  // namespace
}  // namespace colony
