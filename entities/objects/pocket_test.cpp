// Pockets (seed 004) and solid landmarks as a user meets them: a pocket put
// down on another rests on it and covers it; a pocket covered beyond its
// threshold vanishes from the omnidirectional camera, one less covered is
// seen where it lies; robots stop at landmarks and still see them; bad
// attributes are load errors; results do not depend on the thread count.
#include "entities/objects/pocket.h"

#include <cmath>
#include <string>
#include <vector>

#include "actuators/differential_steering/differential_steering.h"
#include "core/entity_type.h"
#include "core/registry.h"
#include "media/test_util.h"
#include "sensors/omnidirectional_camera/omnidirectional_camera.h"

namespace colony {
namespace {

using testing::Experiment;
using testing::LoadError;
using testing::LoadXml;

// Records its camera's blobs; drives straight at params speed (m/s) if given.
class PocketEye : public Controller {
 public:
  void Init(const Params& params) override {
    speed_ = params.GetDouble("speed", 0);
    camera_ = &GetSensor<OmnidirectionalCamera>("omnidirectional_camera");
    if (speed_ > 0) steering_ = &GetActuator<DifferentialSteering>("differential_steering");
  }
  void ControlStep() override {
    blobs = camera_->blobs();
    if (steering_) steering_->SetLinearVelocity(speed_, speed_);
  }
  std::vector<OmnidirectionalCamera::Blob> blobs;

