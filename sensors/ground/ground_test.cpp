// Ground sensors as a controller sees them: 8 downward sensors on the
// marXbot reading the floor's grey level, 0 black .. 1 white, from a flat
// floor colour or a PNG image stretched over the arena.
#include "sensors/ground/ground.h"

#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <regex>
#include <string>
#include <vector>

#include "core/registry.h"
#include "tests/test_util.h"

namespace colony {
namespace {

using testing::Experiment;
using testing::LoadError;
using testing::LoadXml;

class GroundProbe : public Controller {
 public:
  void Init(const Params& params) override { sensor_ = &GetSensor<GroundSensor>("ground"); }
  void ControlStep() override { last = sensor_->readings(); }
  std::vector<GroundSensor::Reading> last;

 private:
  const GroundSensor* sensor_ = nullptr;
};

COLONY_REGISTER_CONTROLLER(GroundProbe, "ground_probe", "test: records ground readings");

std::string Controllers(const std::string& attributes = "") {
  return "<ground_probe id=\"gp\"><sensors><ground " + attributes + "/></sensors></ground_probe>";
}

std::string Robot(const std::string& id, const std::string& position, double yaw_degrees = 0) {
  return "<marxbot id=\"" + id + "\"><body position=\"" + position + "\" orientation=\"" +
         std::to_string(yaw_degrees) + ",0,0\"/><controller config=\"gp\"/></marxbot>";
}

const std::vector<GroundSensor::Reading>& Readings(Simulation& sim, const std::string& robot) {
  auto* probe = dynamic_cast<GroundProbe*>(sim.ControllerOf(sim.space().Find(robot)));
  EXPECT_NE(probe, nullptr) << robot;
  static const std::vector<GroundSensor::Reading> kNone;
  return probe ? probe->last : kNone;
}

// --- A minimal PNG writer (RGB, 8 bits, zlib "stored" blocks), so the test
// needs no image library: the test target links only libcolony.
uint32_t Crc32(const uint8_t* data, size_t n, uint32_t crc = 0) {
  crc = ~crc;
  for (size_t i = 0; i < n; ++i) {
    crc ^= data[i];
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

void PutU32(std::vector<uint8_t>& out, uint32_t v) {
  for (int s = 24; s >= 0; s -= 8) out.push_back(static_cast<uint8_t>(v >> s));
}

void Chunk(std::vector<uint8_t>& png, const char* type, const std::vector<uint8_t>& data) {
  PutU32(png, static_cast<uint32_t>(data.size()));
  std::vector<uint8_t> body(type, type + 4);
  body.insert(body.end(), data.begin(), data.end());
  png.insert(png.end(), body.begin(), body.end());
  PutU32(png, Crc32(body.data(), body.size()));
}

// `rgb` holds width*height*3 bytes, row 0 first (the arena's max-y edge).
void WritePng(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb) {
  std::vector<uint8_t> raw;
  for (int y = 0; y < height; ++y) {
    raw.push_back(0);  // filter: none
    raw.insert(raw.end(), rgb.begin() + y * width * 3, rgb.begin() + (y + 1) * width * 3);
  }
  std::vector<uint8_t> z = {0x78, 0x01};
  size_t pos = 0;
  do {
    const size_t len = std::min<size_t>(65535, raw.size() - pos);
    z.push_back(pos + len == raw.size() ? 1 : 0);
    z.push_back(static_cast<uint8_t>(len));
    z.push_back(static_cast<uint8_t>(len >> 8));
    z.push_back(static_cast<uint8_t>(~len));
    z.push_back(static_cast<uint8_t>(~len >> 8));
    z.insert(z.end(), raw.begin() + pos, raw.begin() + pos + len);
    pos += len;
  } while (pos < raw.size());
  uint32_t a = 1, b = 0;
  for (uint8_t c : raw) {
    a = (a + c) % 65521;
    b = (b + a) % 65521;
  }
  PutU32(z, (b << 16) | a);
  std::vector<uint8_t> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  std::vector<uint8_t> ihdr;
  PutU32(ihdr, width);
  PutU32(ihdr, height);
  ihdr.insert(ihdr.end(), {8, 2, 0, 0, 0});  // 8 bits, RGB, deflate, no filter, no interlace
  Chunk(png, "IHDR", ihdr);
  Chunk(png, "IDAT", z);
  Chunk(png, "IEND", {});
  FILE* f = std::fopen(path.c_str(), "wb");
  ASSERT_NE(f, nullptr) << path;
  std::fwrite(png.data(), 1, png.size(), f);
  std::fclose(f);
}

std::string TempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("colony_ground_test_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

TEST(Ground, MarxbotHasEightSensorsFortyFiveDegreesApart) {
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0"), Controllers()));
  sim->Step();
  const auto& r = Readings(*sim, "r");
  ASSERT_EQ(r.size(), 8u);
  for (size_t i = 0; i < r.size(); ++i) {
    // Same direction as 45 * i degrees (the sign of 180 degrees aside).
    EXPECT_NEAR(std::cos(r[i].angle), std::cos(DegToRad(45.0 * i)), 1e-6) << "sensor " << i;
    EXPECT_NEAR(std::sin(r[i].angle), std::sin(DegToRad(45.0 * i)), 1e-6) << "sensor " << i;
  }
  EXPECT_NEAR(r[0].angle, 0.0, 1e-7);  // the first looks forwards
  EXPECT_NEAR(r[2].angle, M_PI / 2, 1e-6);
}

TEST(Ground, AnglesAreInTheDocumentedInterval) {
  // WrapAngle (core/math.h) promises (-pi, pi]; the sensor straight behind
  // (180 degrees) should read +pi. Exposes WrapAngle(pi) == -pi.
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0"), Controllers()));
  sim->Step();
  const auto& r = Readings(*sim, "r");
  ASSERT_EQ(r.size(), 8u);
  for (const auto& x : r) {
    EXPECT_GT(x.angle, -static_cast<float>(M_PI)) << "angle " << x.angle;
    EXPECT_LE(x.angle, static_cast<float>(M_PI)) << "angle " << x.angle;
  }
}

TEST(Ground, FlatColoursReadTheirGreyLevel) {
  struct Case {
    const char* color;
    double grey;
  } cases[] = {{"black", 0.0}, {"white", 1.0}, {"gray50", 127 / 255.0}, {"255,0,0", 0.299}};
  for (const auto& c : cases) {
    auto sim = LoadXml(
        Experiment("<floor color=\"" + std::string(c.color) + "\"/>" + Robot("r", "0.3,-0.2,0", 33),
                   Controllers()));
    sim->Step();
    for (const auto& x : Readings(*sim, "r")) EXPECT_NEAR(x.value, c.grey, 1e-3) << c.color;
  }
}

TEST(Ground, DefaultFloorIsWhite) {
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0"), Controllers()));
  sim->Step();
  for (const auto& x : Readings(*sim, "r")) EXPECT_FLOAT_EQ(x.value, 1.0f);
}

TEST(Ground, ImageFloorIsReadUnderEachSensor) {
  // 2 x 2 image over the 4 x 4 arena: north-west black, north-east white,
  // south-west white, south-east grey. Row 0 of the image is the north
  // (max y) edge.
  const std::string path = TempPath("quadrants.png");
  WritePng(path, 2, 2, {0, 0, 0, 255, 255, 255, 255, 255, 255, 128, 128, 128});
  auto sim =
      LoadXml(Experiment("<floor source=\"image\" path=\"" + path + "\"/>" + Robot("nw", "-1,1,0") +
                             Robot("ne", "1,1,0") + Robot("sw", "-1,-1,0") + Robot("se", "1,-1,0") +
                             Robot("edge", "0,1,0", 90),
                         Controllers()));
  sim->Step();
  for (const auto& x : Readings(*sim, "nw")) EXPECT_NEAR(x.value, 0.0, 1e-6);
  for (const auto& x : Readings(*sim, "ne")) EXPECT_NEAR(x.value, 1.0, 1e-6);
  for (const auto& x : Readings(*sim, "sw")) EXPECT_NEAR(x.value, 1.0, 1e-6);
  for (const auto& x : Readings(*sim, "se")) EXPECT_NEAR(x.value, 128 / 255.0, 1e-3);
  // Straddling the black/white line x = 0 while facing north (+y): the
  // sensors on its left (west) read black, those on its right white.
  const auto& edge = Readings(*sim, "edge");
  ASSERT_EQ(edge.size(), 8u);
  for (int i : {1, 2, 3})
    EXPECT_NEAR(edge[i].value, 0.0, 1e-6) << "sensor " << i;  // 45..135 degrees: west
  for (int i : {5, 6, 7})
    EXPECT_NEAR(edge[i].value, 1.0, 1e-6) << "sensor " << i;  // 225..315 degrees: east
  std::filesystem::remove(path);
}

TEST(Ground, ReadingsFollowTheRobot) {
  // Left half of the arena black, right half white; the robot is moved from
  // the black half into the white half between two ticks.
  const std::string path = TempPath("halves.png");
  WritePng(path, 2, 1, {0, 0, 0, 255, 255, 255});
  auto sim = LoadXml(Experiment(
      "<floor source=\"image\" path=\"" + path + "\"/>" + Robot("r", "-0.5,0,0"), Controllers()));
  sim->Step();
  for (const auto& x : Readings(*sim, "r")) EXPECT_EQ(x.value, 0.0f);
  sim->space().pose(sim->space().Find("r").index).position.x() = 0.5;
  sim->Step();
  for (const auto& x : Readings(*sim, "r")) EXPECT_EQ(x.value, 1.0f);
  std::filesystem::remove(path);
}

TEST(Ground, MissingImageIsReported) {
  const std::string message = LoadError(
      Experiment("<floor source=\"image\" path=\"/nonexistent/floor.png\"/>" + Robot("r", "0,0,0"),
                 Controllers()));
  EXPECT_NE(message.find("attribute 'path'"), std::string::npos) << message;
  EXPECT_NE(message.find("/nonexistent/floor.png"), std::string::npos) << message;
  const std::string no_path =
      LoadError(Experiment("<floor source=\"image\"/>" + Robot("r", "0,0,0"), Controllers()));
  EXPECT_NE(no_path.find("attribute 'path'"), std::string::npos) << no_path;
}

TEST(Ground, NoiseIsReproducibleAndClamped) {
  const std::string arena = "<floor color=\"gray50\"/>" + Robot("r", "0,0,0");
  const std::string noisy = Controllers("noise=\"gaussian\" noise_std_dev=\"0.1\"");
  auto a = LoadXml(Experiment(arena, noisy));
  auto b = LoadXml(Experiment(arena, noisy));
  bool changed = false;
  for (int t = 0; t < 5; ++t) {
    a->Step();
    b->Step();
    const auto& ra = Readings(*a, "r");
    const auto& rb = Readings(*b, "r");
    ASSERT_EQ(ra.size(), rb.size());
    for (size_t i = 0; i < ra.size(); ++i) {
      EXPECT_EQ(ra[i].value, rb[i].value);
      EXPECT_NEAR(ra[i].value, 0.5, 0.6);
      changed = changed || std::abs(ra[i].value - 127 / 255.0) > 1e-4;
    }
  }
  EXPECT_TRUE(changed);
  // On white, large noise is clamped at 1.
  auto white = LoadXml(
      Experiment(Robot("r", "0,0,0"), Controllers("noise=\"uniform\" noise_range=\"0,0.5\"")));
  white->Step();
  for (const auto& x : Readings(*white, "r")) EXPECT_EQ(x.value, 1.0f);
}

TEST(Ground, DroppedReadingsReadZero) {
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0"), Controllers("drop_probability=\"1\"")));
  sim->Step();
  for (const auto& x : Readings(*sim, "r")) EXPECT_EQ(x.value, 0.0f);
}

// --- Ditches: a sensor over a hole reads 0 ("no ground"), unless something
// solid fills the hole up to within 1 cm of the sensor's height.

// A 3 x 3 cm ditch under the front sensor only (0.065 m ahead of the axis).
const std::string kFrontDitch =
    "<floor color=\"gray50\"><ditch center=\"0.065,0\" size=\"0.03,0.03\" depth=\"0.06\"/></floor>";
constexpr float kGray50 = 127 / 255.0f;

void MoveTo(Simulation& sim, const std::string& id, double x, double y, double z) {
  sim.space().pose(sim.space().Find(id).index).position = Vec3(x, y, z);
}

TEST(Ground, SensorOverADitchReadsNoGround) {
  auto sim = LoadXml(Experiment(kFrontDitch + Robot("r", "0,0,0"), Controllers()));
  sim->Step();
  const auto& r = Readings(*sim, "r");
  ASSERT_EQ(r.size(), 8u);
  EXPECT_EQ(r[0].value, 0.0f) << "the front sensor is over the ditch";
  for (int i = 1; i < 8; ++i) EXPECT_NEAR(r[i].value, kGray50, 1e-6) << "sensor " << i;
  // Moved 6.5 cm past the ditch and facing +y: the ditch is on its left
  // (90 degrees), under sensor 2.
  MoveTo(*sim, "r", 0.13, 0, 0);
  sim->space().pose(sim->space().Find("r").index).orientation = FromEulerZYX(M_PI / 2, 0, 0);
  sim->Step();
  for (int i = 0; i < 8; ++i)
    EXPECT_NEAR(r[i].value, i == 2 ? 0.0f : kGray50, 1e-6) << "sensor " << i;
}

TEST(Ground, SomethingFillingTheDitchUpToTheFloorIsRead) {
  // A red box, put into the ditch under the front sensor after loading (the
  // loader does not place things below the floor).
  auto sim = LoadXml(
      Experiment(kFrontDitch + Robot("r", "0,0,0") +
                     "<box id=\"b\" size=\"0.03,0.03,0.06\" movable=\"true\" color=\"255,0,0\">"
                     "<body position=\"1,1,0\"/></box>",
                 Controllers()));
  const auto& r = Readings(*sim, "r");
  auto front_with_box_top_at = [&](double top) {
    MoveTo(*sim, "b", 0.065, 0, top - 0.06);
    sim->Step();
    return r[0].value;
  };
  EXPECT_NEAR(front_with_box_top_at(0.0), 0.299, 1e-3) << "flush with the floor: the box's grey";
  EXPECT_NEAR(front_with_box_top_at(-0.008), 0.299, 1e-3) << "8 mm down still reflects";
  EXPECT_EQ(front_with_box_top_at(-0.012), 0.0f) << "12 mm down: no ground";
  EXPECT_EQ(front_with_box_top_at(-0.05), 0.0f);
  for (int i = 1; i < 8; ++i) EXPECT_NEAR(r[i].value, kGray50, 1e-6) << "the others read the floor";
}

TEST(Ground, RobotDownInADitchReadsItsBottom) {
  // A wide ditch; the robot first over it at floor level, then down in it.
  auto sim = LoadXml(Experiment(
      "<floor color=\"gray50\"><ditch center=\"1,1\" size=\"0.5,0.5\" depth=\"0.08\"/></floor>" +
          Robot("r", "0,0,0"),
      Controllers()));
  sim->Step();
  for (const auto& x : Readings(*sim, "r"))
    EXPECT_NEAR(x.value, kGray50, 1e-6) << "a ditch elsewhere changes nothing";
  MoveTo(*sim, "r", 1, 1, 0);
  sim->Step();
  for (const auto& x : Readings(*sim, "r")) EXPECT_EQ(x.value, 0.0f) << "over the ditch";
  MoveTo(*sim, "r", 1, 1, -0.08);
  sim->Step();
  for (const auto& x : Readings(*sim, "r"))
    EXPECT_NEAR(x.value, kGray50, 1e-6) << "on the ditch's bottom";
}

TEST(Ground, NoGroundWithNoiseStaysInRange) {
  auto sim = LoadXml(Experiment(kFrontDitch + Robot("r", "0,0,0"),
                                Controllers("noise=\"uniform\" noise_range=\"-0.1,0\"")));
  for (int t = 0; t < 5; ++t) {
    sim->Step();
    EXPECT_EQ(Readings(*sim, "r")[0].value, 0.0f) << "0 minus noise is clamped at 0";
  }
}

TEST(Ground, RegisteredAttributesMatchTheReadme) {
  const auto* entry = Registry<SensorSystem>::Get().Find("ground");
  ASSERT_NE(entry, nullptr);
  const std::vector<std::string> registered = entry->info.AttributeNames();
  EXPECT_EQ(registered, (std::vector<std::string>{"noise", "noise_std_dev", "noise_range",
                                                  "drop_probability"}));
  // The README's table also lists `implementation`, which every device takes.
  const std::string text = testing::ReadFile(COLONY_SOURCE_DIR "/sensors/ground/README.md");
  std::vector<std::string> documented;
  const std::regex row(R"(\n\| `([a-z_]+)` \|)");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), row); it != std::sregex_iterator();
       ++it) {
    if ((*it)[1] != "implementation") documented.push_back((*it)[1]);
  }
  EXPECT_EQ(documented, registered);
}

}  // namespace
}  // namespace colony
