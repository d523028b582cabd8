// The camera sensor as a controller sees it: an RGB image of what is in
// front of the robot, drawn off-screen with no display; and refused at load
// by a build without an image renderer.
#include "sensors/camera/camera.h"

#include <cstdlib>
#include <string>

#include "core/output.h"
#include "core/registry.h"
#include "tests/test_util.h"

namespace colony {
namespace {

using testing::Experiment;
using testing::LoadError;
using testing::LoadXml;
using testing::Mentions;

// Keeps what its camera saw at the last control step.
class CameraProbe : public Controller {
 public:
  void Init(const Params& params) override { camera_ = &GetSensor<CameraSensor>("camera"); }
  void ControlStep() override { seen = *camera_; }
  CameraSensor seen;

 private:
  const CameraSensor* camera_ = nullptr;
};
COLONY_REGISTER_CONTROLLER(CameraProbe, "camera_probe", "test: records camera images");

// Holds its LEDs at the colour given in <leds color>.
class LedRobot : public Controller {
 public:
  void ControlStep() override {}
};
COLONY_REGISTER_CONTROLLER(LedRobot, "led_robot", "test: does nothing; its LEDs keep their colour");

std::string Controllers(const std::string& camera_attributes = "") {
  return "<camera_probe id=\"cp\"><sensors><camera " + camera_attributes +
         "/></sensors></camera_probe>";
}

std::string Robot(const std::string& id, const std::string& position, double yaw_degrees = 0) {
  return "<marxbot id=\"" + id + "\"><body position=\"" + position + "\" orientation=\"" +
         std::to_string(yaw_degrees) + ",0,0\"/><controller config=\"cp\"/></marxbot>";
}

std::string Cylinder(const std::string& id, const std::string& position, const std::string& color) {
  return "<cylinder id=\"" + id + "\" radius=\"0.1\" height=\"0.3\" color=\"" + color +
         "\"><body position=\"" + position + "\"/></cylinder>";
}

const CameraSensor& Seen(Simulation& sim, const std::string& robot) {
  auto* probe = dynamic_cast<CameraProbe*>(sim.ControllerOf(sim.space().Find(robot)));
  EXPECT_NE(probe, nullptr) << robot;
  static const CameraSensor kNone;
  return probe ? probe->seen : kNone;
}

std::string Text(Color c) {
  return std::to_string(c.r) + "," + std::to_string(c.g) + "," + std::to_string(c.b);
}
bool IsGreen(Color c) { return c.g > 80 && c.g > 2 * c.r && c.g > 2 * c.b; }
bool IsRed(Color c) { return c.r > 80 && c.r > 2 * c.g && c.r > 2 * c.b; }

class Camera : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!HaveImageRenderer()) GTEST_SKIP() << "this build has no image renderer";
    unsetenv("DISPLAY");
  }
};

TEST_F(Camera, FacingAGreenCylinderSeesGreenAtTheImageCentre) {
  auto sim = LoadXml(Experiment(
      Robot("r", "0,0,0") + Cylinder("green", "1,0,0", "green") + Cylinder("red", "0,1,0", "red"),
      Controllers()));
  sim->Step();
  const CameraSensor& image = Seen(*sim, "r");
  ASSERT_EQ(image.width(), 384);  // the marXbot's front camera, as used
  ASSERT_EQ(image.height(), 128);
  ASSERT_EQ(image.rgb().size(), 384u * 128 * 3);
  const Color centre = image.At(192, 64);
  EXPECT_TRUE(IsGreen(centre)) << Text(centre);
  // The red cylinder is to the robot's left, outside a 45 degree view.
  for (int x = 0; x < image.width(); ++x) {
    EXPECT_FALSE(IsRed(image.At(x, 64))) << x << ": " << Text(image.At(x, 64));
  }
}

TEST_F(Camera, TurnsWithTheRobotAndWithItsMount) {
  // The red cylinder is north (+y) of the robot: seen by a robot facing
  // north, or by one facing east with its camera turned 90 degrees left.
  const std::string cylinder = Cylinder("red", "0,1,0", "red");
  auto turned_robot = LoadXml(Experiment(Robot("r", "0,0,0", 90) + cylinder, Controllers()));
  auto turned_camera =
      LoadXml(Experiment(Robot("r", "0,0,0") + cylinder, Controllers("orientation=\"90,0,0\"")));
  auto neither = LoadXml(Experiment(Robot("r", "0,0,0") + cylinder, Controllers()));
  for (auto* sim : {turned_robot.get(), turned_camera.get(), neither.get()}) {
    sim->Step();
  }
  EXPECT_TRUE(IsRed(Seen(*turned_robot, "r").At(192, 64)))
      << Text(Seen(*turned_robot, "r").At(192, 64));
  EXPECT_TRUE(IsRed(Seen(*turned_camera, "r").At(192, 64)))
      << Text(Seen(*turned_camera, "r").At(192, 64));
  EXPECT_FALSE(IsRed(Seen(*neither, "r").At(192, 64))) << Text(Seen(*neither, "r").At(192, 64));
}

