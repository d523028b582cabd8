// The osmesa renderer as a user meets it: frames from <visualization> with no
// display, what they show, meshes, overlays, bad settings, results unchanged,
// and `colony run --frames / --video`; and the image renderer it provides
// (core/image_renderer.h), which draws the camera sensor's images.
#include <png.h>
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "actuators/handbot_arms/handbot_arms_state.h"
#include "actuators/rope_launcher/rope_state.h"
#include "core/drawing.h"
#include "core/image_renderer.h"
#include "core/loop_functions.h"
#include "core/output.h"
#include "core/registry.h"
#include "entities/eyebot/eyebot.h"
#include "render/osmesa/view.h"
#include "sensors/camera/camera.h"
#include "tests/test_util.h"

namespace colony {
namespace {

namespace fs = std::filesystem;
using testing::Experiment;
using testing::LoadError;
using testing::LoadXml;

// Holds its LEDs at the colour given in <leds color>.
class LedHolder : public Controller {
 public:
  void ControlStep() override {}
};
COLONY_REGISTER_CONTROLLER(LedHolder, "led_holder",
                           "test: does nothing; its LEDs keep their colour");

const std::string kRedRobots =
    "<led_holder id=\"red\"><actuators><leds color=\"red\"/></actuators></led_holder>";

std::string Robot(const std::string& id, const std::string& position,
                  const std::string& config = "red") {
  return "<marxbot id=\"" + id + "\"><body position=\"" + position + "\"/><controller config=\"" +
         config + "\"/></marxbot>";
}

std::string Visualization(const std::string& osmesa_attributes, const std::string& children) {
  return "\n<visualization>\n  <osmesa " + osmesa_attributes + ">\n    " + children +
         "\n  </osmesa>\n</visualization>";
}

// A camera 1 m above (x, y), looking straight down, north up.
std::string TopCamera(const std::string& x_y) {
  return "<camera id=\"top\" position=\"" + x_y + ",1\" look_at=\"" + x_y +
         ",0\" up=\"0,1,0\" fov=\"60\"/>";
}

struct Png {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;
  Color At(int x, int y) const {
    const uint8_t* p = rgb.data() + (static_cast<size_t>(y) * width + x) * 3;
    return {p[0], p[1], p[2], 255};
  }
};

Png ReadPng(const fs::path& path) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  Png out;
  if (!png_image_begin_read_from_file(&image, path.c_str())) {
    ADD_FAILURE() << "cannot read " << path;
    return out;
  }
  image.format = PNG_FORMAT_RGB;
  out.width = static_cast<int>(image.width);
  out.height = static_cast<int>(image.height);
  out.rgb.resize(PNG_IMAGE_SIZE(image));
  EXPECT_TRUE(png_image_finish_read(&image, nullptr, out.rgb.data(), 0, nullptr)) << path;
  return out;
}

void WriteTwoColourPng(const fs::path& path, Color top, Color bottom) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = 4;
  image.height = 4;
  image.format = PNG_FORMAT_RGB;
  std::vector<uint8_t> rgb;
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 4; ++x) {
      const Color c = y < 2 ? top : bottom;
      rgb.insert(rgb.end(), {c.r, c.g, c.b});
    }
  }
  ASSERT_TRUE(png_image_write_to_file(&image, path.c_str(), 0, rgb.data(), 0, nullptr));
}

std::string Hex(Color c) {
  return std::to_string(c.r) + "," + std::to_string(c.g) + "," + std::to_string(c.b);
}

void ExpectNear(Color actual, Color expected, int tolerance, const std::string& where) {
  EXPECT_NEAR(actual.r, expected.r, tolerance)
      << where << ": " << Hex(actual) << " vs " << Hex(expected);
  EXPECT_NEAR(actual.g, expected.g, tolerance)
      << where << ": " << Hex(actual) << " vs " << Hex(expected);
  EXPECT_NEAR(actual.b, expected.b, tolerance)
      << where << ": " << Hex(actual) << " vs " << Hex(expected);
}

class Rendering : public ::testing::Test {
 protected:
  // Rendering needs no display: prove it by having none.
  void SetUp() override { unsetenv("DISPLAY"); }
  void TearDown() override { fs::remove_all(dir_); }

  // Loads `xml`, points its renderers at a fresh folder and draws tick 0.
  std::unique_ptr<Simulation> Render(const std::string& xml) {
    auto sim = LoadXml(xml);
    for (const auto& r : sim->renderers()) {
      r->set_output_dir(dir_.string());
      r->AfterTick();
    }
    return sim;
  }

  const fs::path dir_ =
      fs::temp_directory_path() / ("colony_render_test_" + std::to_string(getpid()));
};

TEST_F(Rendering, WritesFramesOfTheRequestedSizeEveryKTicks) {
  auto sim = LoadXml(
      Experiment(Robot("r", "0,0,0"), kRedRobots, "4,4,1",
                 Visualization("width=\"320\" height=\"240\" every=\"3\"", TopCamera("0,0"))));
  ASSERT_EQ(sim->renderers().size(), 1u);
  sim->renderers()[0]->set_output_dir(dir_.string());
  RunToEnd(*sim, nullptr, 0, {});  // 100 ticks: frames of ticks 0, 3, ..., 99
  for (int k = 0; k < 34; ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "top_%06d.png", k);
    const Png png = ReadPng(dir_ / name);
    EXPECT_EQ(png.width, 320) << name;
    EXPECT_EQ(png.height, 240) << name;
  }
  EXPECT_FALSE(fs::exists(dir_ / "top_000034.png"));
  const auto series = sim->renderers()[0]->frame_series();
  ASSERT_EQ(series.size(), 1u);
  EXPECT_EQ(series[0].camera, "top");
  EXPECT_EQ(series[0].pattern, (dir_ / "top_%06d.png").string());
  EXPECT_EQ(series[0].frames, 34u);
  EXPECT_DOUBLE_EQ(series[0].frames_per_second, 10.0 / 3);
}

