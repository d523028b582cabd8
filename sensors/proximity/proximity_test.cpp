// Proximity sensors as a controller sees them: a ring of 24 IR readings on the
// marXbot, 0.01/d of the distance d to the nearest solid thing in range.
#include "sensors/proximity/proximity.h"

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "actuators/differential_steering/differential_steering.h"
#include "core/geometry2d.h"
#include "core/registry.h"
#include "tests/test_util.h"

namespace colony {
namespace {

using testing::Experiment;
using testing::LoadError;
using testing::LoadXml;
using testing::RunFor;

// Copies what its proximity ring read at every control step.
class ProximityProbe : public Controller {
 public:
  void Init(const Params& params) override { sensor_ = &GetSensor<ProximitySensor>("proximity"); }
  void ControlStep() override {
    const auto readings = sensor_->readings();
    last.assign(readings.begin(), readings.end());
    ++steps;
  }
  std::vector<ProximitySensor::Reading> last;
  int steps = 0;

 private:
  const ProximitySensor* sensor_ = nullptr;
};

COLONY_REGISTER_CONTROLLER(ProximityProbe, "proximity_probe", "test: records proximity readings");

std::string Controllers(const std::string& proximity_attributes = "") {
  return "<proximity_probe id=\"pp\"><sensors><proximity " + proximity_attributes +
         "/></sensors></proximity_probe>";
}

std::string Robot(const std::string& id, const std::string& position, double yaw_degrees = 0) {
  return "<marxbot id=\"" + id + "\"><body position=\"" + position + "\" orientation=\"" +
         std::to_string(yaw_degrees) + ",0,0\"/><controller config=\"pp\"/></marxbot>";
}

std::string Box(const std::string& id, const std::string& size, const std::string& position) {
  return "<box id=\"" + id + "\" size=\"" + size + "\"><body position=\"" + position + "\"/></box>";
}

const std::vector<ProximitySensor::Reading>& Readings(Simulation& sim, const std::string& robot) {
  auto* probe = dynamic_cast<ProximityProbe*>(sim.ControllerOf(sim.space().Find(robot)));
  EXPECT_NE(probe, nullptr) << robot;
  static const std::vector<ProximitySensor::Reading> kNone;
  return probe ? probe->last : kNone;
}

float MaxOf(const std::vector<ProximitySensor::Reading>& r) {
  float m = 0;
  for (const auto& x : r) m = std::max(m, x.value);
  return m;
}

// Distance along sensor ray `angle` (robot at the origin, yaw 0) from the body
// surface (radius 0.085) to the plane x = face.
double RayToPlane(double angle, double face) {
  return (face - 0.085 * std::cos(angle)) / std::cos(angle);
}

TEST(Proximity, MarxbotHas24SensorsFifteenDegreesApartFromSevenAndAHalf) {
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0"), Controllers()));
  sim->Step();
  const auto& r = Readings(*sim, "r");
  ASSERT_EQ(r.size(), 24u);
  for (size_t i = 0; i < r.size(); ++i) {
    const double expected = WrapAngle(DegToRad(7.5 + 15.0 * i));
    EXPECT_NEAR(r[i].angle, expected, 1e-6) << "sensor " << i;
  }
  // Ring order is counter-clockwise: the first sensor is just left of the
  // front, the last just right of it.
  EXPECT_NEAR(r.front().angle, DegToRad(7.5), 1e-6);
  EXPECT_NEAR(r.back().angle, DegToRad(-7.5), 1e-6);
  for (size_t i = 0; i < r.size(); ++i) {
    EXPECT_GT(r[i].angle, -M_PI);
    EXPECT_LE(r[i].angle, M_PI);
  }
}

TEST(Proximity, NothingInRangeReadsZero) {
  auto sim = LoadXml(
      Experiment(Robot("r", "0,0,0") + Box("far", "0.2,0.2,0.2", "0.5,0,0"), Controllers()));
  sim->Step();
  for (const auto& x : Readings(*sim, "r")) EXPECT_EQ(x.value, 0.0f) << "angle " << x.angle;
}

// What controllers ask before summing a ring (the diffusion controller, the
// swarm obstacle vector): true only when no sensor reads anything.
TEST(Proximity, AllZeroHoldsOnlyWhenNoSensorReadsAnything) {
  const float angles[4] = {0.0f, 1.5f, 3.0f, -1.5f};
  float values[4] = {0.0f, -0.0f, 0.0f, 0.0f};
  EXPECT_TRUE(ProximitySensor::Readings(values, angles, 4).AllZero());  // -0 reads nothing
  EXPECT_TRUE(ProximitySensor::Readings(values, angles, 0).AllZero());  // no sensors
  for (int i = 0; i < 4; ++i) {
    float seen[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    seen[i] = 1e-30f;  // the faintest reading counts
    EXPECT_FALSE(ProximitySensor::Readings(seen, angles, 4).AllZero()) << "sensor " << i;
  }
  values[3] = std::nanf("");
  EXPECT_FALSE(ProximitySensor::Readings(values, angles, 4).AllZero());
  // Only the first `size` values are looked at.
  values[3] = 1.0f;
  EXPECT_TRUE(ProximitySensor::Readings(values, angles, 3).AllZero());
}

TEST(Proximity, BoxInFrontIsSeenByTheFrontSensorsOnly) {
  // Box face 5 cm in front of the body (the body's radius is 8.5 cm).
  auto sim = LoadXml(
      Experiment(Robot("r", "0,0,0") + Box("b", "0.1,0.6,0.2", "0.185,0,0"), Controllers()));
  sim->Step();
  const auto& r = Readings(*sim, "r");
  ASSERT_EQ(r.size(), 24u);
  // The two sensors either side of the front: 0.01 / d along their rays.
  EXPECT_NEAR(r[0].value, 0.01 / RayToPlane(DegToRad(7.5), 0.135), 1e-5);
  EXPECT_NEAR(r[23].value, 0.01 / RayToPlane(DegToRad(-7.5), 0.135), 1e-5);
  EXPECT_GT(r[0].value, 0.18f);
  EXPECT_FLOAT_EQ(r[0].value, r[23].value);  // symmetric
  // The front ones read most.
  EXPECT_EQ(MaxOf(r), r[0].value);
  // Everything looking backwards reads nothing.
  for (const auto& x : r) {
    if (std::cos(x.angle) < 0) {
      EXPECT_EQ(x.value, 0.0f) << "angle " << x.angle;
    }
  }
}

TEST(Proximity, ReadingsFollowTheRobotsHeading) {
  // Box at +y; the robot faces +y (yaw 90 degrees): its front sensors see it.
  // A second robot faces +x with a box at +y: its left sensors (90 degrees) see it.
  auto sim =
      LoadXml(Experiment(Robot("north", "-1,0,0", 90) + Box("b1", "0.6,0.1,0.2", "-1,0.185,0") +
                             Robot("east", "1,0,0", 0) + Box("b2", "0.6,0.1,0.2", "1,0.185,0"),
                         Controllers()));
  sim->Step();
  const auto& north = Readings(*sim, "north");
  EXPECT_GT(north[0].value, 0.18f);
  EXPECT_GT(north[23].value, 0.18f);
  EXPECT_EQ(north[11].value, 0.0f);
  const auto& east = Readings(*sim, "east");
  // Sensors 5 and 6 are at 82.5 and 97.5 degrees.
  EXPECT_GT(east[5].value, 0.18f);
  EXPECT_GT(east[6].value, 0.18f);
  EXPECT_EQ(east[5].value, MaxOf(east));
  EXPECT_EQ(east[0].value, 0.0f);
  EXPECT_EQ(east[23].value, 0.0f);
  EXPECT_EQ(east[17].value, 0.0f);  // 262.5 degrees: the right side
}

TEST(Proximity, ReadingsFallWithDistance) {
  // Three robots, each with a box at 2, 5 and 8 cm from its front.
  std::string arena;
  const double gaps[] = {0.02, 0.05, 0.08};
  for (int k = 0; k < 3; ++k) {
    const std::string y = std::to_string(-1.0 + k);
    arena += Robot("r" + std::to_string(k), "0," + y + ",0") +
             Box("b" + std::to_string(k), "0.1,0.6,0.2",
                 std::to_string(0.085 + gaps[k] + 0.05) + "," + y + ",0");
  }
  auto sim = LoadXml(Experiment(arena, Controllers()));
  sim->Step();
  const float near = Readings(*sim, "r0")[0].value;
  const float mid = Readings(*sim, "r1")[0].value;
  const float far = Readings(*sim, "r2")[0].value;
  EXPECT_GT(near, mid);
  EXPECT_GT(mid, far);
  EXPECT_GT(far, 0.0f);
  EXPECT_NEAR(near, 0.01 / RayToPlane(DegToRad(7.5), 0.105), 1e-5);
  EXPECT_NEAR(far, 0.01 / RayToPlane(DegToRad(7.5), 0.165), 1e-5);
}

TEST(Proximity, TouchingReadsOne) {
  // Within 1 cm of the body: saturated at 1.
  auto sim =
      LoadXml(Experiment(Robot("r", "0,0,0") + Box("b", "0.1,0.6,0.2", "0.14,0,0"), Controllers()));
  sim->Step();
  const auto& r = Readings(*sim, "r");
  EXPECT_EQ(r[0].value, 1.0f);
  EXPECT_EQ(r[23].value, 1.0f);
  for (const auto& x : r) EXPECT_LE(x.value, 1.0f);
}

TEST(Proximity, DefaultRangeIsTenCentimetresFromTheBody) {
  // Faces at 9 cm and 12 cm from the front (along the x axis).
  auto sim = LoadXml(Experiment(Robot("in", "0,-1,0") + Box("b1", "0.1,0.6,0.2", "0.225,-1,0") +
                                    Robot("out", "0,1,0") + Box("b2", "0.1,0.6,0.2", "0.255,1,0"),
                                Controllers()));
  sim->Step();
  EXPECT_GT(Readings(*sim, "in")[0].value, 0.09f);
  EXPECT_EQ(MaxOf(Readings(*sim, "out")), 0.0f);
}

TEST(Proximity, RangeAttributeWidensOrNarrowsTheRange) {
  const std::string arena =
      Robot("r", "0,0,0") + Box("b", "0.1,0.6,0.2", "0.285,0,0");  // face 15 cm away
  {
    auto sim = LoadXml(Experiment(arena, Controllers()));
    sim->Step();
    EXPECT_EQ(MaxOf(Readings(*sim, "r")), 0.0f);
  }
  {
    auto sim = LoadXml(Experiment(arena, Controllers("range=\"0.2\"")));
    sim->Step();
    EXPECT_NEAR(Readings(*sim, "r")[0].value, 0.01 / RayToPlane(DegToRad(7.5), 0.235), 1e-5);
  }
  {
    // A 4 cm range hides a box 5 cm away.
    auto sim = LoadXml(Experiment(Robot("r", "0,0,0") + Box("b", "0.1,0.6,0.2", "0.185,0,0"),
                                  Controllers("range=\"0.04\"")));
    sim->Step();
    EXPECT_EQ(MaxOf(Readings(*sim, "r")), 0.0f);
  }
}

TEST(Proximity, BadRangeIsReported) {
  const std::string message =
      LoadError(Experiment(Robot("r", "0,0,0"), Controllers("range=\"-0.1\"")));
  EXPECT_NE(message.find("<proximity>"), std::string::npos) << message;
  EXPECT_NE(message.find("attribute 'range'"), std::string::npos) << message;
  EXPECT_NE(message.find("> 0"), std::string::npos) << message;
  const std::string typo = LoadError(Experiment(Robot("r", "0,0,0"), Controllers("rnage=\"0.1\"")));
  EXPECT_NE(typo.find("did you mean 'range'"), std::string::npos) << typo;
}

TEST(Proximity, LowObjectsAreNotSeen) {
  // The sensors are 6 cm above the floor: a 3 cm high box passes under them,
  // and so does a box hanging above them.
  auto sim =
      LoadXml(Experiment(Robot("low", "0,-1,0") + Box("b1", "0.1,0.6,0.03", "0.185,-1,0") +
                             Robot("high", "0,1,0") + Box("b2", "0.1,0.6,0.2", "0.185,1,0.1") +
                             Robot("seen", "-1,0,0") + Box("b3", "0.1,0.6,0.07", "-0.815,0,0"),
                         Controllers()));
  sim->Step();
  EXPECT_EQ(MaxOf(Readings(*sim, "low")), 0.0f);
  EXPECT_EQ(MaxOf(Readings(*sim, "high")), 0.0f);
  EXPECT_GT(Readings(*sim, "seen")[0].value, 0.18f);
}

TEST(Proximity, OtherRobotsAndCylindersAreSeenLightsAreNot) {
  // Another marXbot 5 cm behind (surface to surface), a cylinder 3 cm to the
  // right, and a light right in front (lights are not solid).
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0") + Robot("other", "-0.22,0,0") +
                                    "<cylinder id=\"c\" radius=\"0.05\" height=\"0.2\"><body "
                                    "position=\"0,-0.165,0\"/></cylinder>"
                                    "<light id=\"l\" position=\"0.1,0,0.06\"/>",
                                Controllers()));
  sim->Step();
  const auto& r = Readings(*sim, "r");
  // Back: sensors 11 and 12 (172.5 and 187.5 degrees) look at the other robot.
  EXPECT_GT(r[11].value, 0.15f);
  EXPECT_GT(r[12].value, 0.15f);
  // Right: sensors 17 and 18 (262.5 and 277.5 degrees) look at the cylinder.
  EXPECT_GT(r[17].value, 0.25f);
  EXPECT_GT(r[18].value, 0.25f);
  // Front: the light is not seen.
  EXPECT_EQ(r[0].value, 0.0f);
  EXPECT_EQ(r[23].value, 0.0f);
  // The other robot sees this one with its front sensors (it faces +x).
  EXPECT_GT(Readings(*sim, "other")[0].value, 0.15f);
}

TEST(Proximity, WallsAreSeen) {
  // 4 x 4 arena with 10 cm walls: the inner face of the east wall is at x = 1.9.
  auto sim = LoadXml(Experiment(
      "<walls thickness=\"0.1\" height=\"0.5\"/>" + Robot("r", "1.76,0,0"), Controllers()));
  sim->Step();
  EXPECT_NEAR(Readings(*sim, "r")[0].value, 0.01 / RayToPlane(DegToRad(7.5), 1.9 - 1.76), 1e-4);
}

// The sensor casts a ray only at the footprints that may lie across it
// (proximity_sim.cpp); casting every ray at every solid thing must give the
// same readings. Robots among boxes turned every way, cylinders and other
// robots, packed close: each reading against the nearest hit of its ray
// (core/geometry2d.h's RayFootprint) over everything in the space.
TEST(Proximity, ReadingsAreThoseOfCastingEveryRayAtEverything) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int hits = 0;
  for (int scene = 0; scene < 20; ++scene) {
    const double yaw = 360 * unit(rng);
    std::string body = Robot("r", "0,0,0", yaw);
    for (int k = 0; k < 12; ++k) {
      const double bearing = 2 * M_PI * unit(rng);
      const double kind = unit(rng);
      const std::string id = "o" + std::to_string(k);
      // Bounding radius at most 0.1; the centre 0.2 to 0.3 m away.
      const double d = 0.2 + 0.1 * unit(rng);
      const std::string at = std::to_string(d * std::cos(bearing)) + "," +
                             std::to_string(d * std::sin(bearing)) + ",0";
      if (kind < 0.5) {
        const double w = 0.02 + 0.1 * unit(rng), l = 0.02 + 0.1 * unit(rng);
        body += "<box id=\"" + id + "\" size=\"" + std::to_string(w) + "," + std::to_string(l) +
                ",0.2\"><body position=\"" + at + "\" orientation=\"" +
                std::to_string(360 * unit(rng)) + ",0,0\"/></box>";
      } else {
        body += "<cylinder id=\"" + id + "\" radius=\"" + std::to_string(0.01 + 0.09 * unit(rng)) +
                "\" height=\"0.2\"><body position=\"" + at + "\"/></cylinder>";
      }
    }
    auto sim = LoadXml(Experiment(body, Controllers()));
    sim->Step();
    const Space& space = sim->space();
    const EntityHandle robot = space.Find("r");
    const Pose& pose = space.pose(robot.index);
    const RingMount& ring = *sim->MountsOf(robot).Ring("proximity");
    const double z = pose.position.z() + ring.elevation;
    const auto& readings = Readings(*sim, "r");
    ASSERT_EQ(readings.size(), 24u);
    for (int i = 0; i < 24; ++i) {
      const double a = YawOf(pose.orientation) + ring.AngleOf(i);
      const Vec2 dir(std::cos(a), std::sin(a));
      const Vec2 origin = pose.position.head<2>() + ring.radius * dir;
      double best = kNoHit;
      for (uint32_t s = 0; s < space.slots(); ++s) {
        if (s == robot.index || !space.alive(s)) continue;
        const Pose& p = space.pose(s);
        const Geometry& g = space.geometry(s);
        if (!(z >= p.position.z() && z < p.position.z() + g.height())) continue;
        best = std::min(best, RayFootprint(origin, dir, p, g));
      }
      const double expected = best <= ring.range ? std::min(1.0, 0.01 / std::max(best, 1e-6)) : 0.0;
      EXPECT_NEAR(readings[i].value, expected, 1e-5) << "scene " << scene << ", sensor " << i;
      hits += expected > 0;
    }
  }
  EXPECT_GT(hits, 80);  // about a fifth of the rays hit something
}