TEST_F(Camera, PitchTiltsTheCameraDown) {
  // Level, the image centre looks at the horizon, beyond the range: black.
  // Tilted 30 degrees down, it looks at the (white) floor 17 cm ahead.
  const std::string robot = Robot("r", "0,0,0");
  auto level = LoadXml(Experiment(robot, Controllers()));
  auto tilted = LoadXml(Experiment(robot, Controllers("orientation=\"0,30,0\"")));
  level->Step();
  tilted->Step();
  const Color horizon = Seen(*level, "r").At(192, 64), floor = Seen(*tilted, "r").At(192, 64);
  EXPECT_EQ(horizon, Color::Black()) << Text(horizon);
  EXPECT_EQ(floor, Color::White()) << Text(floor);
}

TEST_F(Camera, SeesADitchAsADarkBandWhereTheFloorWouldBeWhite) {
  // Tilted 30 degrees down, the image centre looks at the floor 17 cm ahead:
  // (26 cm ahead of the robot's centre): white on a flat floor, dark where
  // a ditch 7 cm wide crosses there.
  const std::string robot = Robot("r", "0,0,0");
  const std::string ditch =
      "<floor color=\"white\"><ditch center=\"0.26,0\" size=\"0.07,4\" "
      "depth=\"0.06\"/></floor>";
  auto flat = LoadXml(Experiment(robot, Controllers("orientation=\"0,30,0\"")));
  auto cut = LoadXml(Experiment(ditch + robot, Controllers("orientation=\"0,30,0\"")));
  flat->Step();
  cut->Step();
  const CameraSensor& seen = Seen(*cut, "r");
  for (int x : {10, 192, 373}) {
    EXPECT_EQ(Seen(*flat, "r").At(x, 64), Color::White()) << x;
    const Color c = seen.At(x, 64);
    EXPECT_LT(c.r + c.g + c.b, 3 * 60) << x << ": " << Text(c);
  }
  // Nearer (lower in the image) and farther (higher): the floor, white.
  EXPECT_EQ(seen.At(192, 127), Color::White()) << Text(seen.At(192, 127));
  EXPECT_EQ(seen.At(192, 0), Color::White()) << Text(seen.At(192, 0));
}

TEST_F(Camera, TheMarxbotFrontCameraPresetIs128By384AndBlindUpTo30CmAheadOfTheBody) {
  // The body's front is 8.5 cm from the robot's axis: the floor from 38.5 cm
  // on is seen, at the lowest row first. A ditch 2 cm wide 41 cm ahead shows
  // as a dark band low in the image; one 35 cm ahead, in the blind zone, not
  // at all.
  auto bottom_dark_rows = [](const std::string& centre_x) {
    auto sim = LoadXml(Experiment("<floor color=\"white\"><ditch center=\"" + centre_x +
                                      ",0\" size=\"0.02,4\" depth=\"0.06\"/></floor>" +
                                      Robot("r", "0,0,0"),
                                  Controllers("preset=\"marxbot_front_camera\"")));
    sim->Step();
    const CameraSensor& image = Seen(*sim, "r");
    EXPECT_EQ(image.width(), 128);
    EXPECT_EQ(image.height(), 384);
    int dark = 0;
    for (int y = 3 * image.height() / 4; y < image.height(); ++y) {  // the floor within 60 cm
      const Color c = image.At(image.width() / 2, y);
      dark += c.r + c.g + c.b < 3 * 60;
    }
    return dark;
  };
  EXPECT_GT(bottom_dark_rows("0.41"), 5);
  EXPECT_EQ(bottom_dark_rows("0.35"), 0);
  // The upper half looks above the horizon: beyond the range, black.
  auto sim = LoadXml(
      Experiment(Robot("r", "0,0,0"), Controllers("preset=\"marxbot_front_camera\" range=\"2\"")));
  sim->Step();
  EXPECT_EQ(Seen(*sim, "r").At(64, 10), Color::Black());
  // Attributes given override the preset's.
  auto small = LoadXml(
      Experiment(Robot("r", "0,0,0"), Controllers("preset=\"marxbot_front_camera\" width=\"32\"")));
  small->Step();
  EXPECT_EQ(Seen(*small, "r").width(), 32);
  EXPECT_EQ(Seen(*small, "r").height(), 384);
}

