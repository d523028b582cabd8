// The eye-bot's pan-tilt head, laser pointer and pan-tilt camera as users
// meet them: the laser's spot where the beam meets the floor, a ditch or a
// box, seen as a red blob by a foot-bot's omnidirectional camera (and hidden
// by a robot in between); the head turning at its speeds, the shorter way
// round, warning once about a tilt beyond its range; the pan-tilt camera
// seeing landmarks, other robots' LEDs and its own laser's spot inside its
// cone, at the bearing and elevation that point the head at them; bad
// attributes reported with line and attribute.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "actuators/eyebot_laser/eyebot_laser.h"
#include "actuators/eyebot_pan_tilt/eyebot_pan_tilt.h"
#include "actuators/leds/leds.h"
#include "core/registry.h"
#include "entities/eyebot/eyebot.h"
#include "media/led/led_medium.h"
#include "media/test_util.h"
#include "sensors/eyebot_pan_tilt_camera/eyebot_pan_tilt_camera.h"
#include "sensors/omnidirectional_camera/omnidirectional_camera.h"

namespace colony {
namespace {

using testing::ExpectMentions;
using testing::LoadError;
using testing::LoadXml;
using testing::ReadmeAttributes;

// --- CastLaser on a bare space: floor, ditches, bodies, range

class EyebotLaserRay : public ::testing::Test {
 protected:
  EyebotLaserRay() {
    space.SetArena(Vec3(0, 0, 1.5), Vec3(10, 10, 3));
    Space::EntityInit init;
    init.id = "e";
    init.type = space.TypeId("eyebot");
    init.pose.position = Vec3(0, 0, 2);
    init.geometry.shape = ShapeKind::kCylinder;
    init.geometry.radius = eyebot::kRadius;
    init.geometry.size = Vec3(0.5, 0.5, eyebot::kHeight);
    init.flags = kSolid | kMovable | kRobot;
    init.components.Add<PanTiltState>().laser_on = true;
    eye = space.Add(std::move(init)).index;
    space.UpdateIndex();
  }
  PanTiltState& unit() { return *space.Get<PanTiltState>(eye); }
  // Points the laser: tilt from straight down, pan from the robot's front (degrees).
  void Aim(double pan, double tilt) {
    unit().pan = DegToRad(pan);
    unit().tilt = DegToRad(tilt);
  }
  uint32_t AddBox(const std::string& id, const Vec3& at, const Vec3& size, double yaw = 0) {
    Space::EntityInit init;
    init.id = id;
    init.type = space.TypeId("box");
    init.pose.position = at;
    init.pose.orientation = FromYaw(DegToRad(yaw));
    init.geometry.shape = ShapeKind::kBox;
    init.geometry.size = size;
    init.flags = kSolid;
    const uint32_t slot = space.Add(std::move(init)).index;
    space.UpdateIndex();
    return slot;
  }
  Space space;
  uint32_t eye = 0;
  const double head_z = 2 + eyebot::kPanTiltElevation;
};

TEST_F(EyebotLaserRay, StraightDownOrSlantedItMeetsTheFloor) {
  auto spot = CastLaser(space, eye);
  ASSERT_TRUE(spot.has_value());
  EXPECT_EQ(spot->entity, LaserSpot::kFloor);
  EXPECT_NEAR((spot->point - Vec3(0, 0, 0)).norm(), 0, 1e-12);
  EXPECT_NEAR(spot->distance, head_z, 1e-12);
  // 60 degrees from the vertical, 90 degrees left: on the floor at -x... +y.
  Aim(90, 60);
  spot = CastLaser(space, eye);
  ASSERT_TRUE(spot.has_value());
  EXPECT_NEAR((spot->point - Vec3(0, head_z * std::tan(DegToRad(60)), 0)).norm(), 0, 1e-9);
  EXPECT_NEAR(spot->distance, head_z / std::cos(DegToRad(60)), 1e-9);
  // The robot turned: the spot turns with it.
  space.pose(eye).orientation = FromYaw(DegToRad(90));
  spot = CastLaser(space, eye);
  ASSERT_TRUE(spot.has_value());
  EXPECT_NEAR((spot->point - Vec3(-head_z * std::tan(DegToRad(60)), 0, 0)).norm(), 0, 1e-9);
}

TEST_F(EyebotLaserRay, NothingWhenOffOrOutOfRange) {
  unit().laser_on = false;
  EXPECT_FALSE(CastLaser(space, eye).has_value());
  unit().laser_on = true;
  Aim(0, 90);  // horizontal: nothing in the arena
  EXPECT_FALSE(CastLaser(space, eye).has_value());
  Aim(0, 80);  // the floor 11.9 m away: beyond the 10 m range
  EXPECT_FALSE(CastLaser(space, eye).has_value());
  unit().laser_range = 12.0;
  EXPECT_TRUE(CastLaser(space, eye).has_value());
}

TEST_F(EyebotLaserRay, BoxesTakeTheSpotOnTheirTopOrSideAndTheRobotsOwnBodyDoesNot) {
  // Straight down through its own body: the floor; a box under it: its top.
  const uint32_t low = AddBox("low", Vec3(0, 0, 0), Vec3(0.4, 0.4, 0.3), 30);
  auto spot = CastLaser(space, eye);
  ASSERT_TRUE(spot.has_value());
  EXPECT_EQ(spot->entity, low);
  EXPECT_NEAR((spot->point - Vec3(0, 0, 0.3)).norm(), 0, 1e-12);
  // Nearly horizontal toward a tall box 1.8 m away: its side.
  const uint32_t tall = AddBox("tall", Vec3(2, 0, 0), Vec3(0.4, 2, 2.8));
  Aim(0, 80);
  spot = CastLaser(space, eye);
  ASSERT_TRUE(spot.has_value());
  EXPECT_EQ(spot->entity, tall);
  EXPECT_NEAR(spot->point.x(), 1.8, 1e-9);
  EXPECT_NEAR(spot->point.z(), head_z - 1.8 * std::tan(DegToRad(10)), 1e-9);
}

TEST_F(EyebotLaserRay, InADitchItMeetsTheBottomOrAWall) {
  space.floor().AddDitch({-0.5, -0.5, 0.5, 0.5, 0.2});
  auto spot = CastLaser(space, eye);
  ASSERT_TRUE(spot.has_value());
  EXPECT_EQ(spot->entity, LaserSpot::kFloor);
  EXPECT_NEAR((spot->point - Vec3(0, 0, -0.2)).norm(), 0, 1e-12);
  // Slanted at 10 degrees from the vertical: enters at x = 0.363, meets the
  // far wall (x = 0.5) 0.78 m... below the floor: at the wall, 0.2 m deep
  // would be x = 0.398: the bottom.
  Aim(0, 10);
  spot = CastLaser(space, eye);
  ASSERT_TRUE(spot.has_value());
  EXPECT_NEAR(spot->point.z(), -0.2, 1e-9);
  EXPECT_NEAR(spot->point.x(), (head_z + 0.2) * std::tan(DegToRad(10)), 1e-9);
  // At 13 degrees it enters at x = 0.475 and meets the wall at x = 0.5.
  Aim(0, 13);
  spot = CastLaser(space, eye);
  ASSERT_TRUE(spot.has_value());
  EXPECT_NEAR(spot->point.x(), 0.5, 1e-9);
  EXPECT_NEAR(spot->point.z(), -(0.5 / std::tan(DegToRad(13)) - head_z), 1e-9);
  EXPECT_LT(spot->point.z(), 0);
  EXPECT_GT(spot->point.z(), -0.2);
  // A neighbouring ditch beyond that wall: on to its bottom.
  space.floor().AddDitch({0.5, -0.5, 1.5, 0.5, 0.2});
  spot = CastLaser(space, eye);
  ASSERT_TRUE(spot.has_value());
  EXPECT_NEAR(spot->point.z(), -0.2, 1e-9);
}

// --- experiments: an eye-bot hanging from the ceiling, foot-bots below

// Records what its cameras see; drives the head and laser when asked. Params
// (all optional): pan, tilt (degrees), laser (true/false), only_led (light
// only that LED, in the colour of <leds color>).
class VisionProbe : public Controller {
 public:
  void Init(const Params& params) override {
    pan_tilt = Try<EyebotPanTiltActuator>(
        [&] { return &GetActuator<EyebotPanTiltActuator>("eyebot_pan_tilt"); });
    laser =
        Try<EyebotLaserActuator>([&] { return &GetActuator<EyebotLaserActuator>("eyebot_laser"); });
    leds = Try<Leds>([&] { return &GetActuator<Leds>("leds"); });
    head_camera = Try<const EyebotPanTiltCamera>(
        [&] { return &GetSensor<EyebotPanTiltCamera>("eyebot_pan_tilt_camera"); });
    omni = Try<const OmnidirectionalCamera>(
        [&] { return &GetSensor<OmnidirectionalCamera>("omnidirectional_camera"); });
    const double pan = params.GetDouble("pan", 0), tilt = params.GetDouble("tilt", 0);
    const bool on = params.GetBool("laser", false);
    const int64_t only = params.GetInt("only_led", -1);
    if (pan_tilt) {
      pan_tilt->SetPan(DegToRad(pan));
      pan_tilt->SetTilt(DegToRad(tilt));
    }
    if (laser) laser->Set(on);
    if (leds && only >= 0) {
      const Color c = leds->colors()[0];
      leds->SetAllColors(Color::Black());
      leds->SetSingleColor(static_cast<size_t>(only), c);
    }
  }
  void ControlStep() override {
    if (head_camera) head_blobs = head_camera->blobs();
    if (omni) omni_blobs = omni->blobs();
  }