TEST_F(Rendering, RedLitMarxbotSeenFromAboveIsRedAtItsCentreOnTheFloorColour) {
  const Color floor{40, 90, 200, 255};
  Render(Experiment(
      "<floor color=\"" + Hex(floor) + "\"/>" + Robot("r", "0.5,-0.3,0"), kRedRobots, "4,4,1",
      Visualization("width=\"200\" height=\"200\" grid=\"0\"", TopCamera("0.5,-0.3"))));
  const Png png = ReadPng(dir_ / "top_000000.png");
  ASSERT_EQ(png.width, 200);
  // The beacon at the centre, the LED ring around it (0.07 m out: 14 pixels).
  for (const auto& [x, y] : {std::pair{100, 100}, {114, 100}, {100, 86}, {86, 100}}) {
    const Color c = png.At(x, y);
    EXPECT_GT(c.r, 200) << x << "," << y << ": " << Hex(c);
    EXPECT_LT(c.g, 50) << x << "," << y << ": " << Hex(c);
    EXPECT_LT(c.b, 50) << x << "," << y << ": " << Hex(c);
  }
  // Everywhere away from the robot (over 0.1 m = 17 pixels off): the floor, exactly.
  for (const auto& [x, y] :
       {std::pair{5, 5}, {194, 5}, {5, 194}, {194, 194}, {100, 125}, {130, 100}}) {
    ExpectNear(png.At(x, y), floor, 1, std::to_string(x) + "," + std::to_string(y));
  }
}

TEST_F(Rendering, FloorImageIsDrawnTheWayGroundSensorsReadIt) {
  fs::create_directories(dir_);
  const Color north{220, 30, 30, 255}, south{30, 30, 220, 255};
  WriteTwoColourPng(dir_ / "floor.png", north, south);
  Render(Experiment("<floor source=\"image\" path=\"" + (dir_ / "floor.png").string() + "\"/>", "",
                    "2,2,1",
                    Visualization("width=\"200\" height=\"200\" grid=\"0\"", TopCamera("0,0"))));
  const Png png = ReadPng(dir_ / "top_000000.png");
  ExpectNear(png.At(100, 40), north, 2, "north half");
  ExpectNear(png.At(100, 160), south, 2, "south half");
}

TEST_F(Rendering, GridIsFaintAndCanBeTurnedOff) {
  const std::string arena = "<floor color=\"white\"/>";
  // 1 m grid: the lines x = 0 and y = 0 cross under the camera.
  Render(Experiment(arena, "", "4,4,1",
                    Visualization("width=\"201\" height=\"201\"", TopCamera("0,0"))));
  const Color line = ReadPng(dir_ / "top_000000.png").At(100, 100);
  EXPECT_LT(line.r, 250);
  EXPECT_GT(line.r, 150);  // faint, not black
  Render(Experiment(arena, "", "4,4,1",
                    Visualization("width=\"201\" height=\"201\" grid=\"0\"", TopCamera("0,0"))));
  ExpectNear(ReadPng(dir_ / "top_000000.png").At(100, 100), Color::White(), 0, "no grid");
}

TEST_F(Rendering, MeshFileLoadsAndReplacesTheEntitysShape) {
  // A 0.4 m box dressed as a 0.2 m orange pyramid: orange at the apex, floor
  // where only the box would have been.
  const Color floor{40, 90, 200, 255};
  const std::string mesh = COLONY_SOURCE_DIR "/experiments/meshes/pyramid.obj";
  Render(Experiment("<floor color=\"" + Hex(floor) +
                        "\"/><box id=\"b\" size=\"0.4,0.4,0.2\"><body position=\"0,0,0\"/></box>",
                    "", "4,4,1",
                    Visualization("width=\"200\" height=\"200\" grid=\"0\"",
                                  TopCamera("0,0") + "<mesh entity=\"b\" file=\"" + mesh +
                                      "\" scale=\"0.2\"/>")));
  const Png png = ReadPng(dir_ / "top_000000.png");
  for (const auto& [x, y] : {std::pair{100, 100}, {100, 93}, {107, 100}}) {
    const Color c = png.At(x, y);
    EXPECT_GT(c.r, 100) << x << "," << y << ": " << Hex(c);
    EXPECT_GT(c.r, c.g + 40) << x << "," << y << ": " << Hex(c);
    EXPECT_LT(c.b, 30) << x << "," << y << ": " << Hex(c);
  }
  ExpectNear(png.At(126, 100), floor, 1, "inside the box, outside the pyramid");
}

TEST_F(Rendering, MeshByTypeDressesEveryEntityOfThatTypeInItsColour) {
  const std::string mesh = COLONY_SOURCE_DIR "/experiments/meshes/pyramid.obj";
  const std::string cylinders =
      "<cylinder id=\"c1\" radius=\"0.1\" height=\"0.1\"><body position=\"-0.5,0,0\"/></cylinder>"
      "<cylinder id=\"c2\" radius=\"0.1\" height=\"0.1\"><body position=\"0.5,0,0\"/></cylinder>";
  Render(Experiment(cylinders, "", "4,4,1",
                    Visualization("width=\"200\" height=\"200\" grid=\"0\"",
                                  TopCamera("0,0") + "<mesh type=\"cylinder\" file=\"" + mesh +
                                      "\" scale=\"0.2\" color=\"green\"/>")));
  const Png png = ReadPng(dir_ / "top_000000.png");
  for (int x : {100 - 87, 100 + 87}) {
    const Color c = png.At(x, 100);
    EXPECT_GT(c.g, 60) << x << ": " << Hex(c);
    EXPECT_LT(c.r, 20) << x << ": " << Hex(c);
  }
}

