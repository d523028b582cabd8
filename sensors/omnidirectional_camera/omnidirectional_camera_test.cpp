// The omnidirectional camera as a controller sees it: blobs of other robots'
// LEDs, lights and landmarks, at the right distance and bearing in the
// robot's frame, hidden behind walls, limited by range and aperture, noisy
// as declared.
#include "sensors/omnidirectional_camera/omnidirectional_camera.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "actuators/leds/leds.h"
#include "core/registry.h"
#include "media/test_util.h"

namespace colony {
namespace {

using testing::ExpectMentions;
using testing::Experiment;
using testing::LoadError;
using testing::LoadXml;
using testing::ReadmeAttributes;

// Records the blobs it sees. Param only_led="k" lights LED k alone (in the
// colour of <leds color>), off="T" switches every LED off at control step T.
class CameraProbe : public Controller {
 public:
  void Init(const Params& params) override {
    only_ = params.GetInt("only_led", -1);
    off_at_ = params.GetInt("off", -1);
    try {
      camera_ = &GetSensor<OmnidirectionalCamera>("omnidirectional_camera");
    } catch (const std::logic_error&) {
    }
    try {
      leds_ = &GetActuator<Leds>("leds");
    } catch (const std::logic_error&) {
    }
    if (leds_ && only_ >= 0) {
      const Color c = leds_->colors()[0];
      leds_->SetAllColors(Color::Black());
      leds_->SetSingleColor(static_cast<size_t>(only_), c);
    }
  }
  void ControlStep() override {
    ++steps;
    if (camera_) blobs = camera_->blobs();
    if (leds_ && steps == off_at_) leds_->SetAllColors(Color::Black());
  }
  std::vector<OmnidirectionalCamera::Blob> blobs;
  int steps = 0;

