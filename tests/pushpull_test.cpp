// The Push-Pull foot-bot (controllers/pushpull/pushpull_footbot.cpp; seed
// 003, 6.2.1): it finds a hand-bot's slot with its camera, connects to the
// hand-bot's ring there and pushes or pulls it; it holds still when a
// connecting foot-bot asks it to, until the time-out.
#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "actuators/gripper/gripper_state.h"
#include "actuators/leds/leds.h"
#include "actuators/range_and_bearing/range_and_bearing.h"
#include "actuators/rope_launcher/rope_state.h"
#include "controllers/pushpull/pushpull_protocol.h"
#include "core/registry.h"
#include "sensors/positioning/positioning.h"
#include "tests/test_util.h"

namespace colony::testing {
namespace {

using namespace colony::pushpull;

// A hand-bot showing one slot: blue at ring LED `slot`, and pull green (or
// push violet) at the next LED counter-clockwise; dark once it has moved
// `until` metres (then it no longer asks to be moved).
class SlotShower : public Controller {
 public:
  void Init(const Params& params) override {
    slot_ = static_cast<int>(params.GetInt("slot", 6, 0, 11));
    push_ = params.GetBool("push", false);
    until_ = params.GetDouble("until", 0.3, 0, 10);
    leds_ = &GetActuator<Leds>("leds");
    position_ = &GetSensor<PositioningSensor>("positioning");
  }
  void ControlStep() override {
    if (!started_) {
      x0_ = position_->x();
      y0_ = position_->y();
      started_ = true;
    }
    leds_->SetAllColors(kOff);
    if (std::hypot(position_->x() - x0_, position_->y() - y0_) < until_) {
      leds_->SetSingleColor(static_cast<size_t>(slot_), kSlotBlue);
      leds_->SetSingleColor(static_cast<size_t>((slot_ + 1) % 12),
                            push_ ? kPushViolet : kPullGreen);
    }
  }

 private:
  int slot_ = 6;
  bool push_ = false, started_ = false;
  double until_ = 0.3, x0_ = 0, y0_ = 0;
  Leds* leds_ = nullptr;
  const PositioningSensor* position_ = nullptr;
};
COLONY_REGISTER_CONTROLLER(SlotShower, "pushpull_test_slot",
                           "test controller of pushpull_test: a hand-bot showing one slot");

// A foot-bot broadcasting a pause, as a connecting foot-bot does, for
// `for` seconds.
class Pauser : public Controller {
 public:
  void Init(const Params& params) override {
    for_ = params.GetDouble("for", 1e9, 0, 1e9);
    rab_ = &GetActuator<RangeAndBearingActuator>("range_and_bearing");
  }
  void ControlStep() override {
    t_ += 0.1;
    rab_->SetByte(0, t_ <= for_ ? kPause : kNothing);
    rab_->SetByte(1, kFootBot);
    rab_->SetByte(2, 0xff);
    rab_->SetByte(3, 0xff);
  }

 private:
  double for_ = 1e9, t_ = 0;
  RangeAndBearingActuator* rab_ = nullptr;
};
COLONY_REGISTER_CONTROLLER(Pauser, "pushpull_test_pauser",
                           "test controller of pushpull_test: a foot-bot asking others to pause");

const char kFootbotConfig[] = R"(
    <pushpull_footbot id="fb" library="pushpull_footbot">
      <actuators>
        <differential_steering/>
        <gripper/>
        <leds/>
        <range_and_bearing data_size="4"/>
      </actuators>
      <sensors>
        <omnidirectional_camera range="2"/>
        <proximity/>
        <range_and_bearing/>
        <gripper/>
      </sensors>
      <params %PARAMS%/>
    </pushpull_footbot>)";

std::string Scene(const std::string& robots, const std::string& footbot_params = "",
                  const std::string& slot_params = "") {
  std::string fb = kFootbotConfig;
  fb.replace(fb.find("%PARAMS%"), 8, footbot_params);
  return R"(<colony>
  <framework><experiment length="60" ticks_per_second="10" random_seed="1"/></framework>
  <controllers>)" +
         fb + R"(
    <pushpull_test_slot id="slot"><actuators><leds/></actuators><sensors><positioning/></sensors>
      <params )" +
         slot_params + R"(/></pushpull_test_slot>
    <pushpull_test_pauser id="pauser"><actuators><range_and_bearing data_size="4"/></actuators>
      <params for="3"/></pushpull_test_pauser>
  </controllers>
  <arena size="4,4,2" center="0,0,1">)" +
         robots + R"(
  </arena>
  <physics_engines><dynamics3d id="d3d" stepper="worldstep"/></physics_engines>
  <media><range_and_bearing id="rab"/><led id="leds"/></media>