TEST_F(Rendering, OverlaysAreDrawnOnlyWhenSwitchedOn) {
  // A robot beside a box: its proximity rays hit the box; its id is written above it.
  const std::string arena =
      "<floor color=\"gray50\"/>" + Robot("r7", "0,0,0") +
      "<box id=\"b\" size=\"0.1,0.6,0.3\"><body position=\"0.16,0,0\"/></box>";
  auto count = [](const Png& png, auto predicate) {
    int n = 0;
    for (int y = 0; y < png.height; ++y)
      for (int x = 0; x < png.width; ++x) n += predicate(png.At(x, y));
    return n;
  };
  auto white = [](Color c) { return c.r > 240 && c.g > 240 && c.b > 240; };
  auto purple = [](Color c) { return c.r > 150 && c.b > 90 && c.g < 90; };
  auto cyan = [](Color c) { return c.b > 150 && c.g > 130 && c.r < 110; };
  const std::string camera =
      "<camera id=\"top\" position=\"0,-0.3,1\" look_at=\"0,0,0\" fov=\"40\"/>";
  Render(Experiment(arena, kRedRobots, "4,4,1",
                    Visualization("width=\"300\" height=\"300\"", camera)));
  const Png plain = ReadPng(dir_ / "top_000000.png");
  Render(Experiment(
      arena, kRedRobots, "4,4,1",
      Visualization("width=\"300\" height=\"300\" ids=\"true\" proximity_rays=\"true\"", camera)));
  const Png overlaid = ReadPng(dir_ / "top_000000.png");
  EXPECT_EQ(count(plain, white), 0);
  EXPECT_GT(count(overlaid, white), 10);
  EXPECT_EQ(count(plain, purple), 0);
  EXPECT_GT(count(overlaid, purple), 10);  // rays that hit the box
  EXPECT_GT(count(overlaid, cyan), 10);    // rays that see nothing
}

TEST_F(Rendering, TrailsFollowTheRobots) {
  // A robot driven straight along +x leaves a blue line on the floor behind it.
  const std::string controllers =
      "<diffusion id=\"dc\" library=\"diffusion\"><actuators><differential_steering/></actuators>"
      "<sensors><proximity/></sensors><params alpha=\"7.5\" delta=\"0.1\" "
      "velocity=\"0.2\"/></diffusion>";
  auto sim = LoadXml(Experiment(
      "<floor color=\"white\"/>" + Robot("r", "-0.5,0,0", "dc"), controllers, "4,4,1",
      Visualization("width=\"200\" height=\"200\" grid=\"0\" every=\"20\" trails=\"true\"",
                    TopCamera("0,0"))));
  sim->renderers()[0]->set_output_dir(dir_.string());
  RunToEnd(*sim, nullptr, 0, {});
  const Png png = ReadPng(dir_ / "top_000001.png");  // tick 20: the robot is at x = -0.1
  const Color behind = png.At(100 - 60, 100);        // x = -0.35
  EXPECT_GT(behind.b, behind.r + 30) << Hex(behind);
  ExpectNear(png.At(100 - 60, 130), Color::White(), 0, "beside the trail");
}

// Draws a yellow disc of radius 0.3 m at the origin, a magenta segment along
// y = 0.4, a cyan point at (0, -0.4) and "hi" above (-0.3, -0.2); counts
// the calls, and reads the space to place a green point on every robot.
class DrawingLoop : public LoopFunctions {
 public:
  static inline int draws = 0;
  void Draw(DrawList& list) const override {
    ++draws;
    list.AddCircle(Vec3(0, 0, 0), 0.3, Color{255, 200, 0, 255}, true);
    list.AddSegment(Vec3(-0.5, 0.4, 0), Vec3(0.5, 0.4, 0), Color{255, 0, 255, 255});
    list.AddPoint(Vec3(0, -0.4, 0), Color{0, 255, 255, 255}, 8);
    list.AddText(Vec3(-0.3, -0.2, 0), "hi");
    const Space& space = sim().space();
    for (uint32_t i = 0; i < space.slots(); ++i) {
      if (space.alive(i) && (space.flags(i) & kRobot))
        list.AddPoint(space.pose(i).position, Color{0, 255, 0, 255}, 4);
    }
  }
};
COLONY_REGISTER_LOOP_FUNCTIONS(DrawingLoop, "render_test_drawing",
                               "test: draws a disc, a segment, a point and text", {});

const std::string kDrawingLoop = "<loop_functions label=\"render_test_drawing\"/>";

TEST_F(Rendering, WhatLoopFunctionsDrawIsInTheFrameWhereTheyDrewIt) {
  const Color floor{40, 90, 200, 255};
  DrawingLoop::draws = 0;
  Render(Experiment(
      "<floor color=\"" + Hex(floor) + "\"/>", "", "4,4,1",
      kDrawingLoop + Visualization("width=\"200\" height=\"200\" grid=\"0\"", TopCamera("0,0"))));
  EXPECT_EQ(DrawingLoop::draws, 1);
  const Png png = ReadPng(dir_ / "top_000000.png");
  // 1 m below a 60-degree camera, 200 pixels span 1.155 m: 173 pixels a metre.
  auto px = [](double metres) { return static_cast<int>(std::lround(173.2 * metres)); };
  // The disc: yellow 0.15 and 0.25 m from its centre, the floor 0.35 m out.
  for (const auto& [x, y] :
       {std::pair{100 + px(0.15), 100}, {100, 100 - px(0.25)}, {100 - px(0.2), 100 + px(0.1)}}) {
    ExpectNear(png.At(x, y), Color{255, 200, 0, 255}, 2,
               std::to_string(x) + "," + std::to_string(y));
  }
  ExpectNear(png.At(100 + px(0.35), 100), floor, 1, "outside the disc");
  // The segment along y = 0.4 (row 31), two pixels wide.
  int magenta = 0;
  for (int y = 100 - px(0.4) - 2; y <= 100 - px(0.4) + 2; ++y) {
    const Color c = png.At(100 - px(0.45), y);
    magenta += c.r > 200 && c.g < 60 && c.b > 200;
  }
  EXPECT_GE(magenta, 1) << "no magenta across y = 0.4";
  ExpectNear(png.At(100, 100 - px(0.4) - 8), floor, 1, "beside the segment");
  // The point: an 8-pixel cyan square at (0, -0.4).
  ExpectNear(png.At(100, 100 + px(0.4)), Color{0, 255, 255, 255}, 0, "the point");
  ExpectNear(png.At(100 + 8, 100 + px(0.4)), floor, 1, "beside the point");
  // The text: white pixels just above (-0.3, -0.2), none elsewhere.
  int white_near = 0, white = 0;
  for (int y = 0; y < png.height; ++y) {
    for (int x = 0; x < png.width; ++x) {
      const Color c = png.At(x, y);
      if (c.r < 240 || c.g < 240 || c.b < 240) continue;
      ++white;
      white_near +=
          std::abs(x - (100 - px(0.3))) < 12 && y < 100 + px(0.2) && y > 100 + px(0.2) - 14;
    }
  }
  EXPECT_GT(white_near, 10);
  EXPECT_EQ(white_near, white);
}