 private:
  int64_t only_ = -1, off_at_ = -1;
  const OmnidirectionalCamera* camera_ = nullptr;
  Leds* leds_ = nullptr;
};

COLONY_REGISTER_CONTROLLER(CameraProbe, "camera_probe",
                           "test: records omnidirectional camera blobs");

// "eye": a camera, LEDs off; "lit": red LEDs, no camera; "both": both.
std::string Controllers(const std::string& camera = "", const std::string& lit_params = "") {
  return "<camera_probe id=\"eye\"><sensors><omnidirectional_camera " + camera +
         "/></sensors></camera_probe>"
         "<camera_probe id=\"lit\"><actuators><leds color=\"red\"/></actuators><params " +
         lit_params +
         "/></camera_probe>"
         "<camera_probe id=\"both\"><sensors><omnidirectional_camera " +
         camera + "/></sensors><actuators><leds color=\"blue\"/></actuators></camera_probe>";
}

std::string Robot(const std::string& id, double x, double y, double yaw_degrees = 0,
                  const std::string& config = "eye") {
  return "<marxbot id=\"" + id + "\"><body position=\"" + std::to_string(x) + "," +
         std::to_string(y) + ",0\" orientation=\"" + std::to_string(yaw_degrees) +
         ",0,0\"/><controller config=\"" + config + "\"/></marxbot>";
}

std::string Landmark(const std::string& id, double x, double y,
                     const std::string& attributes = "") {
  return "<landmark id=\"" + id + "\" " + attributes + "><body position=\"" + std::to_string(x) +
         "," + std::to_string(y) + ",0\"/></landmark>";
}

std::string Box(const std::string& id, const std::string& size, const std::string& position) {
  return "<box id=\"" + id + "\" size=\"" + size + "\"><body position=\"" + position + "\"/></box>";
}

const std::vector<OmnidirectionalCamera::Blob>& Blobs(Simulation& sim, const std::string& robot) {
  auto* probe = dynamic_cast<CameraProbe*>(sim.ControllerOf(sim.space().Find(robot)));
  if (!probe) throw std::runtime_error("no probe on " + robot);
  return probe->blobs;
}

bool Red(const OmnidirectionalCamera::Blob& b) {
  return b.red == 255 && b.green == 0 && b.blue == 0;
}
bool Green(const OmnidirectionalCamera::Blob& b) {
  return b.red == 0 && b.green == 255 && b.blue == 0;
}

// The one blob seen, or a failure.
OmnidirectionalCamera::Blob Only(Simulation& sim, const std::string& robot) {
  const auto& blobs = Blobs(sim, robot);
  EXPECT_EQ(blobs.size(), 1u) << robot;
  return blobs.empty() ? OmnidirectionalCamera::Blob{0, 0, 0, -1, -100} : blobs[0];
}

TEST(OmnidirectionalCamera, LandmarksFrontLeftBehindRight) {
  // One eye per scene, 6 m apart (beyond range), each with one landmark.
  auto sim =
      LoadXml(Experiment(Robot("front", -3, -3) + Landmark("l1", -2, -3) + Robot("left", 3, -3) +
                             Landmark("l2", 3, -2.5) + Robot("behind", -3, 3) +
                             Landmark("l3", -4.2, 3) + Robot("right", 3, 3) + Landmark("l4", 3, 2),
                         Controllers(), "10,10,1"));
  sim->Step();
  auto b = Only(*sim, "front");
  EXPECT_NEAR(b.distance, 1.0, 1e-6);
  EXPECT_NEAR(b.bearing, 0.0, 1e-6);
  EXPECT_TRUE(Green(b));
  b = Only(*sim, "left");
  EXPECT_NEAR(b.distance, 0.5, 1e-6);
  EXPECT_NEAR(b.bearing, M_PI / 2, 1e-6);
  b = Only(*sim, "behind");
  EXPECT_NEAR(b.distance, 1.2, 1e-6);
  EXPECT_NEAR(b.bearing, M_PI, 1e-6);
  EXPECT_GT(b.bearing, 0.0f);  // (-pi, pi]
  b = Only(*sim, "right");
  EXPECT_NEAR(b.distance, 1.0, 1e-6);
  EXPECT_NEAR(b.bearing, -M_PI / 2, 1e-6);
}

TEST(OmnidirectionalCamera, BearingIsInTheRobotsFrame) {
  // Facing +y: a landmark at +x is on the right, one at -y behind.
  auto sim = LoadXml(Experiment(Robot("north", -3, 0, 90) + Landmark("east", -2, 0) +
                                    Robot("north2", 3, 0, 90) + Landmark("south", 3, -0.7) +
                                    Robot("ne", 0, 3, 45) + Landmark("l", 0, 4),
                                Controllers(), "10,10,1"));
  sim->Step();
  EXPECT_NEAR(Only(*sim, "north").bearing, -M_PI / 2, 1e-6);
  EXPECT_NEAR(std::abs(Only(*sim, "north2").bearing), M_PI, 1e-6);
  EXPECT_NEAR(Only(*sim, "north2").distance, 0.7, 1e-6);
  EXPECT_NEAR(Only(*sim, "ne").bearing, M_PI / 4, 1e-6);  // north is 45 degrees left of north-east
}

TEST(OmnidirectionalCamera, EachLitLedOfAnotherRobotIsABlobWhereTheLedIs) {
  // The other robot at (1, 0), turned 90 degrees, lights only its LED 0 (its
  // front, so at +y in the world) and then only its beacon (index 12, on top
  // of its axis).
  {
    auto sim = LoadXml(Experiment(Robot("eye", 0, 0) + Robot("other", 1, 0, 90, "lit"),
                                  Controllers("", "only_led=\"0\"")));
    sim->Step();
    const auto b = Only(*sim, "eye");
    EXPECT_TRUE(Red(b));
    EXPECT_NEAR(b.distance, std::hypot(1.0, 0.075), 1e-6);
    EXPECT_NEAR(b.bearing, std::atan2(0.075, 1.0), 1e-6);
  }
  {
    auto sim =
        LoadXml(Experiment(Robot("eye", 0, 0) + Robot("other", 1, 0, 90, "lit"),
                           Controllers("", "only_led=\"3\"")));  // 90 degrees left of its front: -x
    sim->Step();
    const auto b = Only(*sim, "eye");
    EXPECT_NEAR(b.distance, 1 - 0.075, 1e-6);
    EXPECT_NEAR(b.bearing, 0.0, 1e-6);
  }
  {
    auto sim = LoadXml(Experiment(Robot("eye", 0, 0) + Robot("other", 1, 0, 90, "lit"),
                                  Controllers("", "only_led=\"12\"")));
    sim->Step();
    const auto b = Only(*sim, "eye");
    EXPECT_NEAR(b.distance, 1.0, 1e-6);
    EXPECT_NEAR(b.bearing, 0.0, 1e-6);
  }
  // All 13 lit: 13 red blobs, 12 on a circle of 7.5 cm around the robot's axis.
  auto sim =
      LoadXml(Experiment(Robot("eye", 0, 0) + Robot("other", 0, 1, 0, "lit"), Controllers()));
  sim->Step();
  const auto& blobs = Blobs(*sim, "eye");
  ASSERT_EQ(blobs.size(), 13u);
  int on_ring = 0;
  for (const auto& b : blobs) {
    EXPECT_TRUE(Red(b));
    const double x = b.distance * std::cos(b.bearing), y = b.distance * std::sin(b.bearing);
    const double from_axis = std::hypot(x, y - 1.0);
    if (std::abs(from_axis - 0.075) < 1e-6)
      ++on_ring;
    else
      EXPECT_NEAR(from_axis, 0.0, 1e-6);
  }
  EXPECT_EQ(on_ring, 12);
}

TEST(OmnidirectionalCamera, OwnLedsAndUnlitLedsAreNotSeen) {
  // "both" lights its own LEDs blue and sees nothing of them; "eye" robots
  // have their LEDs off and are not seen either.
  auto sim =
      LoadXml(Experiment(Robot("self", 0, 0, 0, "both") + Robot("dark", 0.5, 0), Controllers()));
  sim->Step();
  EXPECT_TRUE(Blobs(*sim, "self").empty());
  // "dark" sees self's 13 blue LEDs.
  EXPECT_EQ(Blobs(*sim, "dark").size(), 13u);
  for (const auto& b : Blobs(*sim, "dark")) EXPECT_EQ(b.blue, 255);
}

TEST(OmnidirectionalCamera, LedsSwitchedOffDisappearAtTheNextTick) {
  auto sim = LoadXml(Experiment(Robot("eye", 0, 0) + Robot("other", 1, 0, 0, "lit"),
                                Controllers("", "off=\"2\"")));
  sim->Step();
  EXPECT_EQ(Blobs(*sim, "eye").size(), 13u);
  sim->Step();  // "other" switches off during this control step
  EXPECT_EQ(Blobs(*sim, "eye").size(), 13u);
  sim->Step();
  EXPECT_TRUE(Blobs(*sim, "eye").empty());
}

TEST(OmnidirectionalCamera, LightsAreSeenInTheirColour) {
  auto sim = LoadXml(
      Experiment(Robot("eye", 0, 0) + "<light id=\"l\" position=\"0,1,0.2\" color=\"orange\"/>",
                 Controllers()));
  sim->Step();
  const auto b = Only(*sim, "eye");
  EXPECT_NEAR(b.distance, 1.0, 1e-6);
  EXPECT_NEAR(b.bearing, M_PI / 2, 1e-6);
  EXPECT_GT(b.red, 200);
  EXPECT_EQ(b.blue, 0);
}

TEST(OmnidirectionalCamera, BlobsBehindAWallAreNotSeenWhenOcclusionsAreChecked) {
  // A wall between eye and the landmark and robot on its east; nothing to its north.
  const std::string arena =
      Robot("eye", 0, 0) + Landmark("hidden", 1, 0) + Robot("hidden_robot", 1, 0.4, 0, "lit") +
      Box("wall", "0.1,1.4,0.3", "0.5,0.2,0") + Landmark("open", 0, 1, "color=\"blue\"");
  auto checked = LoadXml(Experiment(arena, Controllers()));
  checked->Step();
  const auto b = Only(*checked, "eye");
  EXPECT_EQ(b.blue, 255);
  EXPECT_NEAR(b.bearing, M_PI / 2, 1e-6);
  auto unchecked = LoadXml(Experiment(arena, Controllers("check_occlusions=\"false\"")));
  unchecked->Step();
  EXPECT_EQ(Blobs(*unchecked, "eye").size(), 1u + 1u + 13u);
}

TEST(OmnidirectionalCamera, ALowObstacleDoesNotHideWhatTheCameraSeesOverIt) {
  // The camera is 28.8 cm up: a 5 cm box between it and a landmark (centre
  // 10 cm up) 1 m away does not hide it; a 25 cm one does.
  auto sim = LoadXml(Experiment(Robot("eye", 0, -1) + Landmark("l1", 1, -1) +
                                    Box("low", "0.1,0.4,0.05", "0.5,-1,0") + Robot("eye2", 0, 1) +
                                    Landmark("l2", 1, 1) + Box("high", "0.1,0.4,0.25", "0.5,1,0"),
                                Controllers("range=\"1.2\"")));
  sim->Step();
  EXPECT_EQ(Blobs(*sim, "eye").size(), 1u);
  EXPECT_TRUE(Blobs(*sim, "eye2").empty());
}

TEST(OmnidirectionalCamera, RangeLimitIsExact) {
  // Default range 1.5 m (horizontal distance from the camera's axis).
  auto sim = LoadXml(Experiment(Robot("a", -2, -1) + Landmark("in", -2 + 1.5 - 1e-6, -1) +
                                    Robot("b", -2, 2) + Landmark("out", -2 + 1.5 + 1e-6, 2),
                                Controllers(), "6,6,1"));
  sim->Step();
  EXPECT_NEAR(Only(*sim, "a").distance, 1.5, 1e-5);
  EXPECT_TRUE(Blobs(*sim, "b").empty());
  auto narrow = LoadXml(Experiment(Robot("a", 0, -1) + Landmark("in", 0.5 - 1e-6, -1) +
                                       Robot("b", 0, 1) + Landmark("out", 0.5 + 1e-6, 1),
                                   Controllers("range=\"0.5\"")));
  narrow->Step();
  EXPECT_EQ(Blobs(*narrow, "a").size(), 1u);
  EXPECT_TRUE(Blobs(*narrow, "b").empty());
}

TEST(OmnidirectionalCamera, ApertureHidesBlobsTooHighOrTooLow) {
  // Camera at 0.288 m. A light 2 m up, 0.3 m away: 80 degrees above the
  // camera's plane. A 2 cm landmark (centre 1 cm up) 0.1 m away: 70.2
  // degrees below (a thin one: landmarks are solid). Both outside the
  // default 70 degrees; inside 85.
  const std::string arena = "<light id=\"high\" position=\"0.3,0,2\"/>" + Robot("eye", 0, 0) +
                            Robot("eye2", 0, 2) +
                            Landmark("low", 0.1, 2, "height=\"0.02\" radius=\"0.01\"");
  auto sim = LoadXml(Experiment(arena, Controllers(), "6,6,1"));
  sim->Step();
  EXPECT_TRUE(Blobs(*sim, "eye").empty());
  EXPECT_TRUE(Blobs(*sim, "eye2").empty());
  auto wide = LoadXml(Experiment(arena, Controllers("aperture=\"85\""), "6,6,1"));
  wide->Step();
  EXPECT_EQ(Blobs(*wide, "eye").size(), 1u);
  EXPECT_EQ(Blobs(*wide, "eye2").size(), 1u);
  EXPECT_NEAR(Blobs(*wide, "eye2")[0].distance, 0.1, 1e-6);
  // A camera mounted lower (elevation 0.05 m) sees the low landmark 22 degrees below.
  auto low = LoadXml(Experiment(arena, Controllers("elevation=\"0.05\""), "6,6,1"));
  low->Step();
  EXPECT_EQ(Blobs(*low, "eye2").size(), 1u);
}

TEST(OmnidirectionalCamera, BlackLandmarksAreNotSeen) {
  auto sim = LoadXml(Experiment(Robot("eye", 0, 0) + Landmark("l", 1, 0, "color=\"black\"") +
                                    Landmark("m", -1, 0, "color=\"255,0,255\""),
                                Controllers()));
  sim->Step();
  const auto b = Only(*sim, "eye");
  EXPECT_EQ(b.red, 255);
  EXPECT_EQ(b.green, 0);
  EXPECT_EQ(b.blue, 255);
}

// --- noise

// 36 landmarks on a circle of radius 1 around an eye at the origin.
std::string Ring() {
  std::string arena = Robot("eye", 0, 0);
  for (int i = 0; i < 36; ++i) {
    const double a = 2 * M_PI * i / 36;
    arena += Landmark("l" + std::to_string(i), std::cos(a), std::sin(a));
  }
  return arena;
}

struct Samples {
  std::vector<double> distance_errors, bearing_errors;
};

Samples Sample(const std::string& camera, int ticks) {
  auto sim = LoadXml(Experiment(Ring(), Controllers(camera)));
  Samples s;
  for (int t = 0; t < ticks; ++t) {
    sim->Step();
    for (const auto& b : Blobs(*sim, "eye")) {
      s.distance_errors.push_back(b.distance - 1.0);
      // The nearest landmark direction (every 10 degrees).
      const double nearest = std::round(b.bearing / (2 * M_PI / 36)) * (2 * M_PI / 36);
      s.bearing_errors.push_back(WrapAngle(b.bearing - nearest));
      EXPECT_GT(b.bearing, -M_PI);
      EXPECT_LE(b.bearing, static_cast<float>(M_PI));
    }
  }
  return s;
}

double StdDev(const std::vector<double>& v) {
  double mean = 0, sum = 0;
  for (double x : v) mean += x;
  mean /= v.size();
  for (double x : v) sum += (x - mean) * (x - mean);
  return std::sqrt(sum / (v.size() - 1));
}

TEST(OmnidirectionalCamera, NoNoiseGivesExactValues) {
  const Samples s = Sample("", 2);
  ASSERT_EQ(s.distance_errors.size(), 72u);
  for (double e : s.distance_errors) EXPECT_NEAR(e, 0, 1e-6);
  for (double e : s.bearing_errors) EXPECT_NEAR(e, 0, 1e-6);
}

TEST(OmnidirectionalCamera, NoiseHasTheDeclaredSpread) {
  // Bearing noise 0.015 rad keeps blobs well within +-5 degrees of their landmark.
  const Samples s =
      Sample("noise=\"gaussian\" noise_std_dev=\"0.03\" bearing_noise_std_dev=\"0.015\"", 150);
  ASSERT_EQ(s.distance_errors.size(), 150u * 36);
  EXPECT_NEAR(StdDev(s.distance_errors), 0.03, 0.03 * 0.04);
  EXPECT_NEAR(StdDev(s.bearing_errors), 0.015, 0.015 * 0.04);
  const Samples u = Sample("noise=\"uniform\" noise_range=\"-0.05,0.05\"", 150);
  for (double e : u.distance_errors) {
    ASSERT_GE(e, -0.05 - 1e-6);
    ASSERT_LE(e, 0.05 + 1e-6);
  }
  EXPECT_NEAR(StdDev(u.distance_errors), 0.1 / std::sqrt(12.0), 0.1 / std::sqrt(12.0) * 0.04);
}

TEST(OmnidirectionalCamera, MissProbabilityIsAsDeclared) {
  const Samples s = Sample("drop_probability=\"0.25\"", 150);
  EXPECT_NEAR(s.distance_errors.size() / (150.0 * 36), 0.75, 0.025);
}

TEST(OmnidirectionalCamera, SameStateHashWhateverTheThreadCount) {
  const std::string xml = Experiment(
      "<walls thickness=\"0.1\" height=\"0.5\"/>" + Box("b", "0.2,1,0.3", "0,0,0") +
          Landmark("lm", 1, 1) +
          "<distribute><position method=\"uniform\" min=\"-1.8,-1.8,0\" max=\"1.8,1.8,0\"/>"
          "<orientation method=\"uniform\" min=\"0,0,0\" max=\"360,0,0\"/>"
          "<entity quantity=\"60\" max_trials=\"1000\"><marxbot id=\"mb\"><controller "
          "config=\"both\"/></marxbot>"
          "</entity></distribute>",
      Controllers("noise=\"gaussian\" noise_std_dev=\"0.02\" bearing_noise_std_dev=\"0.05\" "
                  "drop_probability=\"0.1\""),
      "4,4,1");
  uint64_t reference = 0;
  for (int threads : {0, 1, 2, 4}) {
    auto sim = LoadXml(xml, {}, threads);
    for (int t = 0; t < 4; ++t) sim->Step();
    if (threads == 0) reference = sim->StateHash();
    EXPECT_EQ(sim->StateHash(), reference) << threads << " threads";
  }
}

// --- bad input

std::string Lines(const std::string& camera, const std::string& media = "") {
  return "<colony><framework><experiment length=\"1\" ticks_per_second=\"10\" "
         "random_seed=\"1\"/></framework>\n"
         "<controllers><camera_probe id=\"eye\"><sensors><omnidirectional_camera " +
         camera + "/></sensors></camera_probe></controllers>\n" + media +
         "<arena size=\"4,4,1\"><marxbot id=\"r\"><body position=\"0,0,0\"/><controller "
         "config=\"eye\"/></marxbot>"
         "</arena><physics_engines><kinematics2d id=\"k\"/></physics_engines></colony>";
}

TEST(OmnidirectionalCamera, BadAttributesAreReportedWithElementAndLine) {
  const std::string at = ":2: <omnidirectional_camera> attribute ";
  ExpectMentions(LoadError(Lines("range=\"-1\"")), {at + "'range'", "> 0"});
  ExpectMentions(LoadError(Lines("aperture=\"0\"")), {at + "'aperture'", "(0, 90]"});
  ExpectMentions(LoadError(Lines("aperture=\"120\"")), {at + "'aperture'", "(0, 90]"});
  ExpectMentions(LoadError(Lines("elevation=\"high\"")),
                 {at + "'elevation'", "not a finite number"});
  ExpectMentions(LoadError(Lines("check_occlusions=\"yes\"")),
                 {at + "'check_occlusions'", "true, false"});
  ExpectMentions(LoadError(Lines("noise=\"pink\"")), {at + "'noise'", "none, gaussian, uniform"});
  ExpectMentions(LoadError(Lines("noise=\"uniform\"")), {at + "'noise_range'", "required"});
  ExpectMentions(LoadError(Lines("bearing_noise_std_dev=\"-1\"")),
                 {at + "'bearing_noise_std_dev'", ">= 0"});
  ExpectMentions(LoadError(Lines("medium=\"eyes\"")),
                 {at + "'medium'", "no medium with id 'eyes'"});
  ExpectMentions(
      LoadError(Lines("medium=\"rab\"", "<media><range_and_bearing id=\"rab\"/></media>\n")),
      {"medium 'rab' is a <range_and_bearing>, not a <led>"});
  ExpectMentions(LoadError(Lines("", "<media><led id=\"leds\" cell_size=\"-2\"/></media>\n")),
                 {":3: <led id=\"leds\"> attribute 'cell_size'", "> 0"});
  EXPECT_EQ(
      LoadError(Lines("medium=\"leds\"", "<media><led id=\"leds\" cell_size=\"0.7\"/></media>\n")),
      "");
  // The landmark's attributes.
  ExpectMentions(LoadError(Experiment(Landmark("l", 0, 0, "height=\"0\""))),
                 {"<landmark id=\"l\">", "'height'", "> 0"});
  ExpectMentions(LoadError(Experiment(Landmark("l", 0, 0, "color=\"sky\""))),
                 {"'color'", "is not a colour"});
}

// --- documentation

TEST(OmnidirectionalCamera, RegisteredAttributesMatchTheReadme) {
  const auto* entry = Registry<SensorSystem>::Get().Find("omnidirectional_camera");
  ASSERT_NE(entry, nullptr);
  auto names = entry->info.AttributeNames();
  names.push_back("implementation");
  EXPECT_EQ(ReadmeAttributes("sensors/omnidirectional_camera/README.md", "## XML"), names);
  const auto* landmark = Registry<EntityType>::Get().Find("landmark");
  ASSERT_NE(landmark, nullptr);
  auto landmark_names = landmark->info.AttributeNames();
  landmark_names.insert(landmark_names.begin(), "id");
  EXPECT_EQ(ReadmeAttributes("entities/objects/README.md", "## landmark"), landmark_names);
}

}  // namespace
}  // namespace colony