std::vector<float> Values(Simulation& sim, const std::string& robot) {
  std::vector<float> v;
  for (const auto& x : Readings(sim, robot)) v.push_back(x.value);
  return v;
}

TEST(Proximity, GaussianNoiseIsReproducibleWithTheSameSeed) {
  const std::string arena = Robot("r", "0,0,0") + Box("b", "0.1,0.6,0.2", "0.185,0,0");
  const std::string noisy = Controllers("noise=\"gaussian\" noise_std_dev=\"0.05\"");
  auto clean = LoadXml(Experiment(arena, Controllers()));
  auto a = LoadXml(Experiment(arena, noisy));
  auto b = LoadXml(Experiment(arena, noisy));
  auto other_seed = LoadXml(Experiment(arena, noisy), {"framework.experiment.random_seed=8"});
  for (int t = 0; t < 5; ++t) {
    clean->Step();
    a->Step();
    b->Step();
    other_seed->Step();
    EXPECT_EQ(Values(*a, "r"), Values(*b, "r")) << "tick " << t;
    EXPECT_NE(Values(*a, "r"), Values(*clean, "r")) << "tick " << t;
    EXPECT_NE(Values(*a, "r"), Values(*other_seed, "r")) << "tick " << t;
    for (float v : Values(*a, "r")) {
      EXPECT_GE(v, 0.0f);
      EXPECT_LE(v, 1.0f);
    }
  }
  // Noise stays around the clean value: 0.05 standard deviation.
  EXPECT_NEAR(Values(*a, "r")[0], Values(*clean, "r")[0], 0.25);
  // And it changes from tick to tick.
  const auto before = Values(*a, "r");
  a->Step();
  EXPECT_NE(Values(*a, "r"), before);
}