TEST_F(Rendering, LoopFunctionsDrawOnlyForFramesAndDrawingChangesNoResults) {
  const std::string controllers =
      "<diffusion id=\"dc\" library=\"diffusion\"><actuators><differential_steering/>"
      "</actuators><sensors><proximity/></sensors><params alpha=\"7.5\" delta=\"0.1\" "
      "velocity=\"0.1\"/></diffusion>";
  const std::string arena =
      "<distribute><position method=\"uniform\" min=\"-1.5,-1.5,0\" max=\"1.5,1.5,0\"/>"
      "<orientation method=\"uniform\" min=\"0,0,0\" max=\"360,0,0\"/><entity "
      "quantity=\"20\"><marxbot id=\"mb\"><controller config=\"dc\"/></marxbot></entity>"
      "</distribute>";
  auto run = [&](const std::string& visualization) {
    auto sim = LoadXml(Experiment(arena, controllers, "4,4,1", kDrawingLoop + visualization));
    for (const auto& r : sim->renderers()) r->set_output_dir(dir_.string());
    return RunToEnd(*sim, nullptr, 0, {}).final_state_hash;
  };
  DrawingLoop::draws = 0;
  const uint64_t plain = run("");
  EXPECT_EQ(DrawingLoop::draws, 0) << "nothing showed the drawing, so nothing asked for it";
  const uint64_t drawn =
      run(Visualization("width=\"160\" height=\"120\" every=\"5\"", TopCamera("0,0")));
  EXPECT_EQ(DrawingLoop::draws, 21);  // ticks 0, 5, ..., 100
  EXPECT_EQ(drawn, plain);
}

TEST_F(Rendering, DefaultCameraSeesTheWholeArena) {
  const Color floor{40, 90, 200, 255};
  auto sim = LoadXml(Experiment("<floor color=\"" + Hex(floor) + "\"/>", "", "6,3,1"));
  Renderer& r =
      sim->AddRenderer("<osmesa width=\"320\" height=\"180\" grid=\"0\" background=\"black\"/>");
  r.set_output_dir(dir_.string());
  r.AfterTick();
  const Png png = ReadPng(dir_ / "camera0_000000.png");
  ASSERT_EQ(png.width, 320);
  ExpectNear(png.At(160, 90), floor, 1, "centre");
  // Background all around the edges: the floor fits inside.
  for (int x = 0; x < 320; ++x) {
    ExpectNear(png.At(x, 0), Color::Black(), 0, "top edge");
    ExpectNear(png.At(x, 179), Color::Black(), 0, "bottom edge");
  }
  for (int y = 0; y < 180; ++y) {
    ExpectNear(png.At(0, y), Color::Black(), 0, "left edge");
    ExpectNear(png.At(319, y), Color::Black(), 0, "right edge");
  }
}

TEST_F(Rendering, FollowCameraMovesWithItsEntity) {
  // A chase camera behind a robot sees it at the image centre wherever it is.
  const std::string camera =
      "<camera id=\"chase\" follow=\"r\" position=\"-0.6,0,0.4\" look_at=\"0,0,0.1\" fov=\"50\"/>";
  for (const std::string position : {"-1,1,0", "1,-0.5,0"}) {
    Render(Experiment("<floor color=\"white\"/>" + Robot("r", position), kRedRobots, "4,4,1",
                      Visualization("width=\"160\" height=\"120\" grid=\"0\"", camera)));
    const Color c = ReadPng(dir_ / "chase_000000.png").At(80, 60);
    EXPECT_LT(c.g, 200) << position << ": " << Hex(c);  // the robot, not the white floor
  }
}

TEST_F(Rendering, RenderingDoesNotChangeTheResults) {
  const std::string controllers =
      "<diffusion id=\"dc\" library=\"diffusion\"><actuators><differential_steering/><leds "
      "color=\"green\"/>"
      "</actuators><sensors><proximity/></sensors><params alpha=\"7.5\" delta=\"0.1\" "
      "velocity=\"0.1\"/></diffusion>";
  const std::string arena =
      "<walls thickness=\"0.1\" height=\"0.3\"/><distribute><position method=\"uniform\" "
      "min=\"-1.5,-1.5,0\" "
      "max=\"1.5,1.5,0\"/><orientation method=\"uniform\" min=\"0,0,0\" max=\"360,0,0\"/><entity "
      "quantity=\"30\">"
      "<marxbot id=\"mb\"><controller config=\"dc\"/></marxbot></entity></distribute>";
  auto run = [&](const std::string& visualization, int threads) {
    auto sim = LoadXml(Experiment(arena, controllers, "4,4,1", visualization), {}, threads);
    for (const auto& r : sim->renderers()) r->set_output_dir(dir_.string());
    return RunToEnd(*sim, nullptr, 0, {}).final_state_hash;
  };
  const std::string frames = Visualization(
      "width=\"320\" height=\"240\" every=\"7\" ids=\"true\" trails=\"true\" "
      "proximity_rays=\"true\"",
      TopCamera("0,0") +
          "<camera id=\"chase\" follow=\"mb3\" "
          "position=\"-0.5,0,0.3\" look_at=\"0,0,0\"/>");
  const uint64_t plain = run("", 0);
  EXPECT_EQ(run(frames, 0), plain);
  EXPECT_EQ(run(frames, 3), plain);
  EXPECT_TRUE(fs::exists(dir_ / "chase_000014.png"));
}