  EyebotPanTiltActuator* pan_tilt = nullptr;
  EyebotLaserActuator* laser = nullptr;
  Leds* leds = nullptr;
  const EyebotPanTiltCamera* head_camera = nullptr;
  const OmnidirectionalCamera* omni = nullptr;
  std::vector<EyebotPanTiltCamera::Blob> head_blobs;
  std::vector<OmnidirectionalCamera::Blob> omni_blobs;

 private:
  template <class T, class F>
  static T* Try(F&& get) {
    try {
      return get();
    } catch (const std::logic_error&) {
      return nullptr;
    }
  }
};

COLONY_REGISTER_CONTROLLER(VisionProbe, "vision_probe",
                           "test: drives an eye-bot's head and laser, records camera blobs");

constexpr double kCeiling = 2.5;
// An attached eye-bot's head: its top at the ceiling, the head 6 cm above its base.
constexpr double kHeadZ = kCeiling - eyebot::kHeight + eyebot::kPanTiltElevation;

// An 8 x 8 x 3 m arena with its floor at z = 0 and a ceiling at 2.5 m;
// foot-bots in kinematics2d, eye-bots in pointmass3d; 10 ticks per second.
std::string World(const std::string& arena, const std::string& controllers,
                  const std::string& media = "") {
  return "<colony><framework><experiment length=\"100\" ticks_per_second=\"10\" "
         "random_seed=\"3\"/></framework>\n<controllers>" +
         controllers + "</controllers>\n" + media +
         "<arena size=\"8,8,3\" center=\"0,0,1.5\"><ceiling height=\"2.5\"/>" + arena +
         "</arena><physics_engines><kinematics2d id=\"ground\"/><pointmass3d id=\"air\" "
         "entities=\"eyebot\"/></physics_engines></colony>";
}

std::string Xyz(double x, double y, double z) {
  return std::to_string(x) + "," + std::to_string(y) + "," + std::to_string(z);
}

// An eye-bot hanging from the ceiling above (x, y), facing `yaw` degrees.
std::string Eyebot(const std::string& id, double x, double y, double yaw, const std::string& config,
                   const std::string& attributes = "") {
  return "<eyebot id=\"" + id + "\" attached=\"true\" " + attributes + "><body position=\"" +
         Xyz(x, y, kCeiling - eyebot::kHeight) + "\" orientation=\"" + std::to_string(yaw) +
         ",0,0\"/><controller config=\"" + config + "\"/></eyebot>";
}

std::string Footbot(const std::string& id, double x, double y, double yaw,
                    const std::string& config) {
  return "<marxbot id=\"" + id + "\"><body position=\"" + Xyz(x, y, 0) + "\" orientation=\"" +
         std::to_string(yaw) + ",0,0\"/><controller config=\"" + config + "\"/></marxbot>";
}

std::string Box(const std::string& id, const Vec3& at, const std::string& size) {
  return "<box id=\"" + id + "\" size=\"" + size + "\"><body position=\"" +
         Xyz(at.x(), at.y(), at.z()) + "\"/></box>";
}

// "eye": an eye-bot's head, laser, camera and green LED, with `eye_params`; "omni": a foot-bot's
// omnidirectional camera (`omni` attributes); "dark": nothing; "beacon": a foot-bot's beacon lit
// red.
std::string Controllers(const std::string& eye_params = "laser=\"true\"",
                        const std::string& omni = "") {
  return "<vision_probe id=\"eye\"><actuators><eyebot_pan_tilt/><eyebot_laser/><leds "
         "color=\"green\"/></actuators><sensors><eyebot_pan_tilt_camera/></sensors><params " +
         eye_params +
         "/></vision_probe>"
         "<vision_probe id=\"omni\"><sensors><omnidirectional_camera " +
         omni +
         "/></sensors></vision_probe>"
         "<vision_probe id=\"dark\"/>"
         "<vision_probe id=\"beacon\"><actuators><leds color=\"red\"/></actuators><params "
         "only_led=\"12\"/></vision_probe>";
}

bool HavePointmass3d() { return testing::HaveEngine("pointmass3d"); }
#define NEED_POINTMASS3D() \
  if (!HavePointmass3d()) GTEST_SKIP() << "the eye-bot needs pointmass3d"

VisionProbe& Probe(Simulation& sim, const std::string& id) {
  auto* probe = dynamic_cast<VisionProbe*>(sim.ControllerOf(sim.space().Find(id)));
  if (!probe) throw std::runtime_error("no probe on " + id);
  return *probe;
}

template <class Blob>
bool Red(const Blob& b) {
  return b.red == 255 && b.green == 0 && b.blue == 0;
}
template <class Blob>
std::vector<Blob> RedOnes(const std::vector<Blob>& blobs) {
  std::vector<Blob> out;
  std::copy_if(blobs.begin(), blobs.end(), std::back_inserter(out), Red<Blob>);
  return out;
}

// Where the laser of an attached eye-bot above (x, y) facing `yaw` meets the
// floor, with the head at pan and tilt (degrees).
Vec3 FloorSpot(double x, double y, double yaw, double pan, double tilt, double floor_z = 0) {
  const double reach = (kHeadZ - floor_z) * std::tan(DegToRad(tilt));
  const double a = DegToRad(yaw + pan);
  return Vec3(x + reach * std::cos(a), y + reach * std::sin(a), floor_z);
}

// Checks that a foot-bot at (x, y) facing `yaw` sees `blob` at `point`
// (horizontal distance within 1 cm, bearing within 1 degree).
void ExpectOmniBlobAt(const OmnidirectionalCamera::Blob& blob, double x, double y, double yaw,
                      const Vec3& point) {
  const Vec2 d(point.x() - x, point.y() - y);
  EXPECT_NEAR(blob.distance, d.norm(), 0.01);
  EXPECT_NEAR(WrapAngle(blob.bearing - (std::atan2(d.y(), d.x()) - DegToRad(yaw))), 0, DegToRad(1));
}

TEST(EyebotLaser, ItsSpotOnTheFloorIsARedBlobForAFootbot) {
  NEED_POINTMASS3D();
  auto sim = LoadXml(World(Eyebot("e", 0, 0, 20, "eye") + Footbot("f", 1.5, 0.2, 90, "omni"),
                           Controllers("laser=\"true\" pan=\"45\" tilt=\"30\"")));
  testing::RunFor(*sim, 1.0);
  const Vec3 expected = FloorSpot(0, 0, 20, 45, 30);
  const auto spot = CastLaser(sim->space(), sim->space().Find("e").index);
  ASSERT_TRUE(spot.has_value());
  EXPECT_EQ(spot->entity, LaserSpot::kFloor);
  EXPECT_NEAR((spot->point - expected).norm(), 0, 1e-6);
  const auto red = RedOnes(Probe(*sim, "f").omni_blobs);
  ASSERT_EQ(red.size(), 1u);
  ExpectOmniBlobAt(red[0], 1.5, 0.2, 90, expected);
  // Switched off: gone at the next tick.
  Probe(*sim, "e").laser->Off();
  sim->Step();
  EXPECT_FALSE(CastLaser(sim->space(), sim->space().Find("e").index).has_value());
  EXPECT_TRUE(RedOnes(Probe(*sim, "f").omni_blobs).empty());
}

TEST(EyebotLaser, ABoxInTheWayTakesTheSpotOnItsTopOrItsSide) {
  NEED_POINTMASS3D();
  const Vec3 floor_spot = FloorSpot(0, 0, 20, 45, 30);
  auto sim = LoadXml(World(Eyebot("e", 0, 0, 20, "eye") + Footbot("f", 1.5, 0.2, 90, "omni") +
                               Footbot("g", -1, -0.8, 90, "omni") +
                               Box("low", floor_spot, "0.4,0.4,0.15") +
                               Box("tall", Vec3(-2, 0, 0), "0.4,2,2.2"),
                           Controllers("laser=\"true\" pan=\"45\" tilt=\"30\"")));
  testing::RunFor(*sim, 1.0);
  const Space& space = sim->space();
  const uint32_t e = space.Find("e").index;
  // On top of the low box: nearer the robot than the floor spot would be.
  const Vec3 top = FloorSpot(0, 0, 20, 45, 30, 0.15);
  auto spot = CastLaser(space, e);
  ASSERT_TRUE(spot.has_value());
  EXPECT_EQ(spot->entity, space.Find("low").index);
  EXPECT_NEAR((spot->point - top).norm(), 0, 1e-6);
  auto red = RedOnes(Probe(*sim, "f").omni_blobs);
  ASSERT_EQ(red.size(), 1u) << "the box's top does not hide the spot on it";
  ExpectOmniBlobAt(red[0], 1.5, 0.2, 90, top);
  // Where the foot-bot sees it: 8.7 cm (0.15 tan 30 degrees) short of the floor spot.
  const double a = red[0].bearing + DegToRad(90);
  const Vec2 seen = Vec2(1.5, 0.2) + red[0].distance * Vec2(std::cos(a), std::sin(a));
  EXPECT_NEAR((seen - floor_spot.head<2>()).norm(), 0.15 * std::tan(DegToRad(30)), 0.01);
  // Turned toward the tall box (its near side at x = -1.8), 10 degrees below
  // the horizontal: the spot on its side, 1.94 m up.
  Probe(*sim, "e").pan_tilt->SetPan(DegToRad(160));  // the robot faces 20 degrees: 180 in the world
  Probe(*sim, "e").pan_tilt->SetTilt(DegToRad(80));
  testing::RunFor(*sim, 1.0);
  spot = CastLaser(space, e);
  ASSERT_TRUE(spot.has_value());
  EXPECT_EQ(spot->entity, space.Find("tall").index);
  const Vec3 side(-1.8, 0, kHeadZ - 1.8 * std::tan(DegToRad(10)));
  EXPECT_NEAR((spot->point - side).norm(), 0, 1e-6);
  // Foot-bot g, on the box's near side, 1.1 m horizontally from the spot.
  red = RedOnes(Probe(*sim, "g").omni_blobs);
  ASSERT_EQ(red.size(), 1u) << "the box's side does not hide the spot on it";
  ExpectOmniBlobAt(red[0], -1, -0.8, 90, side);
}

TEST(EyebotLaser, ARobotInBetweenHidesTheSpot) {
  NEED_POINTMASS3D();
  const Vec3 spot = FloorSpot(0, 0, 20, 45, 30);
  // A dark marXbot 0.3 m from the spot on the way to the camera, whose line
  // of sight there is 7 cm up: hidden. Without occlusion checks: seen.
  const Vec3 f(1.5, 0.2, 0);
  const Vec3 blocker = spot + 0.3 * (f - spot).normalized();
  const std::string arena = Eyebot("e", 0, 0, 20, "eye") + Footbot("f", f.x(), f.y(), 90, "omni") +
                            Footbot("b", blocker.x(), blocker.y(), 0, "dark");
  auto sim = LoadXml(World(arena, Controllers("laser=\"true\" pan=\"45\" tilt=\"30\"")));
  testing::RunFor(*sim, 1.0);
  EXPECT_TRUE(RedOnes(Probe(*sim, "f").omni_blobs).empty());
  auto blind = LoadXml(World(
      arena, Controllers("laser=\"true\" pan=\"45\" tilt=\"30\"", "check_occlusions=\"false\"")));
  testing::RunFor(*blind, 1.0);
  ASSERT_EQ(RedOnes(Probe(*blind, "f").omni_blobs).size(), 1u);
}

TEST(EyebotLaser, TheMediumHoldsOneRedPointPerLaserJustOffTheSurface) {
  NEED_POINTMASS3D();
  auto sim = LoadXml(World(
      Eyebot("e", 0, 0, 0, "eye") + Eyebot("q", 2, 0, 0, "eye") + Footbot("f", 1, -1, 0, "omni"),
      Controllers("laser=\"true\" tilt=\"40\""), "<media><led id=\"leds\"/></media>"));
  testing::RunFor(*sim, 1.0);
  const LedMedium* medium = nullptr;
  for (const auto& m : sim->media()) medium = dynamic_cast<const LedMedium*>(m.get());
  ASSERT_NE(medium, nullptr);
  const auto& spots = medium->laser_spots();
  ASSERT_EQ(spots.size(), 2u);
  const uint32_t e = sim->space().Find("e").index, q = sim->space().Find("q").index;
  for (const auto& [robot, x] : {std::pair{e, 0.0}, std::pair{q, 2.0}}) {
    const uint32_t owner = robot;  // a lambda cannot capture a structured binding (clang)
    const LedMedium::Led* s = medium->LaserSpotOf(owner);
    ASSERT_NE(s, nullptr);
    EXPECT_EQ(s->color, (Color{255, 0, 0, 255}));
    // 2 mm back along the beam (40 degrees from the vertical) from the floor.
    const Vec3 back = FloorSpot(x, 0, 0, 0, 40) -
                      0.002 * Vec3(std::sin(DegToRad(40)), 0, -std::cos(DegToRad(40)));
    EXPECT_NEAR((Vec3(s->x, s->y, s->z) - back).norm(), 0, 1e-9);
    EXPECT_EQ(std::count_if(medium->leds().begin(), medium->leds().end(),
                            [&](const LedMedium::Led& l) {
                              return l.owner == owner && l.x == s->x && l.z == s->z;
                            }),
              1);
  }
  EXPECT_EQ(medium->LaserSpotOf(sim->space().Find("f").index), nullptr);
}

// --- the head

TEST(EyebotPanTilt, PanAndTiltMoveAtTheirSpeedsTheShorterWayAndStopOnTheTargets) {
  NEED_POINTMASS3D();
  auto sim = LoadXml(World(Eyebot("e", 0, 0, 0, "eye", "tilt_speed=\"45\""), Controllers()));
  VisionProbe& p = Probe(*sim, "e");
  const PanTiltState& unit = *sim->space().Get<PanTiltState>(sim->space().Find("e").index);
  p.pan_tilt->SetPan(DegToRad(135));
  p.pan_tilt->SetTilt(DegToRad(45));
  // 180 degrees/s (the default) and 45 degrees/s: 18 and 4.5 degrees a tick.
  for (int t = 1; t <= 12; ++t) {
    sim->Step();
    EXPECT_NEAR(RadToDeg(p.pan_tilt->pan()), std::min(18.0 * t, 135.0), 1e-9) << "tick " << t;
    EXPECT_NEAR(RadToDeg(p.pan_tilt->tilt()), std::min(4.5 * t, 45.0), 1e-9) << "tick " << t;
    EXPECT_EQ(unit.pan, p.pan_tilt->pan());
    EXPECT_EQ(p.head_camera->pan(), unit.pan);
    EXPECT_EQ(p.head_camera->tilt(), unit.tilt);
  }
  EXPECT_EQ(p.pan_tilt->tilt(), DegToRad(45)) << "still on the target";
  // From 135 to -135 degrees: 90 degrees through the back, not 270 through the front.
  p.pan_tilt->SetPan(DegToRad(-135));
  const double expected[] = {153, 171, -171, -153, -135, -135};
  for (double e : expected) {
    sim->Step();
    EXPECT_NEAR(RadToDeg(p.pan_tilt->pan()), e, 1e-9);
  }
  // Any pan is wrapped to (-pi, pi].
  p.pan_tilt->SetPan(2 * M_PI + 0.5);
  EXPECT_NEAR(p.pan_tilt->target_pan(), 0.5, 1e-12);
  p.pan_tilt->SetPan(-M_PI);
  EXPECT_DOUBLE_EQ(p.pan_tilt->target_pan(), M_PI);
}

TEST(EyebotPanTilt, ATiltBeyondItsRangeGoesToTheNearestLimitWithOneWarning) {
  NEED_POINTMASS3D();
  auto sim = LoadXml(World(Eyebot("e", 0, 0, 0, "eye"), Controllers()));
  VisionProbe& p = Probe(*sim, "e");
  ::testing::internal::CaptureStderr();
  p.pan_tilt->SetTilt(2.0);
  testing::RunFor(*sim, 1.5);
  p.pan_tilt->SetTilt(-1.0);
  sim->Step();
  const std::string log = ::testing::internal::GetCapturedStderr();
  EXPECT_NE(log.find("robot 'e': tilt 2 rad"), std::string::npos) << log;
  EXPECT_NE(log.find("[0, 1.5708] rad"), std::string::npos) << log;
  EXPECT_NE(log.find("it goes to 1.5708 rad (90 degrees)"), std::string::npos) << log;
  EXPECT_EQ(log.find("tilt -1"), std::string::npos) << "said once per robot: " << log;
  EXPECT_DOUBLE_EQ(p.pan_tilt->target_tilt(), 0.0);
  testing::RunFor(*sim, 1.5);
  EXPECT_DOUBLE_EQ(p.pan_tilt->tilt(), 0.0);
}

// --- the pan-tilt camera

// The bearing and elevation (degrees, robot frame) of `point` from the head
// of an attached eye-bot above (x, y) facing `yaw`.
Vec2 Direction(double x, double y, double yaw, const Vec3& point) {
  const Vec3 d = point - Vec3(x, y, kHeadZ);
  return Vec2(RadToDeg(WrapAngle(std::atan2(d.y(), d.x()) - DegToRad(yaw))),
              RadToDeg(std::atan2(d.z(), std::hypot(d.x(), d.y()))));
}

TEST(EyebotPanTiltCamera, SeesLandmarksAndLedsWhereTheyAreInsideItsConeOnly) {
  NEED_POINTMASS3D();
  auto sim = LoadXml(World(Eyebot("e", 0, 0, 30, "eye") +
                               "<landmark id=\"post\" height=\"0.4\" color=\"blue\"><body "
                               "position=\"1,1,0\"/></landmark>" +
                               Footbot("f", -1, 0.5, 0, "beacon"),
                           Controllers("")));
  VisionProbe& p = Probe(*sim, "e");
  const Vec3 post(1, 1, 0.2), beacon(-1, 0.5, 0.147);
  // Pointed at each: seen on the axis, at the bearing and elevation that
  // point the head at it; the other, far outside the cone, is not seen.
  for (const bool at_post : {true, false}) {
    const Vec3 target = at_post ? post : beacon;
    const Vec2 at = Direction(0, 0, 30, target);
    p.pan_tilt->SetPan(DegToRad(at.x()));
    p.pan_tilt->SetTilt(DegToRad(90 + at.y()));
    testing::RunFor(*sim, 1.5);
    ASSERT_EQ(p.head_blobs.size(), 1u);
    const auto& b = p.head_blobs[0];
    EXPECT_EQ(b.blue, at_post ? 255 : 0);
    EXPECT_EQ(b.red, at_post ? 0 : 255);
    EXPECT_NEAR(b.distance, (target - Vec3(0, 0, kHeadZ)).norm(), 1e-5);
    EXPECT_NEAR(RadToDeg(b.bearing), at.x(), 1e-4);
    EXPECT_NEAR(RadToDeg(b.elevation), at.y(), 1e-4);
  }
  // The 60-degree cone: 25 degrees off the landmark (tilted past it) it is
  // still seen, 35 degrees off it is not.
  const Vec2 at = Direction(0, 0, 30, post);
  p.pan_tilt->SetPan(DegToRad(at.x()));
  p.pan_tilt->SetTilt(DegToRad(90 + at.y() + 25));
  testing::RunFor(*sim, 1.5);
  ASSERT_EQ(p.head_blobs.size(), 1u);
  EXPECT_EQ(p.head_blobs[0].blue, 255);
  p.pan_tilt->SetTilt(DegToRad(90 + at.y() + 35));
  testing::RunFor(*sim, 1.5);
  EXPECT_TRUE(p.head_blobs.empty());
}

TEST(EyebotPanTiltCamera, SeesItsOwnLaserSpotButNotItsOwnLed) {
  NEED_POINTMASS3D();
  auto sim = LoadXml(World(Eyebot("e", 0.5, -0.5, -60, "eye"), Controllers()));
  VisionProbe& p = Probe(*sim, "e");
  // Straight down: its own green LED is in the cone, under the head; only
  // the red spot under it is seen.
  testing::RunFor(*sim, 0.5);
  ASSERT_EQ(p.head_blobs.size(), 1u);
  EXPECT_TRUE(Red(p.head_blobs[0]));
  EXPECT_NEAR(p.head_blobs[0].distance, kHeadZ - 0.002, 1e-6);
  EXPECT_NEAR(RadToDeg(p.head_blobs[0].elevation), -90, 1e-4);
  // Turned: the spot on the axis, at the bearing and elevation of the head.
  p.pan_tilt->SetPan(DegToRad(-120));
  p.pan_tilt->SetTilt(DegToRad(50));
  testing::RunFor(*sim, 1.5);
  ASSERT_EQ(p.head_blobs.size(), 1u);
  EXPECT_TRUE(Red(p.head_blobs[0]));
  EXPECT_NEAR(p.head_blobs[0].distance, kHeadZ / std::cos(DegToRad(50)) - 0.002, 1e-6);
  EXPECT_NEAR(RadToDeg(p.head_blobs[0].bearing), -120, 1e-4);
  EXPECT_NEAR(RadToDeg(p.head_blobs[0].elevation), -40, 1e-4);
}

TEST(EyebotPanTiltCamera, SameStateHashWhateverTheThreadCount) {
  NEED_POINTMASS3D();
  std::string arena;
  for (int i = 0; i < 6; ++i) {
    arena += Eyebot("e" + std::to_string(i), -3 + 1.2 * i, 0.5 * (i % 2), 40 * i, "eye") +
             Footbot("f" + std::to_string(i), -3 + 1.2 * i, -1, 25 * i, "omni") +
             Footbot("g" + std::to_string(i), -3 + 1.2 * i, 1.5, 0, "beacon");
  }
  const std::string xml =
      World(arena,
            "<vision_probe id=\"eye\"><actuators><eyebot_pan_tilt/><eyebot_laser/><leds "
            "color=\"green\"/></actuators><sensors><eyebot_pan_tilt_camera noise=\"gaussian\" "
            "noise_std_dev=\"0.02\" angle_noise_std_dev=\"0.01\" drop_probability=\"0.1\" "
            "fov=\"90\"/></sensors><params laser=\"true\" pan=\"150\" tilt=\"40\"/></vision_probe>"
            "<vision_probe id=\"omni\"><sensors><omnidirectional_camera/></sensors></vision_probe>"
            "<vision_probe id=\"beacon\"><actuators><leds color=\"red\"/></actuators><params "
            "only_led=\"12\"/></vision_probe>");
  uint64_t reference = 0;
  size_t seen = 0;
  for (int threads : {0, 2}) {
    auto sim = LoadXml(xml, {}, threads);
    testing::RunFor(*sim, 1.0);
    if (threads == 0) {
      reference = sim->StateHash();
      for (int i = 0; i < 6; ++i) seen += Probe(*sim, "e" + std::to_string(i)).head_blobs.size();
    }
    EXPECT_EQ(sim->StateHash(), reference) << threads << " threads";
  }
  EXPECT_GT(seen, 6u) << "the cameras see something";
}

// --- bad input

// The pan-tilt camera (line 2) on the devices of an eye-bot at line 3.
std::string Lines(const std::string& camera, const std::string& eyebot_attributes = "",
                  const std::string& robot = "eyebot") {
  return "<colony><framework><experiment length=\"1\" ticks_per_second=\"10\"/></framework>\n"
         "<controllers><vision_probe id=\"c\"><sensors><eyebot_pan_tilt_camera " +
         camera +
         "/></sensors><actuators><eyebot_pan_tilt/><eyebot_laser/></actuators></vision_probe>"
         "</controllers>\n<arena size=\"4,4,3\" center=\"0,0,1.5\"><" +
         robot + " id=\"r\" " + eyebot_attributes +
         "><body position=\"0,0,0\"/><controller config=\"c\"/></" + robot +
         "></arena><physics_engines><kinematics2d id=\"ground\"/><pointmass3d id=\"air\" "
         "entities=\"eyebot\"/></physics_engines></colony>";
}

TEST(EyebotPanTiltCamera, BadAttributesAreReportedWithElementAndLine) {
  NEED_POINTMASS3D();
  EXPECT_EQ(LoadError(Lines("")), "");
  const std::string at = ":2: <eyebot_pan_tilt_camera> attribute ";
  ExpectMentions(LoadError(Lines("fov=\"0\"")), {at + "'fov'", "(0, 180"});
  ExpectMentions(LoadError(Lines("fov=\"180\"")), {at + "'fov'", "(0, 180)"});
  ExpectMentions(LoadError(Lines("fov=\"wide\"")), {at + "'fov'", "not a finite number"});
  ExpectMentions(LoadError(Lines("range=\"0\"")), {at + "'range'", "> 0"});
  ExpectMentions(LoadError(Lines("check_occlusions=\"maybe\"")),
                 {at + "'check_occlusions'", "true, false"});
  ExpectMentions(LoadError(Lines("angle_noise_std_dev=\"-0.1\"")),
                 {at + "'angle_noise_std_dev'", ">= 0"});
  ExpectMentions(LoadError(Lines("noise=\"gaussian\"")), {at + "'noise_std_dev'", "required"});
  ExpectMentions(LoadError(Lines("medium=\"eyes\"")),
                 {at + "'medium'", "no medium with id 'eyes'"});
  ExpectMentions(LoadError(Lines("fvo=\"60\"")), {at + "'fvo'", "did you mean 'fov'"});
  // The head's speeds and the laser's range are the robot's.
  ExpectMentions(LoadError(Lines("", "pan_speed=\"0\"")),
                 {":3: <eyebot id=\"r\"> attribute 'pan_speed'", "> 0"});
  ExpectMentions(LoadError(Lines("", "laser_range=\"-1\"")),
                 {":3: <eyebot id=\"r\"> attribute 'laser_range'", "> 0"});
  // A robot without a pan-tilt unit cannot carry them.
  ExpectMentions(LoadError(Lines("", "", "marxbot")),
                 {"robot 'r' (a marxbot, line 3) cannot carry this sensor: it has no pan_tilt",
                  "cannot carry this actuator: it has no pan_tilt"});
}

TEST(EyebotPanTiltCamera, RegisteredAttributesMatchTheReadmes) {
  const auto* camera = Registry<SensorSystem>::Get().Find("eyebot_pan_tilt_camera");
  ASSERT_NE(camera, nullptr);
  auto names = camera->info.AttributeNames();
  names.push_back("implementation");
  EXPECT_EQ(ReadmeAttributes("sensors/eyebot_pan_tilt_camera/README.md", "## XML"), names);
  for (const std::string actuator : {"eyebot_pan_tilt", "eyebot_laser"}) {
    const auto* entry = Registry<ActuatorSystem>::Get().Find(actuator);
    ASSERT_NE(entry, nullptr) << actuator;
    auto listed = entry->info.AttributeNames();
    listed.push_back("implementation");
    EXPECT_EQ(ReadmeAttributes("actuators/" + actuator + "/README.md", "# " + actuator), listed);
  }
}

}  // namespace
}  // namespace colony