</colony>)";
}

std::string Handbot(const std::string& position, const std::string& orientation = "0,0,0") {
  return "<handbot id=\"h\"><body position=\"" + position + "\" orientation=\"" + orientation +
         "\"/><controller config=\"slot\"/></handbot>";
}
std::string Footbot(const std::string& id, const std::string& position,
                    const std::string& orientation, const std::string& config = "fb") {
  return "<marxbot id=\"" + id + "\"><body position=\"" + position + "\" orientation=\"" +
         orientation + "\"/><controller config=\"" + config + "\"/></marxbot>";
}

TEST(pushpull, AFootBotFindsAPullSlotConnectsAndPullsTheHandBot) {
  // The hand-bot's slot at LEDs 6-7 faces -x; the foot-bot starts 1 m away,
  // off to the side, facing away.
  auto sim = LoadXml(
      Scene(Handbot("0,0,0") + Footbot("f", "-1,0.5,0", "90,0,0"), "", "slot=\"6\" until=\"0.3\""));
  const uint32_t f = sim->space().Find("f").index;
  const Vec3 start = PositionOf(*sim, "h");
  bool held = false;
  while (!sim->Done()) {
    sim->Step();
    held = held || sim->space().Get<GripperState>(f)->holding();
  }
  EXPECT_TRUE(held) << "connected to the hand-bot";
  const Vec3 end = PositionOf(*sim, "h");
  EXPECT_GT((end - start).norm(), 0.3) << "moved the hand-bot";
  EXPECT_LT(end.x() - start.x(), -0.25) << "pulled it out towards the slot's side";
  EXPECT_FALSE(sim->space().Get<GripperState>(f)->holding()) << "and let go";
}

TEST(pushpull, AFootBotPushesAtAPushSlot) {
  auto sim = LoadXml(Scene(Handbot("0,0,0") + Footbot("f", "-1,-0.5,0", "0,0,0"), "",
                           "slot=\"6\" push=\"true\" until=\"0.3\""));
  const Vec3 start = PositionOf(*sim, "h");
  while (!sim->Done()) sim->Step();
  EXPECT_GT(PositionOf(*sim, "h").x() - start.x(), 0.25) << "pushed away from the slot's side";
}

TEST(pushpull, AFootBotThatHearsAPauseHoldsStillUntilTheTimeOut) {
  // The pauser asks for 3 s; with pause_timeout 1.5 s the foot-bot holds
  // 1.5 s, then moves on.
  auto sim =
      LoadXml(Scene(Footbot("f", "0,0,0", "0,0,0") + Footbot("p", "-0.7,0,0", "0,0,0", "pauser"),
                    "pause_timeout=\"1.5\""));
  RunFor(*sim, 0.2);  // the pause reaches it a tick after it is sent
  const Vec3 start = PositionOf(*sim, "f");
  RunFor(*sim, 1.2);
  EXPECT_LT((PositionOf(*sim, "f") - start).norm(), 0.002) << "held still while paused";
  RunFor(*sim, 1.5);
  EXPECT_GT((PositionOf(*sim, "f") - start).norm(), 0.05) << "moved on after the time-out";
}

TEST(pushpull, BadParametersAreNamedWithTheirLine) {
  EXPECT_TRUE(Mentions(LoadError(Scene(Footbot("f", "0,0,0", "0,0,0"), "speed=\"fast\"")),
                       {"speed", "'fast'"}));
  const std::string e = LoadError(Scene(Footbot("f", "0,0,0", "0,0,0"), "pause_timeout=\"-1\""));
  EXPECT_TRUE(Mentions(e, {"pause_timeout", "-1"})) << e;
}