// The image renderer seen through its interface: two robots under a camera
// looking straight down; the one it is told to hide is not drawn, the other is.
TEST(ImageRenderer, DrawsWhatTheCameraSeesExceptTheHiddenEntity) {
  unsetenv("DISPLAY");
  ASSERT_TRUE(HaveImageRenderer());
  auto sim =
      LoadXml(Experiment(Robot("below", "0,0,0") + Robot("beside", "0.15,0.15,0"), kRedRobots));
  sim->Step();
  CameraView view;
  view.position = Vec3(0, 0, 1);
  view.orientation = FromEulerZYX(0, DegToRad(90), 0);  // x (the optical axis) down
  view.fov = 40;
  view.far_clip = 2;
  view.width = 80;
  view.height = 60;
  const auto renderer = MakeImageRenderer(*sim);
  auto draw = [&](EntityHandle hidden) {
    view.hidden = hidden;
    std::vector<uint8_t> rgb;
    renderer->Render(view, rgb);
    EXPECT_EQ(rgb.size(), 80u * 60 * 3);
    return rgb;
  };
  auto not_floor = [](const std::vector<uint8_t>& rgb) {  // the floor is white
    int n = 0;
    for (size_t k = 0; k + 2 < rgb.size(); k += 3) n += rgb[k] + rgb[k + 1] + rgb[k + 2] < 3 * 255;
    return n;
  };
  auto centre = [](const std::vector<uint8_t>& rgb) {
    const uint8_t* p = rgb.data() + (30 * 80 + 40) * 3;
    return Color{p[0], p[1], p[2], 255};
  };
  const auto both = draw({});
  const auto without_below = draw(sim->space().Find("below"));
  EXPECT_NE(centre(both), Color::White());
  EXPECT_EQ(centre(without_below), Color::White());
  EXPECT_GT(not_floor(without_below), 100);  // the robot beside is still drawn
  EXPECT_LT(not_floor(without_below), not_floor(both) - 100);
  EXPECT_EQ(draw({}), both);  // the same image again
}

// The hand-bot hanging on its rope, seen from the side: the hull where the
// robot is, the rope above it up to the ceiling; and a marXbot's
// construction manipulator, seen from above, in front of its body.
bool HaveDynamics3d() { return Registry<PhysicsEngine>::Get().Find("dynamics3d") != nullptr; }

TEST(ImageRenderer, DrawsTheHandBotOnItsRopeAndTheMarxbotsManipulator) {
  if (!HaveDynamics3d()) GTEST_SKIP() << "the hand-bot and the manipulator need dynamics3d";
  unsetenv("DISPLAY");
  ASSERT_TRUE(HaveImageRenderer());
  auto sim = LoadXml(Experiment(
      "<ceiling height=\"2.5\"/><handbot id=\"h\" color=\"red\"><body position=\"0,0,0\"/>"
      "<controller config=\"red\"/></handbot><marxbot id=\"m\" manipulator=\"true\" color=\"blue\">"
      "<body position=\"1,1,0\"/><controller config=\"red\"/></marxbot><marxbot id=\"p\" "
      "color=\"blue\">"
      "<body position=\"1,-1,0\"/><controller config=\"red\"/></marxbot>",
      kRedRobots, "4,4,3", "", "<dynamics3d id=\"d3d\" stepper=\"worldstep\"/>"));
  Space& space = sim->space();
  RopeState& rope = *space.Get<RopeState>(space.Find("h").index);
  rope.want_launch = true;
  sim->Step();
  ASSERT_TRUE(rope.attached());
  rope.climb_speed = 0.1;
  for (int t = 0; t < 50; ++t) sim->Step();
  ASSERT_NEAR(space.pose(space.Find("h").index).position.z(), 0.5, 0.02);
  const auto renderer = MakeImageRenderer(*sim);
  // From 2 m away on -y, level with the middle of the hull (0.5 + 0.1 m up),
  // looking along +y; 320 x 240 pixels over 40 degrees.
  CameraView side;
  side.position = Vec3(0, -2, 0.6);
  side.orientation = FromEulerZYX(DegToRad(90), 0, 0);  // x (the optical axis) along +y
  side.fov = 40;
  side.far_clip = 10;
  side.width = 320;
  side.height = 240;
  auto draw = [&](CameraView view, EntityHandle hidden) {
    view.hidden = hidden;
    std::vector<uint8_t> rgb;
    renderer->Render(view, rgb);
    return rgb;
  };
  auto at = [](const std::vector<uint8_t>& rgb, int width, int x, int y) {
    const uint8_t* p = rgb.data() + (static_cast<size_t>(y) * width + x) * 3;
    return Color{p[0], p[1], p[2], 255};
  };
  const auto with = draw(side, {}), without = draw(side, space.Find("h"));
  const Color hull = at(with, 320, 160, 120);
  EXPECT_GT(hull.r, 2 * hull.g) << "the red hull at the image's centre: " << Hex(hull);
  EXPECT_NE(at(without, 320, 160, 120), hull);
  // The rope: above the robot, the centre column differs with and without
  // the hand-bot in most rows up to the top of the image.
  int rope_rows = 0;
  for (int y = 0; y < 60; ++y) {
    bool differs = false;
    for (int x = 157; x <= 163; ++x)
      differs = differs || at(with, 320, x, y) != at(without, 320, x, y);
    rope_rows += differs;
  }
  EXPECT_GT(rope_rows, 50) << "the rope runs up out of the image";
  // The manipulator, from 1 m above: the marXbot with it covers more of the
  // floor than the same marXbot without it, all of it ahead of the robot
  // (+x: the top half of this view, whose rows run along -x).
  CameraView top;
  top.orientation = FromEulerZYX(0, DegToRad(90), 0);  // x (the optical axis) down
  top.fov = 40;
  top.far_clip = 2;
  top.width = 160;
  top.height = 120;
  struct Halves {
    int ahead = 0, behind = 0;
  };
  auto covered = [&](const char* id, const Vec3& above) {
    top.position = above;
    const auto robot = draw(top, {}), floor = draw(top, space.Find(id));
    Halves h;
    for (int y = 0; y < 120; ++y) {
      for (int x = 0; x < 160; ++x) {
        if (at(robot, 160, x, y) == at(floor, 160, x, y)) continue;
        (y < 60 ? h.ahead : h.behind)++;
      }
    }
    return h;
  };
  const Halves with_head = covered("m", Vec3(1, 1, 1)), plain = covered("p", Vec3(1, -1, 1));
  EXPECT_GT(with_head.ahead, plain.ahead + 10) << "the head in front of the body";
  EXPECT_NEAR(with_head.behind, plain.behind, 3) << "nothing more behind";
}