TEST(Proximity, UniformNoiseStaysWithinItsRange) {
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0") + Box("b", "0.1,0.6,0.2", "0.185,0,0"),
                                Controllers("noise=\"uniform\" noise_range=\"-0.02,0.02\"")));
  const double clean = 0.01 / RayToPlane(DegToRad(7.5), 0.135);
  bool changed = false;
  for (int t = 0; t < 20; ++t) {
    sim->Step();
    const auto& r = Readings(*sim, "r");
    EXPECT_NEAR(r[0].value, clean, 0.02 + 1e-6);
    changed = changed || std::abs(r[0].value - clean) > 1e-6;
    // Nothing behind: noise on 0, clamped at 0.
    EXPECT_GE(r[12].value, 0.0f);
    EXPECT_LE(r[12].value, 0.02f + 1e-6f);
  }
  EXPECT_TRUE(changed);
}

TEST(Proximity, DroppedReadingsReadZero) {
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0") + Box("b", "0.1,0.6,0.2", "0.185,0,0"),
                                Controllers("drop_probability=\"1\"")));
  sim->Step();
  EXPECT_EQ(MaxOf(Readings(*sim, "r")), 0.0f);
}

TEST(Proximity, NoiseAttributesAreChecked) {
  const std::string robot = Robot("r", "0,0,0");
  const std::string missing = LoadError(Experiment(robot, Controllers("noise=\"gaussian\"")));
  EXPECT_NE(missing.find("noise_std_dev"), std::string::npos) << missing;
  const std::string kind =
      LoadError(Experiment(robot, Controllers("noise=\"gausian\" noise_std_dev=\"0.1\"")));
  EXPECT_NE(kind.find("did you mean 'gaussian'"), std::string::npos) << kind;
  const std::string range =
      LoadError(Experiment(robot, Controllers("noise=\"uniform\" noise_range=\"0.1,-0.1\"")));
  EXPECT_NE(range.find("noise_range"), std::string::npos) << range;
  const std::string drop = LoadError(Experiment(robot, Controllers("drop_probability=\"1.5\"")));
  EXPECT_NE(drop.find("drop_probability"), std::string::npos) << drop;
}

