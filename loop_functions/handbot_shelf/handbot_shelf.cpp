// handbot_shelf: success, time and height of the shelf-climbing experiment
// (seed 000, 3.3.2; experiments/handbot_shelf.xml), from ground truth.
//   params: robot (id; default: the only robot), book (id; default "book"),
//           stop ("true": end the run on success; default true)
//   success: the book has come down (its base within 0.3 m of the floor,
//            off the shelf) and the hand-bot stands on the floor again, its
//            rope slack, after climbing at least 0.2 m.
//   metrics: success (0/1), success_time (s, -1 until then), climb_height
//            (m, the highest the robot's base has been above where it
//            started), book_retrieved (0/1), book_held (0/1: in one of the
//            hand-bot's grippers now), robot_z (m above the floor), grips (how
//            many times a gripper has closed on something other than the book:
//            the board, as it climbs)
#include <algorithm>
#include <cmath>
#include <string>

#include "actuators/handbot_arms/handbot_arms_state.h"
#include "actuators/rope_launcher/rope_state.h"
#include "core/loop_functions.h"
#include "core/simulation.h"
#include "loop_functions/common/measured_entity.h"

namespace colony {
namespace {

class HandbotShelf : public LoopFunctions {
 public:
  void Init(const Params& params) override {
    Space& space = sim().space();
    stop_ = params.GetBool("stop", true);
    robot_ = FindMeasured(space, params, "robot", "hand-bot",
                          [&](uint32_t s) { return space.Get<RopeState>(s) != nullptr; });
    if (!space.Get<RopeState>(robot_.index) || !space.Get<HandbotArmsState>(robot_.index)) {
      throw ParamError("robot", space.id(robot_.index),
                       "parameter 'robot': '" + space.id(robot_.index) + "' is not a hand-bot");
    }
    const std::string book = params.GetString("book", "book");
    book_ = space.Find(book);
    if (!book_.valid()) {
      throw ParamError("book", book, "parameter 'book': no entity '" + book + "' in the arena");
    }
    if (!(space.flags(book_.index) & kMovable)) {
      throw ParamError("book", book,
                       "parameter 'book': '" + book + "' is fixed; the book must be movable");
    }
    start_z_ = space.pose(robot_.index).position.z();
    weight_ = space.mass(robot_.index) * 9.81;
    PostStep();
  }

  void PostStep() override {
    const Space& space = sim().space();
    Metrics& m = sim().metrics();
    if (!space.IsAlive(robot_) || !space.IsAlive(book_)) return;
    const double floor_z = space.arena_min().z();
    const double z = space.pose(robot_.index).position.z();
    climb_height_ = std::max(climb_height_, z - start_z_);
    const bool book_down = space.pose(book_.index).position.z() - floor_z < 0.3;
    const HandbotArmsState& arms = *space.Get<HandbotArmsState>(robot_.index);
    const bool held = arms.claws[0].held == book_.index || arms.claws[1].held == book_.index;
    for (int k = 0; k < 2; ++k) {
      const uint32_t h = arms.claws[k].held;
      const bool other = h != HandbotArmsState::kNothing && h != book_.index;
      if (other && !gripping_[k]) ++grips_;
      gripping_[k] = other;
    }
    const RopeState& rope = *space.Get<RopeState>(robot_.index);
    const bool standing = z - floor_z < 0.05 && rope.tension < 0.2 * weight_;
    if (!success_ && book_down && standing && climb_height_ > 0.2) {
      success_ = true;
      time_ = sim().time();
    }
    m.Set("success", success_ ? 1 : 0);
    m.Set("success_time", time_);
    m.Set("climb_height", climb_height_);
    m.Set("book_retrieved", book_down ? 1 : 0);
    m.Set("book_held", held ? 1 : 0);
    m.Set("robot_z", z - floor_z);
    m.Set("grips", grips_);
  }

  bool IsExperimentFinished() override { return stop_ && success_; }

 private:
  bool stop_ = true, success_ = false, gripping_[2] = {false, false};
  int grips_ = 0;
  EntityHandle robot_, book_;
  double start_z_ = 0, weight_ = 0, climb_height_ = 0, time_ = -1;
};

COLONY_REGISTER_LOOP_FUNCTIONS(
    HandbotShelf, "handbot_shelf",
    "success, time and height of the hand-bot's shelf climbing (seed 000, 3.3.2), from ground "
    "truth",
    {{"robot", "an entity id", "the only hand-bot", "the climbing hand-bot"},
     {"book", "an entity id", "book", "the movable box it must bring down"},
     {"stop", "true, false", "true", "end the run on success"}});

}  // namespace
}  // namespace colony