// A camera on a hand-bot's gripper looks out of its claws, wherever the arm
// puts it: straight ahead at a red box with the arm extended, sideways
// with it folded.
TEST(ImageRenderer, ACameraOnAGripperLooksWhereTheGripperPoints) {
  if (!HaveDynamics3d()) GTEST_SKIP() << "the hand-bot needs dynamics3d";
  unsetenv("DISPLAY");
  auto sim = LoadXml(
      "<colony><framework><experiment length=\"10\" "
      "ticks_per_second=\"10\"/></framework><controllers>"
      "<led_holder id=\"c\"><sensors><camera anchor=\"gripper_left\" width=\"32\" height=\"24\" "
      "fov=\"40\"/>"
      "</sensors></led_holder></controllers><arena size=\"4,4,2\" center=\"0,0,1\"><handbot "
      "id=\"h\">"
      "<body position=\"0,0,0\"/><controller config=\"c\"/></handbot><box id=\"target\" "
      "size=\"0.2,0.4,0.4\" "
      "color=\"red\"><body position=\"1,0.06,0\"/></box></arena><physics_engines><dynamics3d "
      "id=\"d3d\" "
      "stepper=\"worldstep\"/></physics_engines></colony>");
  const auto& camera = dynamic_cast<LedHolder&>(*sim->ControllerOf(sim->space().Find("h")))
                           .GetSensor<CameraSensor>("camera");
  auto centre = [&] {
    const uint8_t* p = camera.rgb().data() + (12 * 32 + 16) * 3;
    return Color{p[0], p[1], p[2], 255};
  };
  sim->Step();
  EXPECT_FALSE(centre().r > 150 && centre().g < 80)
      << "folded, the gripper looks sideways: " << Hex(centre());
  auto& arms = *sim->space().Get<HandbotArmsState>(sim->space().Find("h").index);
  arms.arm[0].target = M_PI / 2;
  for (int t = 0; t < 20; ++t) sim->Step();
  ASSERT_NEAR(arms.arm[0].position, M_PI / 2, 0.02);
  EXPECT_GT(centre().r, 150) << "straight ahead, the red box: " << Hex(centre());
  EXPECT_LT(centre().g, 80);
  // An anchor the robot does not have is refused at load.
  EXPECT_TRUE(testing::Mentions(
      LoadError(
          "<colony><framework><experiment length=\"10\" "
          "ticks_per_second=\"10\"/></framework><controllers>"
          "<led_holder id=\"c\"><sensors><camera "
          "anchor=\"elbow\"/></sensors></led_holder></controllers>"
          "<arena size=\"4,4,2\" center=\"0,0,1\"><handbot id=\"h\"><body position=\"0,0,0\"/>"
          "<controller config=\"c\"/></handbot></arena><physics_engines><dynamics3d id=\"d3d\"/>"
          "</physics_engines></colony>"),
      {"<camera>", "'h'", "no 'elbow' anchor"}));
}

// A bad setting names the file, line, element and attribute.
std::string Bad(const std::string& osmesa_attributes, const std::string& children) {
  return LoadError(Experiment(Robot("r", "0,0,0"), kRedRobots, "4,4,1",
                              Visualization(osmesa_attributes, children)));
}

// --- the eye-bot, its laser spot and a camera on its pan-tilt head

bool HavePointmass3d() { return Registry<PhysicsEngine>::Get().Find("pointmass3d") != nullptr; }

// An eye-bot "e" (configuration "c") hanging from a ceiling at 2.5 m above
// the origin, its head at 2.26 m, facing +x; `arena` around it; the floor at 0.
std::string EyebotWorld(const std::string& arena, const std::string& controllers,
                        const std::string& extra = "") {
  return "<colony><framework><experiment length=\"10\" ticks_per_second=\"10\"/></framework>"
         "<controllers>" +
         controllers +
         "</controllers><arena size=\"8,8,3\" center=\"0,0,1.5\"><ceiling height=\"2.5\"/>"
         "<eyebot id=\"e\" attached=\"true\"><body position=\"0,0,2.2\"/><controller "
         "config=\"c\"/></eyebot>" +
         arena +
         "</arena><physics_engines><kinematics2d id=\"ground\"/><pointmass3d id=\"air\" "
         "entities=\"eyebot\"/></physics_engines>" +
         extra + "</colony>";
}

TEST_F(Rendering, TheLaserSpotIsRedWhereTheBeamMeetsTheFloorOrABoxAndTheBeamLeadsToIt) {
  if (!HavePointmass3d()) GTEST_SKIP() << "the eye-bot needs pointmass3d";
  const Color floor{40, 90, 200, 255};
  const double tilt = DegToRad(30), head = 2.26;
  // From 1 m above the floor 1.3 m out on +x, looking straight down.
  render::View top;
  top.eye = Vec3(1.3, 0, 1);
  top.target = Vec3(1.3, 0, 0);
  top.up = Vec3(0, 1, 0);
  top.width = top.height = 200;
  const Vec3 beam(std::sin(tilt), 0, -std::cos(tilt));
  for (const double box_top : {0.0, 0.3}) {
    SCOPED_TRACE(box_top > 0 ? "on the box" : "on the floor");
    fs::remove_all(dir_);
    const std::string box =
        box_top > 0 ? "<box id=\"b\" size=\"0.5,0.5,0.3\"><body position=\"1.3,0,0\"/></box>" : "";
    auto sim = LoadXml(
        EyebotWorld("<floor color=\"" + Hex(floor) + "\"/>" + box, "<led_holder id=\"c\"/>",
                    Visualization("width=\"200\" height=\"200\" grid=\"0\"", TopCamera("1.3,0"))));
    PanTiltState& unit = *sim->space().Get<PanTiltState>(sim->space().Find("e").index);
    unit.tilt = unit.target_tilt = tilt;
    unit.laser_on = true;
    sim->renderers()[0]->set_output_dir(dir_.string());
    sim->renderers()[0]->AfterTick();
    const Png png = ReadPng(dir_ / "top_000000.png");
    ASSERT_EQ(png.width, 200);
    const Vec3 spot = Vec3(0, 0, head) + (head - box_top) / std::cos(tilt) * beam;
    const Vec2 at = *top.ToPixel(spot);
    ASSERT_TRUE(at.x() >= 0 && at.x() < 200 && at.y() >= 0 && at.y() < 190) << at.transpose();
    const Color c = png.At(static_cast<int>(at.x()), static_cast<int>(at.y()));
    EXPECT_GT(c.r, 200) << Hex(c) << " at " << at.transpose();
    EXPECT_LT(c.g, 60) << Hex(c);
    EXPECT_LT(c.b, 60) << Hex(c);
    // 1.5 cm in radius (2.6 pixels from 1 m, or 1.9 from 0.7 m): 8 pixels
    // beside it, the surface.
    const Color beside = png.At(static_cast<int>(at.x()), static_cast<int>(at.y()) + 8);
    EXPECT_LT(beside.r, 180) << Hex(beside);
    // The beam, 0.2 m above the spot: a red line.
    const Vec2 up = *top.ToPixel(spot - 0.2 / std::cos(tilt) * beam);
    ASSERT_TRUE(up.x() >= 0 && up.x() < 200 && up.y() >= 1 && up.y() < 199) << up.transpose();
    int red = 0;
    for (int dy = -1; dy <= 1; ++dy) {
      const Color b = png.At(static_cast<int>(up.x()), static_cast<int>(up.y()) + dy);
      red += b.r > b.g + 60;
    }
    EXPECT_GE(red, 1) << "the beam passes " << up.transpose();
    // Off: no spot.
    unit.laser_on = false;
    sim->renderers()[0]->AfterTick();
    const Color off =
        ReadPng(dir_ / "top_000001.png").At(static_cast<int>(at.x()), static_cast<int>(at.y()));
    EXPECT_LT(off.r, 180) << Hex(off);
  }
}