TEST(Proximity, ReadingsUpdateAsTheWorldChanges) {
  // A box added at run time is seen from the next tick; removed, it is gone.
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0"), Controllers()));
  sim->Step();
  EXPECT_EQ(MaxOf(Readings(*sim, "r")), 0.0f);
  const EntityHandle box = sim->AddEntity(Box("b", "0.1,0.6,0.2", "0.185,0,0"));
  sim->Step();
  EXPECT_GT(Readings(*sim, "r")[0].value, 0.18f);
  sim->RemoveEntity(box);
  sim->Step();
  EXPECT_EQ(MaxOf(Readings(*sim, "r")), 0.0f);
}

// Sampling periods, rates and events (docs/events.md).

// Drives at `speed` for `forward` ticks, then back at the same speed; counts
// its steps; with watch="true" asks its ring (or the sensor named by
// `sensor`) for events on reading 0 crossing `threshold` (crossing: rising,
// falling or both), and records them with the tick they came on.
class EventProbe : public Controller {
 public:
  void Init(const Params& params) override {
    ring = &GetSensor<ProximitySensor>("proximity");
    wheels_ = &GetActuator<DifferentialSteering>("differential_steering");
    speed_ = params.GetDouble("speed", 0);
    forward_ = params.GetInt("forward", 1000000);
    if (params.GetBool("watch", false)) {
      ThresholdWatch watch;
      watch.reading = 0;
      watch.threshold = params.GetDouble("threshold", 0.2);
      watch.hysteresis = params.GetDouble("hysteresis", 0);
      const std::string crossing = params.GetString("crossing", "both");
      watch.crossing = crossing == "rising"    ? Crossing::kRising
                       : crossing == "falling" ? Crossing::kFalling
                                               : Crossing::kBoth;
      GetSensor<Sensor>(params.GetString("sensor", "proximity")).Watch(watch);
    }
  }
  void ControlStep() override {
    ++steps;
    const double v = steps <= forward_ ? speed_ : -speed_;
    wheels_->SetLinearVelocity(v, v);
    if (read) (void)ring->readings();
  }
  void OnEvent(const SensorEvent& event) override { events.push_back(event); }