// Two hand-bots by a 3 kg object under a ceiling 2.5 m up, their ropes on the
// ceiling above them (rope_anchor), both trying to lift at once.
std::string LiftScene(const std::string& b_position,
                      const std::string& params = "try_probability=\"10\"") {
  return R"(<colony>
  <framework><experiment length="30" ticks_per_second="10" random_seed="1"/></framework>
  <controllers>
    <pushpull_handbot id="hb" library="pushpull_handbot">
      <actuators><rope_launcher/><handbot_arms/><handbot_grippers/><handbot_fans/><leds/>
        <range_and_bearing data_size="4"/></actuators>
      <sensors><rope_traction/><imu/><handbot_gripper_proximity/><handbot_grippers/>
        <range_and_bearing/></sensors>
      <params retry_time="1000" )" +
         params + R"(/>
    </pushpull_handbot>
  </controllers>
  <arena size="3,3,3" center="0,0,1.5">
    <ceiling height="2.5"/>
    <handbot id="a" rope_anchor="-0.5,0"><body position="-0.5,0,0"/><controller config="hb"/></handbot>
    <handbot id="b" rope_anchor="0.5,0"><body position=")" +
         b_position + R"(" orientation="180,0,0"/><controller config="hb"/></handbot>
    <box id="object" size="0.3,0.4,0.22" movable="true" mass="3"><body position="0,0,0"/></box>
  </arena>
  <physics_engines><dynamics3d id="d3d" stepper="worldstep"/></physics_engines>
  <media><range_and_bearing id="rab"/><led id="leds"/></media>
</colony>)";
}

double TiltOf(Simulation& sim, const std::string& id) {
  const Quat& q = sim.space().pose(sim.space().Find(id).index).orientation;
  return std::acos(std::clamp((q * Vec3::UnitZ()).z(), -1.0, 1.0));
}

std::span<const Color> LedsOf(const Simulation& sim, const std::string& id) {
  return sim.space().leds(sim.space().Find(id).index);
}

TEST(pushpull, TwoHandBotsOnEitherSideLiftTheObjectLevel) {
  auto sim = LoadXml(LiftScene("0.5,0,0"));
  while (!sim->Done()) sim->Step();
  EXPECT_GT(PositionOf(*sim, "object").z(), 0.09) << "lifted 0.1 m";
  EXPECT_LT(TiltOf(*sim, "a"), 0.02);
  EXPECT_LT(TiltOf(*sim, "b"), 0.02);
  EXPECT_LT(TiltOf(*sim, "object"), 0.02);
}

TEST(pushpull, AHandBotAloneTipsGivesUpAndTheOtherAsksToBePushed) {
  // b stands 0.5 m back from where it would reach the object: it does not see it, so it shows a
  // push slot and does not try; a, alone, tips forward and goes back down.
  auto sim = LoadXml(LiftScene("1.0,0,0"));
  double highest = 0, most_tilt = 0;
  while (!sim->Done()) {
    sim->Step();
    highest = std::max(highest, PositionOf(*sim, "object").z());
    most_tilt = std::max(most_tilt, TiltOf(*sim, "a"));
  }
  EXPECT_GT(most_tilt, 0.08) << "a tipped forward holding the object alone";
  EXPECT_LT(highest, 0.09) << "the object never reached the lift height";
  EXPECT_LT(PositionOf(*sim, "object").z(), 0.005) << "back on the floor";
  EXPECT_LT(PositionOf(*sim, "a").z(), 0.005) << "a back on the floor";
  const auto b = LedsOf(*sim, "b");
  EXPECT_EQ(b[6], kSlotBlue);
  EXPECT_EQ(b[7], kPushViolet) << "b asks to be pushed to the object";
  const auto a = LedsOf(*sim, "a");
  EXPECT_EQ(a[6], kOff) << "a sees the object: no slot";
}