TEST_F(Camera, ResolutionFieldOfViewAndRangeFromXml) {
  // A 20 degree view misses a cylinder 30 degrees off the axis that a 90
  // degree view shows; beyond the range, nothing is seen.
  const std::string arena = Robot("r", "0,0,0") + Cylinder("green", "1,0.577,0", "green");
  auto narrow = LoadXml(Experiment(arena, Controllers("width=\"64\" height=\"48\" fov=\"20\"")));
  auto wide = LoadXml(Experiment(arena, Controllers("width=\"64\" height=\"48\" fov=\"90\"")));
  auto short_range = LoadXml(
      Experiment(arena, Controllers("width=\"64\" height=\"48\" fov=\"90\" range=\"0.5\"")));
  for (auto* sim : {narrow.get(), wide.get(), short_range.get()}) sim->Step();
  auto greens = [](const CameraSensor& image) {
    int n = 0;
    for (int y = 0; y < image.height(); ++y)
      for (int x = 0; x < image.width(); ++x) n += IsGreen(image.At(x, y));
    return n;
  };
  EXPECT_EQ(Seen(*wide, "r").width(), 64);
  EXPECT_EQ(Seen(*wide, "r").height(), 48);
  EXPECT_EQ(greens(Seen(*narrow, "r")), 0);
  EXPECT_GT(greens(Seen(*wide, "r")), 20);
  EXPECT_EQ(greens(Seen(*short_range, "r")), 0);
  // The cylinder is on the left of the image (the robot's left).
  EXPECT_TRUE(IsGreen(Seen(*wide, "r").At(13, 24))) << Text(Seen(*wide, "r").At(13, 24));
}

TEST_F(Camera, SeesOtherRobotsLeds) {
  // The camera level with the other robot's LED ring (13 cm up).
  const std::string controllers =
      Controllers("position=\"0.085,0,0.13\"") +
      "<led_robot id=\"lit\"><actuators><leds color=\"blue\"/></actuators></led_robot>";
  auto sim = LoadXml(
      Experiment(Robot("r", "0,0,0") +
                     "<marxbot id=\"other\"><body position=\"0.6,0,0\" orientation=\"180,0,0\"/>"
                     "<controller config=\"lit\"/></marxbot>",
                 controllers));
  sim->Step();
  const Color centre = Seen(*sim, "r").At(192, 64);
  EXPECT_GT(centre.b, 200) << Text(centre);
  EXPECT_LT(centre.r, 60) << Text(centre);
}

TEST_F(Camera, ImagesAreTheSameWhateverTheThreadCount) {
  const std::string arena = "<walls thickness=\"0.1\" height=\"0.3\"/>" + Robot("a", "0,0,0") +
                            Robot("b", "0.5,0.5,0", 200) + Robot("c", "-0.8,0.3,0", 45) +
                            Robot("d", "0.3,-1,0", 120) + Cylinder("g", "1,0,0", "green");
  const std::string controllers =
      Controllers("width=\"96\" height=\"32\" noise=\"gaussian\" noise_std_dev=\"0.02\"");
  auto hash = [&](int threads) {
    auto sim =
        LoadXml(Experiment(arena, controllers), {"framework.experiment.length=0.5"}, threads);
    return RunToEnd(*sim, nullptr, 0, {}).final_state_hash;
  };
  const uint64_t one = hash(0);
  EXPECT_EQ(hash(2), one);
  EXPECT_EQ(hash(4), one);
}

TEST(CameraErrors, BadSettingsAreRejected) {
  const std::string robot = Robot("r", "0,0,0");
  const std::string fov = LoadError(Experiment(robot, Controllers("fov=\"0\"")));
  EXPECT_NE(fov.find("<camera> attribute 'fov'"), std::string::npos) << fov;
  EXPECT_NE(fov.find("(0, 179]"), std::string::npos) << fov;
  const std::string width = LoadError(Experiment(robot, Controllers("width=\"0\"")));
  EXPECT_NE(width.find("attribute 'width'"), std::string::npos) << width;
  const std::string range = LoadError(Experiment(robot, Controllers("range=\"-1\"")));
  EXPECT_NE(range.find("attribute 'range'"), std::string::npos) << range;
  const std::string drop = LoadError(Experiment(robot, Controllers("drop_probability=\"0.5\"")));
  EXPECT_NE(drop.find("attribute 'drop_probability'"), std::string::npos) << drop;
  const std::string preset = LoadError(Experiment(robot, Controllers("preset=\"marxbot\"")));
  EXPECT_TRUE(Mentions(preset, {"attribute 'preset'", "marxbot_front_camera"})) << preset;
  const std::string aspect = LoadError(Experiment(robot, Controllers("pixel_aspect=\"0\"")));
  EXPECT_NE(aspect.find("attribute 'pixel_aspect'"), std::string::npos) << aspect;
}

TEST(CameraErrors, ABuildWithoutAnImageRendererRefusesTheCameraNamingTheOption) {
  const testing::WithoutImageRenderer no_image_renderer;
  const std::string message = LoadError(Experiment(Robot("r", "0,0,0"), "\n" + Controllers()));
  EXPECT_TRUE(
      Mentions(message, {"<string>:2: <camera>",
                         "the camera sensor needs an image renderer, and this build has none: "
                         "configure with -DCOLONY_WITH_OSMESA=ON (needs libosmesa6-dev and "
                         "libassimp-dev)"}));
}

}  // namespace
}  // namespace colony