  ProximitySensor* ring = nullptr;
  int64_t steps = 0;
  bool read = false;
  std::vector<SensorEvent> events;

 private:
  DifferentialSteering* wheels_ = nullptr;
  double speed_ = 0;
  int64_t forward_ = 0;
};

COLONY_REGISTER_CONTROLLER(EventProbe, "event_probe", "test: drives, counts steps and events");

std::string EventProbeController(const std::string& controller_attributes,
                                 const std::string& proximity_attributes, const std::string& params,
                                 const std::string& more_sensors = "") {
  return "<event_probe id=\"pp\" " + controller_attributes +
         "><actuators><differential_steering/></actuators><sensors><proximity " +
         proximity_attributes + "/>" + more_sensors + "</sensors><params " + params +
         "/></event_probe>";
}

EventProbe& ProbeOf(Simulation& sim) {
  return *dynamic_cast<EventProbe*>(sim.ControllerOf(sim.space().Find("r")));
}

TEST(ProximitySampling, At67HzIn200TicksPerSecondTheReadingsChangeAtMostEveryThirdTick) {
  // A robot near a wall with noisy readings: a fresh sample always differs
  // from the last one, so the readings change exactly on the sampling ticks.
  // period="0.015" is the marXbot's 67 Hz (seed 000's 15 ms).
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0") + Box("w", "0.1,1,0.5", "0.19,0,0"),
                                EventProbeController("",
                                                     "period=\"0.015\" noise=\"gaussian\" "
                                                     "noise_std_dev=\"0.05\"",
                                                     "")),
                     {"framework.experiment.ticks_per_second=200"});
  EventProbe& probe = ProbeOf(*sim);
  std::vector<float> last(24, 0.0f);
  std::vector<uint64_t> changed;
  for (int t = 0; t < 60; ++t) {
    sim->Step();
    const auto& readings = probe.ring->readings();
    bool differs = false;
    for (size_t i = 0; i < readings.size(); ++i) {
      differs = differs || readings[i].value != last[i];
      last[i] = readings[i].value;
    }
    if (differs) changed.push_back(sim->tick());
  }
  ASSERT_EQ(changed.size(), 20u);
  EXPECT_EQ(changed.front(), 1u);
  for (size_t i = 1; i < changed.size(); ++i) {
    EXPECT_GE(changed[i] - changed[i - 1], 3u)
        << "changed on ticks " << changed[i - 1] << " and " << changed[i];
  }
  // The controller still steps every tick, reading the held values.
  EXPECT_EQ(probe.steps, 60);
}