TEST(pushpull, AHandBotPressedAgainstTheObjectAsksToBePulledBack) {
  auto sim = LoadXml(
      LiftScene("0.5,0,0", "try_probability=\"0\" press=\"0.3\" see=\"0.1\" reach=\"0.05\""));
  RunFor(*sim, 1);
  const auto a = LedsOf(*sim, "a");
  EXPECT_EQ(a[6], kSlotBlue);
  EXPECT_EQ(a[7], kPullGreen);
}

TEST(pushpull, AHandBotsRopeStartsOnTheCeilingWhereTheFileSays) {
  auto sim = LoadXml(LiftScene("0.5,0,0", "try_probability=\"0\""));
  RunFor(*sim, 0.2);
  const RopeState& rope = *sim->space().Get<RopeState>(sim->space().Find("a").index);
  ASSERT_TRUE(rope.attached());
  EXPECT_NEAR(rope.anchor.x(), -0.5, 1e-9);
  EXPECT_NEAR(rope.anchor.z(), 2.5, 1e-9);
  EXPECT_NEAR(rope.length, 2.5 - 0.33, 0.002) << "taut, straight up";
  // Beyond the rope's reach: a warning, and the rope starts in its tube.
  ::testing::internal::CaptureStderr();
  std::string far = LiftScene("0.5,0,0", "try_probability=\"0\"");
  far.replace(far.find("rope_anchor=\"-0.5,0\""), 20, "rope_anchor=\"-4.0,0\"");
  auto sim2 = LoadXml(far);
  const std::string log = ::testing::internal::GetCapturedStderr();
  EXPECT_TRUE(Mentions(log, {"warning", "'a'", "rope_anchor", "beyond rope_length"})) << log;
  EXPECT_FALSE(sim2->space().Get<RopeState>(sim2->space().Find("a").index)->attached());
}

std::unique_ptr<Simulation> LoadPushPull(uint64_t seed, std::vector<std::string> overrides = {},
                                         std::optional<int> threads = std::nullopt) {
  return LoadExperiment("pushpull.xml", seed, std::move(overrides), threads);
}

TEST(pushpull, TheExperimentWithThreeFootBotsSucceeds) {
  // Seeds 1-3 with the file's 3 foot-bots: the foot-bots push the east
  // hand-bot to the object and the two hand-bots lift it.
  int successes = 0;
  for (uint64_t seed : {1, 2, 3}) {
    auto sim = LoadPushPull(seed);
    while (!sim->Done()) sim->Step();
    if (Metric(*sim, "success") != 1) continue;
    ++successes;
    EXPECT_LT(Metric(*sim, "completion_tick"), 50000) << "seed " << seed;
    EXPECT_GE(Metric(*sim, "connections"), 1) << "seed " << seed << ": a foot-bot pushed";
    EXPECT_GE(Metric(*sim, "lift_attempts"), 2) << "seed " << seed;
    EXPECT_GT(PositionOf(*sim, "object").z(), 0.085) << "seed " << seed;
  }
  EXPECT_GE(successes, 1);
}

TEST(pushpull, SameFinalHashWith0And1And2Threads) {
  std::vector<uint64_t> hashes;
  for (int threads : {0, 1, 2}) {
    auto sim = LoadPushPull(2, {"framework.experiment.length=120"}, threads);
    while (!sim->Done()) sim->Step();
    hashes.push_back(sim->StateHash());
  }
  EXPECT_EQ(hashes[0], hashes[1]);
  EXPECT_EQ(hashes[0], hashes[2]);
}

TEST(pushpull, BadLoopFunctionAndControllerParametersAreRefused) {
  const std::string file = ReadFile(COLONY_SOURCE_DIR "/experiments/pushpull.xml");
  EXPECT_TRUE(Mentions(LoadError(file, {"loop_functions.params.object=nothing"}),
                       {"object", "nothing", "no entity"}));
  EXPECT_TRUE(Mentions(LoadError(file, {"controllers.pushpull_handbot.params.reach=0.5"}),
                       {"reach", "see"}));
  EXPECT_TRUE(Mentions(LoadError(file, {"controllers.pushpull_footbot.params.move_time=never"}),
                       {"move_time", "never"}));
}

}  // namespace
}  // namespace colony::testing