 private:
  double speed_ = 0;
  const OmnidirectionalCamera* camera_ = nullptr;
  DifferentialSteering* steering_ = nullptr;
};

COLONY_REGISTER_CONTROLLER(PocketEye, "pocket_eye", "test: records blobs, drives straight");

std::string Controllers(const std::string& camera = "") {
  return "<pocket_eye id=\"eye\"><sensors><omnidirectional_camera " + camera +
         "/></sensors></pocket_eye>"
         "<pocket_eye id=\"driver\"><sensors><omnidirectional_camera/></sensors><actuators>"
         "<differential_steering/></actuators><params speed=\"0.1\"/></pocket_eye>";
}

std::string Pocket(const std::string& id, double x, double y, double z = 0, double yaw = 0,
                   const std::string& attributes = "") {
  return "<pocket id=\"" + id + "\" " + attributes + "><body position=\"" + std::to_string(x) +
         "," + std::to_string(y) + "," + std::to_string(z) + "\" orientation=\"" +
         std::to_string(yaw) + ",0,0\"/></pocket>";
}

std::string Robot(const std::string& id, double x, double y, const std::string& config = "eye") {
  return "<marxbot id=\"" + id + "\"><body position=\"" + std::to_string(x) + "," +
         std::to_string(y) + ",0\"/><controller config=\"" + config + "\"/></marxbot>";
}

const PocketState& StateOf(const Simulation& sim, const std::string& id) {
  return *sim.space().Get<PocketState>(sim.space().Find(id).index);
}
double Z(const Simulation& sim, const std::string& id) {
  return sim.space().pose(sim.space().Find(id).index).position.z();
}

std::vector<OmnidirectionalCamera::Blob> RedBlobs(Simulation& sim, const std::string& robot) {
  const auto* eye = dynamic_cast<PocketEye*>(sim.ControllerOf(sim.space().Find(robot)));
  std::vector<OmnidirectionalCamera::Blob> red;
  for (const auto& b : eye->blobs) {
    if (b.red == 255 && b.green == 0 && b.blue == 0) red.push_back(b);
  }
  return red;
}

// Moves pocket `id` to (x, y), heading yaw (degrees), high above the floor,
// and puts it down there.
double Drop(Simulation& sim, const std::string& id, double x, double y, double yaw = 0) {
  const uint32_t s = sim.space().Find(id).index;
  sim.space().pose(s) = Pose{Vec3(x, y, 0.2), FromYaw(DegToRad(yaw))};
  return SettlePocket(sim.space(), s);
}

TEST(Pocket, PocketsSettleWhenPlacedEvenWithoutACamera) {
  // No <media>: the pockets settle as the arena is built, and one added
  // while running settles as it is added.
  auto sim = testing::LoadXml(testing::Experiment(
      Pocket("low", 0, 0, 0) + Pocket("high", 0.02, 0, 0.3) + Pocket("far", 1, 1, 0.4)));
  EXPECT_NEAR(Z(*sim, "high"), pocket::kThickness, 1e-9);
  EXPECT_NEAR(Z(*sim, "far"), 0, 1e-9);
  EXPECT_GT(StateOf(*sim, "low").occlusion, 0.7);
  sim->AddEntity(Pocket("late", 0, 0, 0.5));
  EXPECT_NEAR(Z(*sim, "late"), 2 * pocket::kThickness, 1e-9);
}

TEST(Pocket, IsARedSolidBoxThatNoEnginePushes) {
  auto sim = LoadXml(Experiment(Pocket("p", 0.5, 0), Controllers()));
  const Space& space = sim->space();
  const uint32_t s = space.Find("p").index;
  EXPECT_EQ(space.geometry(s).shape, ShapeKind::kBox);
  EXPECT_EQ(space.geometry(s).size, Vec3(0.12, 0.07, 0.015));
  EXPECT_DOUBLE_EQ(space.mass(s), 0.1);
  EXPECT_EQ(space.color(s), (Color{255, 0, 0, 255}));
  EXPECT_EQ(space.flags(s) & (kSolid | kMovable), kSolid | kMovable);
  EXPECT_DOUBLE_EQ(StateOf(*sim, "p").threshold, 0.75);
  EXPECT_EQ(StateOf(*sim, "p").holder, PocketState::kNobody);
}

TEST(Pocket, DroppedOnAnotherSettlesOnTopAndCoversIt) {
  auto sim = LoadXml(Experiment(Pocket("low", 0, 0) + Pocket("high", 1, 1), Controllers()));
  sim->Step();
  EXPECT_EQ(StateOf(*sim, "low").occlusion, 0);
  // Dropped slightly askew over the lower one: one thickness up, level.
  EXPECT_NEAR(Drop(*sim, "high", 0.01, 0.005, 10), 0.015, 1e-12);
  EXPECT_NEAR(Z(*sim, "high"), 0.015, 1e-12);
  EXPECT_GT(StateOf(*sim, "low").occlusion, 0.75);
  EXPECT_EQ(StateOf(*sim, "high").occlusion, 0);
  // Dropped beside it, edge to edge: on the floor, and the lower one is bare again.
  EXPECT_NEAR(Drop(*sim, "high", 0.12, 0), 0, 1e-12);
  EXPECT_EQ(StateOf(*sim, "low").occlusion, 0);
  // A third on two: on the higher one.
  EXPECT_NEAR(Drop(*sim, "high", 0.05, 0), 0.015, 1e-12);
}

TEST(Pocket, HalfCoveredIsHalfOccluded) {
  // The upper pocket shifted by half a length along the lower one.
  auto sim = LoadXml(Experiment(Pocket("low", 0, 0) + Pocket("high", 1, 1), Controllers()));
  Drop(*sim, "high", 0.06, 0);
  EXPECT_NEAR(StateOf(*sim, "low").occlusion, 0.5, 1e-9);
  // A quarter across its width (7 cm wide, shifted 5.25 cm: a quarter covered)... about.
  Drop(*sim, "high", 0, 0.0525);
  EXPECT_NEAR(StateOf(*sim, "low").occlusion, 0.2, 0.06);
}

TEST(Pocket, DeclaredOverAnotherRestsOnItWhateverTheFileOrder) {
  // "top" comes first in the file, declared 10 cm up.
  auto sim = LoadXml(
      Experiment(Pocket("top", 0.01, 0, 0.1) + Pocket("bottom", 0, 0) + Pocket("apart", 1, 0, 0.3),
                 Controllers()));
  sim->Step();
  EXPECT_NEAR(Z(*sim, "bottom"), 0, 1e-12);
  EXPECT_NEAR(Z(*sim, "top"), 0.015, 1e-12);
  EXPECT_NEAR(Z(*sim, "apart"), 0, 1e-12);
  EXPECT_GT(StateOf(*sim, "bottom").occlusion, 0.8);
}

TEST(Pocket, CoveredBeyondItsThresholdVanishesFromTheCamera) {
  // Pockets 0.5 m ahead and 0.3 m to the left of the eye (facing +x).
  const double x = 0.5, y = 0.3;
  auto sim = LoadXml(Experiment(Robot("eye", 0, 0) + Pocket("p", x, y) + Pocket("cover", 1.5, 1.5),
                                Controllers()));
  sim->Step();
  auto blobs = RedBlobs(*sim, "eye");
  ASSERT_EQ(blobs.size(), 1u);
  EXPECT_NEAR(blobs[0].distance, std::hypot(x, y), 1e-5);
  EXPECT_NEAR(blobs[0].bearing, std::atan2(y, x), 1e-3);

  // Half covered (the cover on its far half): still seen, at the centre of
  // its bare half, 3 cm nearer.
  Drop(*sim, "cover", x + 0.06, y);
  sim->Step();
  blobs = RedBlobs(*sim, "eye");
  ASSERT_EQ(blobs.size(), 2u);
  EXPECT_NEAR(std::min(blobs[0].distance, blobs[1].distance), std::hypot(x - 0.03, y), 1e-5);

  // 80% covered: beyond the default 75%, only the cover is seen.
  Drop(*sim, "cover", x + 0.12 * 0.2, y);
  EXPECT_NEAR(StateOf(*sim, "p").occlusion, 0.75, 1e-9);  // 6 of 8 columns
  Drop(*sim, "cover", x + 0.12 * 0.1, y);
  EXPECT_NEAR(StateOf(*sim, "p").occlusion, 0.875, 1e-9);
  sim->Step();
  blobs = RedBlobs(*sim, "eye");
  ASSERT_EQ(blobs.size(), 1u);
  EXPECT_NEAR(blobs[0].distance, std::hypot(x + 0.012, y), 1e-5);  // the cover's top
}

TEST(Pocket, ThresholdZeroHidesAnyCoverAndHundredNone) {
  const std::string arena = Robot("eye", 0, 0) +
                            Pocket("strict", 0.5, 0.3, 0, 0, "occlusion_threshold=\"0\"") +
                            Pocket("lax", 0.5, -0.3, 0, 0, "occlusion_threshold=\"100\"") +
                            Pocket("c1", 1.5, 1.5) + Pocket("c2", 1.5, -1.5);
  // Without the camera's occlusion check, so that only the percentage counts.
  auto sim = LoadXml(Experiment(arena, Controllers("check_occlusions=\"false\"")));
  Drop(*sim, "c1", 0.5 + 0.105, 0.3);  // covers one eighth of strict
  Drop(*sim, "c2", 0.5, -0.3);         // covers all of lax
  EXPECT_NEAR(StateOf(*sim, "strict").occlusion, 0.125, 1e-9);
  EXPECT_EQ(StateOf(*sim, "lax").occlusion, 1);
  sim->Step();
  const auto blobs = RedBlobs(*sim, "eye");
  // c1, c2, lax (under c2, at the same bearing), not strict.
  ASSERT_EQ(blobs.size(), 3u);
  int left = 0;
  for (const auto& b : blobs) left += b.bearing > 0;
  EXPECT_EQ(left, 1);  // c1 only
}

TEST(Pocket, HeldIsNotSeenAndCoversNothing) {
  auto sim = LoadXml(
      Experiment(Robot("eye", 0, 0) + Pocket("p", 0.5, 0) + Pocket("c", 1.5, 1.5), Controllers()));
  Drop(*sim, "c", 0.5, 0);
  EXPECT_EQ(StateOf(*sim, "p").occlusion, 1);
  Space& space = sim->space();
  // Picked up and carried off (as the manipulator does).
  const uint32_t c = space.Find("c").index;
  space.Get<PocketState>(c)->holder = space.Find("eye").index;
  space.pose(c).position = Vec3(1.5, -1.5, 0.1);
  UpdatePocketOcclusion(space);
  EXPECT_EQ(StateOf(*sim, "p").occlusion, 0);
  sim->Step();
  // Only p: the held one is not seen.
  ASSERT_EQ(RedBlobs(*sim, "eye").size(), 1u);
  EXPECT_NEAR(RedBlobs(*sim, "eye")[0].distance, 0.5, 1e-5);
}

// In the 2D engines; in dynamics3d the pocket is not pushed either, but the
// treels may climb onto it (1.5 cm).
TEST(Pocket, RobotsStopAtPocketsAndNeverPushThem) {
  for (const std::string engine :
       {"<kinematics2d id=\"e\"/>", "<dynamics2d id=\"e\"/>", "<dynamics3d id=\"e\"/>"}) {
    const std::string label = engine.substr(1, engine.find(' ') - 1);
    if (!testing::HaveEngine(label)) continue;  // not in this build
    SCOPED_TRACE(engine);
    auto sim = LoadXml(Experiment(Robot("r", 0, 0, "driver") + Pocket("p", 0.4, 0, 0, 90),
                                  Controllers(), "4,4,1", "", engine));
    testing::RunFor(*sim, 6);
    const Vec3 p = testing::PositionOf(*sim, "p");
    EXPECT_NEAR(p.x(), 0.4, 1e-6);
    EXPECT_NEAR(p.y(), 0, 1e-6);
    EXPECT_NEAR(p.z(), 0, 1e-9);
    if (engine.find("dynamics3d") != std::string::npos) continue;
    // Front of the robot (radius 8.5 cm) against the pocket (3.5 cm half width).
    EXPECT_LT(testing::PositionOf(*sim, "r").x(), 0.4 - 0.035 - 0.085 + 0.01);
    EXPECT_GT(testing::PositionOf(*sim, "r").x(), 0.2);
  }
}

TEST(Landmark, RobotsStopAtItAndStillSeeItGreen) {
  for (const std::string engine :
       {"<kinematics2d id=\"e\"/>", "<dynamics2d id=\"e\"/>", "<dynamics3d id=\"e\"/>"}) {
    const std::string label = engine.substr(1, engine.find(' ') - 1);
    if (!testing::HaveEngine(label)) continue;  // not in this build
    SCOPED_TRACE(engine);
    auto sim = LoadXml(Experiment(
        Robot("r", 0, 0, "driver") + "<landmark id=\"l\"><body position=\"0.5,0,0\"/></landmark>",
        Controllers(), "4,4,1", "", engine));
    testing::RunFor(*sim, 8);
    const double x = testing::PositionOf(*sim, "r").x();
    EXPECT_LT(x, 0.5 - 0.03 - 0.085 + 0.005);
    EXPECT_GT(x, 0.3);
    const auto* eye = dynamic_cast<PocketEye*>(sim->ControllerOf(sim->space().Find("r")));
    ASSERT_EQ(eye->blobs.size(), 1u);
    EXPECT_EQ(eye->blobs[0].green, 255);
    EXPECT_NEAR(eye->blobs[0].distance, 0.5 - x, 0.01);
    EXPECT_NEAR(eye->blobs[0].bearing, 0, 0.01);
  }
}

TEST(Landmark, IsASolidCylinderOfItsRadius) {
  auto sim = LoadXml(Experiment(
      "<landmark id=\"a\"><body position=\"0,0,0\"/></landmark>"
      "<landmark id=\"b\" radius=\"0.05\" height=\"0.3\"><body position=\"1,0,0\"/></landmark>",
      Controllers()));
  const Space& space = sim->space();
  const uint32_t a = space.Find("a").index, b = space.Find("b").index;
  EXPECT_EQ(space.geometry(a).shape, ShapeKind::kCylinder);
  EXPECT_DOUBLE_EQ(space.geometry(a).radius, 0.03);
  EXPECT_DOUBLE_EQ(space.geometry(b).radius, 0.05);
  EXPECT_DOUBLE_EQ(space.geometry(b).height(), 0.3);
  EXPECT_EQ(space.flags(a) & (kSolid | kMovable), kSolid);
  // A robot may not start inside one.
  EXPECT_NE(LoadError(Experiment("<landmark id=\"l\"><body position=\"0,0,0\"/></landmark>" +
                                     Robot("r", 0.1, 0),
                                 Controllers()))
                .find("overlaps 'l'"),
            std::string::npos);
}

TEST(Pocket, BadAttributesAreLoadErrorsNamingLineAndAttribute) {
  auto error = [](const std::string& attributes) {
    return LoadError(Experiment(Pocket("p", 0, 0, 0, 0, attributes), Controllers()));
  };
  testing::ExpectMentions(
      error("occlusion_threshold=\"120\""),
      {"<string>:1:", "<pocket id=\"p\">", "attribute 'occlusion_threshold'", "'120'", "[0, 100]"});
  testing::ExpectMentions(error("occlusion_threshold=\"-1\""),
                          {"attribute 'occlusion_threshold'", "'-1'"});
  testing::ExpectMentions(error("mass=\"-0.1\""), {"<string>:1:", "attribute 'mass'", "'-0.1'"});
  testing::ExpectMentions(error("mass=\"0\""), {"attribute 'mass'", "> 0"});
  testing::ExpectMentions(error("size=\"1,1,1\""), {"attribute 'size'", "unknown attribute"});
  testing::ExpectMentions(
      LoadError(Experiment("<landmark id=\"l\" radius=\"0\"><body position=\"0,0,0\"/></landmark>",
                           Controllers())),
      {"<landmark id=\"l\">", "attribute 'radius'", "> 0"});
  // Two pockets at the same height, one over the other: declare the upper one higher.
  testing::ExpectMentions(
      LoadError(Experiment(Pocket("a", 0, 0) + Pocket("b", 0.05, 0), Controllers())),
      {"entity 'b'", "overlaps 'a'"});
}

TEST(Pocket, SameStateHashAtOneAndTwoThreads) {
  std::string arena;
  for (int i = 0; i < 4; ++i) arena += Robot("r" + std::to_string(i), -1.2 + 0.4 * i, -1, "driver");
  for (int i = 0; i < 12; ++i)
    arena += Pocket("p" + std::to_string(i), -0.5 + 0.05 * i, 0.2 + 0.01 * i, 0.02 * i, 15 * i);
  const std::string xml = Experiment(arena, Controllers(), "4,4,1");
  uint64_t hashes[2];
  for (int threads : {1, 2}) {
    auto sim = LoadXml(xml, {}, threads);
    testing::RunFor(*sim, 1);
    hashes[threads - 1] = sim->StateHash();
    EXPECT_GT(Z(*sim, "p11"), 0.01);  // on the heap
  }
  EXPECT_EQ(hashes[0], hashes[1]);
}

TEST(Pocket, RegisteredAttributesMatchTheReadme) {
  const auto* entry = Registry<EntityType>::Get().Find("pocket");
  ASSERT_NE(entry, nullptr);
  auto names = entry->info.AttributeNames();
  names.insert(names.begin(), "id");
  EXPECT_EQ(testing::ReadmeAttributes("entities/objects/README.md", "## pocket"), names);
}

}  // namespace
}  // namespace colony