TEST(ProximitySampling, AControllerAt25HzIn200TicksPerSecondStepsEveryEighthTick) {
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0"), EventProbeController("rate=\"25\"", "", "")),
                     {"framework.experiment.ticks_per_second=200"});
  RunFor(*sim, 1.0);
  EXPECT_EQ(ProbeOf(*sim).steps, 25);
  auto at67 = LoadXml(Experiment(Robot("r", "0,0,0"), EventProbeController("rate=\"67\"", "", "")),
                      {"framework.experiment.ticks_per_second=200"});
  RunFor(*at67, 3.0);
  EXPECT_EQ(ProbeOf(*at67).steps, 3 * 67);
}

// The robot drives 6 cm towards a wall 8 cm ahead, then backs away: reading 0
// rises past 0.2 (5 cm) once and falls back below it once.
struct Crossings {
  std::vector<SensorEvent> events;
  std::vector<uint64_t> event_ticks, rose, fell;  // ticks: of events; reading 0 seen crossing
};

Crossings DriveToWallAndBack(const std::string& params, const std::string& noise = "") {
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0") + Box("w", "0.1,1,0.5", "0.215,0,0"),
                                EventProbeController("", noise,
                                                     "speed=\"0.05\" forward=\"12\" watch=\"true\" "
                                                     "threshold=\"0.2\" " +
                                                         params)));
  EventProbe& probe = ProbeOf(*sim);
  Crossings c;
  bool above = false;
  for (int t = 0; t < 40; ++t) {
    const size_t before = probe.events.size();
    sim->Step();
    for (size_t i = before; i < probe.events.size(); ++i) c.event_ticks.push_back(sim->tick());
    const double v = probe.ring->readings()[0].value;
    if (!above && v >= 0.2) c.rose.push_back(sim->tick());
    if (above && v < 0.2) c.fell.push_back(sim->tick());
    above = v >= 0.2;
  }
  c.events = probe.events;
  return c;
}