// A camera on the head (anchor "pan_tilt") sees what the head points at:
// straight down a red box under the robot, straight ahead a green wall,
// turned round nothing.
TEST(ImageRenderer, ACameraOnTheEyebotsHeadLooksWhereTheHeadPoints) {
  if (!HavePointmass3d()) GTEST_SKIP() << "the eye-bot needs pointmass3d";
  unsetenv("DISPLAY");
  auto sim = LoadXml(EyebotWorld(
      "<box id=\"under\" size=\"0.6,0.6,0.2\" color=\"red\"><body position=\"0,0,0\"/></box>"
      "<box id=\"ahead\" size=\"0.2,1.5,2.45\" color=\"green\"><body position=\"1.5,0,0\"/></box>",
      "<led_holder id=\"c\"><sensors><camera anchor=\"pan_tilt\" position=\"0.03,0,0\" "
      "width=\"32\" height=\"24\" fov=\"40\"/></sensors></led_holder>"));
  const auto& camera = dynamic_cast<LedHolder&>(*sim->ControllerOf(sim->space().Find("e")))
                           .GetSensor<CameraSensor>("camera");
  PanTiltState& unit = *sim->space().Get<PanTiltState>(sim->space().Find("e").index);
  sim->Step();
  Color c = camera.At(16, 12);
  EXPECT_GT(c.r, 120) << "straight down, the red box: " << Hex(c);
  EXPECT_LT(c.g, 60) << Hex(c);
  unit.tilt = M_PI / 2;
  sim->Step();
  c = camera.At(16, 12);
  EXPECT_GT(c.g, 120) << "ahead, the green wall: " << Hex(c);
  EXPECT_LT(c.r, 60) << Hex(c);
  unit.pan = M_PI;
  sim->Step();
  c = camera.At(16, 12);
  EXPECT_FALSE(c.g > 120 || c.r > 120) << "behind, nothing: " << Hex(c);
}

TEST(RenderingErrors, BadCamerasAreRejectedWithElementAndLine) {
  const std::string zero_fov =
      Bad("", "<camera id=\"c\" position=\"0,0,1\" look_at=\"0,0,0\" fov=\"0\"/>");
  EXPECT_NE(zero_fov.find("<string>:4: <camera id=\"c\"> attribute 'fov'"), std::string::npos)
      << zero_fov;
  EXPECT_NE(zero_fov.find("(0, 179]"), std::string::npos) << zero_fov;
  const std::string nowhere = Bad("", "<camera id=\"c\" position=\"1,2,3\" look_at=\"1,2,3\"/>");
  EXPECT_NE(nowhere.find("<string>:4: <camera id=\"c\"> attribute 'look_at'"), std::string::npos)
      << nowhere;
  EXPECT_NE(nowhere.find("looks nowhere"), std::string::npos) << nowhere;
  const std::string up = Bad("", "<camera position=\"0,0,1\" look_at=\"0,0,0\" up=\"0,0,1\"/>");
  EXPECT_NE(up.find("attribute 'up'"), std::string::npos) << up;
  const std::string missing = Bad("", "<camera id=\"c\" look_at=\"0,0,0\"/>");
  EXPECT_NE(missing.find("attribute 'position'"), std::string::npos) << missing;
  const std::string twice =
      Bad("",
          "<camera id=\"c\" position=\"0,0,1\" look_at=\"0,1,0\"/>\n<camera id=\"c\" "
          "position=\"0,0,2\" look_at=\"0,1,0\"/>");
  EXPECT_NE(twice.find("<string>:5: <camera id=\"c\"> attribute 'id'"), std::string::npos) << twice;
  EXPECT_NE(twice.find("already used at line 4"), std::string::npos) << twice;
}

TEST(RenderingErrors, UnreadableMeshFilesAreRejectedWithElementAndLine) {
  const std::string absent = Bad("", "<mesh type=\"marxbot\" file=\"/no/such/robot.obj\"/>");
  EXPECT_NE(absent.find("<string>:4: <mesh> attribute 'file'"), std::string::npos) << absent;
  EXPECT_NE(absent.find("cannot read mesh file '/no/such/robot.obj'"), std::string::npos) << absent;
  const std::string not_a_mesh =
      Bad("", "<mesh type=\"marxbot\" file=\"" COLONY_SOURCE_DIR "/README.md\"/>");
  EXPECT_NE(not_a_mesh.find("attribute 'file'"), std::string::npos) << not_a_mesh;
  const std::string type = Bad(
      "", "<mesh type=\"marxbox\" file=\"" COLONY_SOURCE_DIR "/experiments/meshes/pyramid.obj\"/>");
  EXPECT_NE(type.find("attribute 'type'"), std::string::npos) << type;
  EXPECT_NE(type.find("marxbot"), std::string::npos) << type;
  const std::string both = Bad("", "<mesh type=\"box\" entity=\"b\" file=\"x.obj\"/>");
  EXPECT_NE(both.find("exactly one of type"), std::string::npos) << both;
}