TEST(ProximityEvents, AThresholdEventFiresExactlyOncePerCrossing) {
  const Crossings c = DriveToWallAndBack("crossing=\"both\"");
  ASSERT_EQ(c.rose.size(), 1u);
  ASSERT_EQ(c.fell.size(), 1u);
  ASSERT_EQ(c.events.size(), 2u);
  EXPECT_TRUE(c.events[0].rising);
  EXPECT_EQ(c.event_ticks[0], c.rose[0]);
  EXPECT_GE(c.events[0].value, 0.2);
  EXPECT_EQ(c.events[0].reading, 0);
  EXPECT_FALSE(c.events[1].rising);
  EXPECT_EQ(c.event_ticks[1], c.fell[0]);
  EXPECT_LT(c.events[1].value, 0.2);
  // The reading stayed above the threshold for several ticks in between.
  EXPECT_GT(c.fell[0] - c.rose[0], 3u);

  const Crossings rising = DriveToWallAndBack("crossing=\"rising\"");
  ASSERT_EQ(rising.events.size(), 1u);
  EXPECT_TRUE(rising.events[0].rising);
  const Crossings falling = DriveToWallAndBack("crossing=\"falling\"");
  ASSERT_EQ(falling.events.size(), 1u);
  EXPECT_FALSE(falling.events[0].rising);
}

TEST(ProximityEvents, HysteresisKeepsNoiseAroundTheThresholdFromFiringAgain) {
  // Noise of 0.01 around a threshold the reading passes slowly would cross
  // it back and forth; a hysteresis of 0.05 leaves one rise and one fall.
  const Crossings c =
      DriveToWallAndBack("hysteresis=\"0.05\"", "noise=\"gaussian\" noise_std_dev=\"0.01\"");
  ASSERT_EQ(c.events.size(), 2u);
  EXPECT_TRUE(c.events[0].rising);
  EXPECT_FALSE(c.events[1].rising);
}

TEST(ProximityEvents, ASensorThatEmitsNoEventsIsNamedWithTheControllersLine) {
  const std::string message = LoadError(Experiment(
      Robot("r", "0,0,0"),
      EventProbeController("", "", "watch=\"true\" sensor=\"positioning\"", "<positioning/>")));
  EXPECT_TRUE(testing::Mentions(message, {"<string>:1:", "event_probe", "emits no events"}))
      << message;
  const std::string unknown = LoadError(Experiment(
      Robot("r", "0,0,0"), EventProbeController("", "", "watch=\"true\" sensor=\"ring2\"")));
  EXPECT_TRUE(testing::Mentions(unknown, {"<string>:1:", "'ring2'", "not declared"})) << unknown;
}

TEST(ProximityBus, PollingAt67HzCounts61BytesAPollAndEventsSevenBytes) {
  auto sim =
      LoadXml(Experiment(Robot("r", "0,0,0"),
                         EventProbeController("rate=\"67\"", "period=\"0.015\" bus=\"true\"", "")),
              {"framework.experiment.ticks_per_second=200"});
  ProbeOf(*sim).read = true;
  RunFor(*sim, 2.0);
  EXPECT_EQ(testing::Metric(*sim, "bus_bytes"), 2 * 4087);
  // Without reading the ring, only its events count: one rise, one fall.
  auto events = LoadXml(Experiment(Robot("r", "0,0,0") + Box("w", "0.1,1,0.5", "0.215,0,0"),
                                   EventProbeController("", "bus=\"true\"",
                                                        "speed=\"0.05\" forward=\"12\" "
                                                        "watch=\"true\" threshold=\"0.2\"")));
  RunFor(*events, 4.0);
  EXPECT_EQ(ProbeOf(*events).events.size(), 2u);
  EXPECT_EQ(testing::Metric(*events, "bus_bytes"), 2 * 7);
}

TEST(ProximityBus, WithoutSamplingPeriodsRatesOrBusTheStateHashIsUnchanged) {
  // The attributes at their defaults give the run without them.
  const std::string plain = Experiment(Robot("r", "0,0,0") + Box("w", "0.1,1,0.5", "0.215,0,0"),
                                       EventProbeController("",
                                                            "noise=\"gaussian\" "
                                                            "noise_std_dev=\"0.02\"",
                                                            "speed=\"0.05\" forward=\"12\""));
  std::string spelled = plain;
  spelled.replace(spelled.find("noise=\"gaussian\""), 0, "period=\"0.1\" bus=\"false\" ");
  auto a = LoadXml(plain), b = LoadXml(spelled);
  for (int t = 0; t < 30; ++t) {
    a->Step();
    b->Step();
    ASSERT_EQ(a->StateHash(), b->StateHash()) << "tick " << a->tick();
  }
}

}  // namespace
}  // namespace colony