TEST(RenderingErrors, BadRendererSettingsAreRejected) {
  const std::string typo = Bad("widht=\"640\"", "");
  EXPECT_NE(typo.find("did you mean 'width'"), std::string::npos) << typo;
  const std::string every = Bad("every=\"0\"", "");
  EXPECT_NE(every.find("attribute 'every'"), std::string::npos) << every;
  const std::string huge = Bad("width=\"4000\" antialias=\"4\"", "");
  EXPECT_NE(huge.find("attribute 'antialias'"), std::string::npos) << huge;
  const std::string child = Bad("", "<camrea/>");
  EXPECT_NE(child.find("did you mean <camera>"), std::string::npos) << child;
  const std::string unknown =
      LoadError(Experiment("", "", "4,4,1", "<visualization><qt-opengl/></visualization>"));
  EXPECT_NE(unknown.find("unknown renderer 'qt-opengl'"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("osmesa"), std::string::npos) << unknown;
}

TEST(RenderingErrors, UnknownEntitiesAreRejectedBeforeTheFirstFrame) {
  auto sim = LoadXml(Experiment(
      Robot("r", "0,0,0"), kRedRobots, "4,4,1",
      Visualization("",
                    "<camera id=\"c\" follow=\"robot9\" position=\"0,0,1\" "
                    "look_at=\"1,0,0\"/>\n<mesh entity=\"box9\" file=\"" COLONY_SOURCE_DIR
                    "/experiments/meshes/pyramid.obj\"/>")));
  sim->renderers()[0]->set_output_dir(fs::temp_directory_path().string());
  try {
    sim->renderers()[0]->AfterTick();
    ADD_FAILURE() << "no error";
  } catch (const ConfigError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("<string>:4: <camera id=\"c\"> attribute 'follow': no entity 'robot9'"),
              std::string::npos)
        << message;
    EXPECT_NE(message.find("<string>:5: <mesh> attribute 'entity': no entity 'box9'"),
              std::string::npos)
        << message;
  }
}

// The colony program.
struct Result {
  int status;
  std::string output;
};

Result Colony(const std::string& args, const std::string& environment = "") {
  FILE* pipe = popen((environment + " " COLONY_EXE " " + args + " 2>&1").c_str(), "r");
  std::string output;
  char buffer[4096];
  while (size_t n = fread(buffer, 1, sizeof buffer, pipe)) output.append(buffer, n);
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

TEST_F(Rendering, FramesFromTheCommandLineWithADefaultCamera) {
  const Result r = Colony("run " COLONY_SOURCE_DIR
                          "/experiments/diffusion.xml --quiet --set "
                          "framework.experiment.length=0.2 --out " +
                              (dir_ / "run").string() + " --frames " + (dir_ / "frames").string(),
                          "env -u DISPLAY");
  ASSERT_EQ(r.status, 0) << r.output;
  for (const char* name : {"camera0_000000.png", "camera0_000001.png", "camera0_000002.png"}) {
    const Png png = ReadPng(dir_ / "frames" / name);
    EXPECT_EQ(png.width, 1280) << name;
    EXPECT_EQ(png.height, 720) << name;
  }
  EXPECT_FALSE(fs::exists(dir_ / "frames" / "camera0_000003.png"));
}

TEST_F(Rendering, ExampleExperimentWritesFramesIntoTheRunFolder) {
  const Result r = Colony("run " COLONY_SOURCE_DIR
                          "/experiments/rendering.xml --quiet --set "
                          "framework.experiment.length=1 --out " +
                          (dir_ / "run").string());
  ASSERT_EQ(r.status, 0) << r.output;
  for (const char* name : {"overview_000000.png", "overview_000001.png", "chase_000001.png"}) {
    EXPECT_TRUE(fs::exists(dir_ / "run" / "frames" / name)) << name;
  }
}

TEST_F(Rendering, VideoWithoutFfmpegIsRefusedBeforeRunning) {
  const Result r = Colony("run " COLONY_SOURCE_DIR "/experiments/diffusion.xml --video " +
                              (dir_ / "v.mp4").string() + " --out " + (dir_ / "run").string(),
                          "PATH=/nonexistent");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("--video needs ffmpeg, which is not installed"), std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "run")) << "the run should not have started";
}

TEST_F(Rendering, VideoIsAssembledByFfmpeg) {
  // A stand-in ffmpeg that records its arguments and creates the output file.
  fs::create_directories(dir_ / "bin");
  {
    std::ofstream script(dir_ / "bin" / "ffmpeg");
    script << "#!/bin/sh\necho \"$@\" > \"" << (dir_ / "ffmpeg_args").string()
           << "\"\nfor last; do :; done\ntouch \"$last\"\n";
  }
  fs::permissions(dir_ / "bin" / "ffmpeg", fs::perms::owner_all);
  const Result r = Colony("run " COLONY_SOURCE_DIR
                          "/experiments/diffusion.xml --quiet --set "
                          "framework.experiment.length=0.3 --video " +
                              (dir_ / "v.mp4").string() + " --out " + (dir_ / "run").string(),
                          "PATH=" + (dir_ / "bin").string() + ":$PATH");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir_ / "v.mp4"));
  std::ifstream args_file(dir_ / "ffmpeg_args");
  std::stringstream args;
  args << args_file.rdbuf();
  EXPECT_NE(args.str().find("-framerate 10 -i " +
                            (dir_ / "run" / "frames" / "camera0_%06d.png").string()),
            std::string::npos)
      << args.str();
  EXPECT_TRUE(fs::exists(dir_ / "run" / "frames" / "camera0_000003.png"));
}

}  // namespace
}  // namespace colony
