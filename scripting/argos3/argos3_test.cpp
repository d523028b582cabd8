// The ARGoS compatibility layer: math types, the configuration tree, and the
// device adapters' unit conversions, checked against fake Colony devices.
#include <argos3/core/control_interface/ci_controller.h>
#include <argos3/core/utility/configuration/argos_configuration.h>
#include <argos3/core/utility/datatypes/byte_array.h>
#include <argos3/core/utility/logging/argos_log.h>
#include <argos3/core/utility/math/rng.h>
#include <argos3/core/utility/math/vector2.h>
#include <argos3/plugins/robots/foot-bot/control_interface/ci_footbot_base_ground_sensor.h>
#include <argos3/plugins/robots/foot-bot/control_interface/ci_footbot_motor_ground_sensor.h>
#include <argos3/plugins/robots/foot-bot/control_interface/ci_footbot_proximity_sensor.h>
#include <argos3/plugins/robots/generic/control_interface/ci_colored_blob_omnidirectional_camera_sensor.h>
#include <argos3/plugins/robots/generic/control_interface/ci_differential_steering_actuator.h>
#include <argos3/plugins/robots/generic/control_interface/ci_leds_actuator.h>
#include <argos3/plugins/robots/generic/control_interface/ci_positioning_sensor.h>
#include <argos3/plugins/robots/generic/control_interface/ci_range_and_bearing_actuator.h>
#include <argos3/plugins/robots/generic/control_interface/ci_range_and_bearing_sensor.h>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "actuators/differential_steering/differential_steering.h"
#include "actuators/leds/leds.h"
#include "actuators/range_and_bearing/range_and_bearing.h"
#include "configuration_tree.h"
#include "sensors/ground/ground.h"
#include "sensors/omnidirectional_camera/omnidirectional_camera.h"
#include "sensors/positioning/positioning.h"
#include "sensors/proximity/proximity.h"
#include "sensors/range_and_bearing/range_and_bearing.h"

using namespace argos;

namespace {

constexpr double kEps = 1e-12;

// ---------------------------------------------------------------------------
// Math types

TEST(Argos3Math, RadiansSignedNormalizeWrapsIntoMinusPiPi) {
  EXPECT_NEAR(CRadians(1.5 * ARGOS_PI).SignedNormalize().GetValue(), -0.5 * ARGOS_PI, kEps);
  EXPECT_NEAR(CRadians(-1.5 * ARGOS_PI).SignedNormalize().GetValue(), 0.5 * ARGOS_PI, kEps);
  EXPECT_NEAR(CRadians(7 * ARGOS_PI + 0.25).SignedNormalize().GetValue(), -ARGOS_PI + 0.25, 1e-9);
  EXPECT_EQ(CRadians(ARGOS_PI).SignedNormalize().GetValue(), ARGOS_PI);  // inside: unchanged
  EXPECT_NEAR(CRadians(-0.5 * ARGOS_PI).UnsignedNormalize().GetValue(), 1.5 * ARGOS_PI, kEps);
  EXPECT_NEAR(CDegrees(370).SignedNormalize().GetValue(), 10, kEps);
  EXPECT_NEAR(CDegrees(-90).UnsignedNormalize().GetValue(), 270, kEps);
}

TEST(Argos3Math, AngleConversionsAndDifferences) {
  EXPECT_NEAR(ToRadians(CDegrees(90)).GetValue(), ARGOS_PI / 2, kEps);
  EXPECT_NEAR(ToDegrees(CRadians::PI).GetValue(), 180, kEps);
  // The short way round, across the +-pi seam.
  EXPECT_NEAR(NormalizedDifference(ToRadians(CDegrees(170)), ToRadians(CDegrees(-170))).GetValue(),
              ToRadians(CDegrees(-20)).GetValue(), kEps);
  EXPECT_NEAR(NormalizedDifference(CDegrees(10), CDegrees(350)).GetValue(), 20, kEps);
  EXPECT_NEAR(Abs(CRadians(-0.3)).GetValue(), 0.3, kEps);
  EXPECT_NEAR(CRadians::PI / CRadians::PI_OVER_TWO, 2, kEps);
  EXPECT_TRUE(CRadians(0.1) > CRadians::ZERO);
}

TEST(Argos3Math, Vector2LengthAngleAndPolarConstruction) {
  EXPECT_NEAR(CVector2(3, 4).Length(), 5, kEps);
  EXPECT_NEAR(CVector2(0, 2).Angle().GetValue(), ARGOS_PI / 2, kEps);
  EXPECT_NEAR(CVector2(-1, -1).Angle().GetValue(), -0.75 * ARGOS_PI, kEps);
  const CVector2 polar(2, CRadians::PI_OVER_TWO);
  EXPECT_NEAR(polar.GetX(), 0, kEps);
  EXPECT_NEAR(polar.GetY(), 2, kEps);
  // Summing readings as a diffusion controller does: equal readings left
  // and right cancel sideways.
  CVector2 sum = CVector2(0.5, CRadians(0.3)) + CVector2(0.5, CRadians(-0.3));
  EXPECT_NEAR(sum.Angle().GetValue(), 0, kEps);
  EXPECT_NEAR(sum.Length(), std::cos(0.3), kEps);
  CVector2 v(1, 0);
  v.Rotate(CRadians::PI_OVER_TWO);
  EXPECT_NEAR(v.GetX(), 0, kEps);
  EXPECT_NEAR(v.GetY(), 1, kEps);
  EXPECT_NEAR(CVector2(2, 0).Normalize().Length(), 1, kEps);
  EXPECT_NEAR(CVector2(1, 0).CrossProduct(CVector2(0, 1)), 1, kEps);
  EXPECT_NEAR(Distance(CVector2(1, 1), CVector2(4, 5)), 5, kEps);
  EXPECT_EQ(-CVector2::X, CVector2(-1, 0));
  EXPECT_EQ(2.0 * CVector2(1, 2), CVector2(2, 4));
}

TEST(Argos3Math, RangeBoundsTruncationAndWrapping) {
  CRange<Real> r(0, 1);
  Real v = 1.5;
  r.TruncValue(v);
  EXPECT_EQ(v, 1);
  EXPECT_TRUE(r.WithinMinBoundIncludedMaxBoundIncluded(1));
  EXPECT_FALSE(r.WithinMinBoundIncludedMaxBoundExcluded(1));
  EXPECT_NEAR(r.NormalizeValue(0.25), 0.25, kEps);
  CRange<UInt32> counts(0, 100);
  EXPECT_NEAR(counts.NormalizeValue(25), 0.25, kEps);
  CRange<CRadians> angles(-CRadians::PI, CRadians::PI);
  CRadians a(3 * ARGOS_PI / 2);
  angles.WrapValue(a);
  EXPECT_NEAR(a.GetValue(), -ARGOS_PI / 2, kEps);
}

TEST(Argos3Math, QuaternionHeadingRoundTrip) {
  const CQuaternion q(ToRadians(CDegrees(30)), CVector3::Z);
  CRadians z, y, x;
  q.ToEulerAngles(z, y, x);
  EXPECT_NEAR(ToDegrees(z).GetValue(), 30, 1e-9);
  EXPECT_NEAR(y.GetValue(), 0, 1e-12);
  EXPECT_NEAR(x.GetValue(), 0, 1e-12);
  CVector3 forward = CVector3::X;
  forward.Rotate(CQuaternion(CRadians::PI_OVER_TWO, CVector3::Z));
  EXPECT_NEAR(forward.GetX(), 0, 1e-12);
  EXPECT_NEAR(forward.GetY(), 1, 1e-12);
  CQuaternion e;
  e.FromEulerAngles(ToRadians(CDegrees(45)), CRadians::ZERO, CRadians::ZERO);
  e.ToEulerAngles(z, y, x);
  EXPECT_NEAR(ToDegrees(z).GetValue(), 45, 1e-9);
}

TEST(Argos3Math, GeneralHelpers) {
  EXPECT_EQ(Max(2, 3), 3);
  EXPECT_EQ(Min<Real>(2.5, 3), 2.5);
  EXPECT_EQ(Sign(-4.0), -1);
  EXPECT_EQ(Sign(0.0), 0);
  EXPECT_EQ(Square(3), 9);
  EXPECT_EQ(Round(2.5), 3);
  EXPECT_NEAR(Interpolate(0.5, {{0, 0}, {1, 10}}), 5, kEps);
}

// ---------------------------------------------------------------------------
// Colours and byte arrays

TEST(Argos3Datatypes, ColorsByNameAndComponents) {
  CColor c;
  c.Set("red");
  EXPECT_EQ(c, CColor::RED);
  c.Set("10,20,30");
  EXPECT_EQ(c, CColor(10, 20, 30));
  c.Set("10,20,30,40");
  EXPECT_EQ(c.GetAlpha(), 40);
  EXPECT_THROW(c.Set("reddish"), CARGoSException);
  EXPECT_THROW(c.Set("1,2,300"), CARGoSException);
  std::ostringstream out;
  out << CColor::GRAY50 << " " << CColor(1, 2, 3);
  EXPECT_EQ(out.str(), "gray50 1,2,3,255");
  EXPECT_NEAR(CColor::WHITE.ToGrayScale(), 255, 1e-9);
}

TEST(Argos3Datatypes, ByteArrayRoundTripsInNetworkOrder) {
  CByteArray b;
  b << UInt8(7) << UInt16(0x0102) << SInt32(-5) << 2.5 << std::string("hi");
  ASSERT_EQ(b.Size(), 1u + 2 + 4 + 8 + 3);
  EXPECT_EQ(b[1], 0x01);  // big-endian
  EXPECT_EQ(b[2], 0x02);
  UInt8 u8;
  UInt16 u16;
  SInt32 s32;
  double d;
  std::string s;
  b >> u8 >> u16 >> s32 >> d >> s;
  EXPECT_EQ(u8, 7);
  EXPECT_EQ(u16, 0x0102);
  EXPECT_EQ(s32, -5);
  EXPECT_EQ(d, 2.5);
  EXPECT_EQ(s, "hi");
  EXPECT_TRUE(b.Empty());
  EXPECT_THROW(b.PopFront<UInt32>(), CARGoSException);
  CByteArray z(3, 9);
  z.Zero();
  EXPECT_EQ(z, CByteArray(3));
}

// ---------------------------------------------------------------------------
// Configuration tree

TConfigurationNode Tree(const internal::ParameterList& parameters) {
  return internal::BuildConfigurationTree("params", parameters);
}

TEST(Argos3Configuration, DottedParametersAreChildNodes) {
  TConfigurationNode root = Tree({{"alpha", "7.5"},
                                  {"wheel_turning.max_speed", "10"},
                                  {"wheel_turning.hard_turn_angle_threshold", "90"},
                                  {"diffusion.go_straight_angle_range", "-5:5"},
                                  {"state.food_rule.active", "true"}});
  Real alpha = 0;
  GetNodeAttribute(root, "alpha", alpha);
  EXPECT_EQ(alpha, 7.5);
  ASSERT_TRUE(NodeExists(root, "wheel_turning"));
  TConfigurationNode& wheels = GetNode(root, "wheel_turning");
  EXPECT_EQ(wheels.Value(), "wheel_turning");
  CDegrees angle;
  GetNodeAttribute(wheels, "hard_turn_angle_threshold", angle);
  EXPECT_EQ(angle.GetValue(), 90);
  CRange<CDegrees> range;
  GetNodeAttribute(GetNode(root, "diffusion"), "go_straight_angle_range", range);
  EXPECT_EQ(range.GetMin().GetValue(), -5);
  EXPECT_EQ(range.GetMax().GetValue(), 5);
  bool active = false;
  GetNodeAttribute(GetNode(GetNode(root, "state"), "food_rule"), "active", active);
  EXPECT_TRUE(active);
  // What was never read, by its dotted name.
  EXPECT_EQ(internal::UnreadAttributes(root), std::vector<std::string>{"wheel_turning.max_speed"});
  TConfigurationNodeIterator it;
  std::vector<std::string> names;
  for (it = it.begin(&root); it != it.end(); ++it) names.push_back(it->Value());
  EXPECT_EQ(names, (std::vector<std::string>{"wheel_turning", "diffusion", "state"}));
}

TEST(Argos3Configuration, DefaultsOnlyWhenMissing) {
  TConfigurationNode root = Tree({{"velocity", "5"}, {"count", "-3"}, {"flag", "yes"}});
  Real velocity = 1;
  GetNodeAttributeOrDefault(root, "velocity", velocity, velocity);
  EXPECT_EQ(velocity, 5);
  Real delta = 0;
  GetNodeAttributeOrDefault(root, "delta", delta, 0.5);
  EXPECT_EQ(delta, 0.5);
  // A malformed value is an error, never the default.
  UInt32 count = 7;
  try {
    GetNodeAttributeOrDefault(root, "count", count, UInt32(7));
    FAIL() << "a negative count was accepted";
  } catch (const CARGoSException& e) {
    EXPECT_EQ(e.parameter(), "count");
    EXPECT_EQ(e.value(), "-3");
    EXPECT_NE(std::string(e.what()).find("whole number in [0, 4294967295]"), std::string::npos)
        << e.what();
  }
  bool flag = false;
  EXPECT_THROW(GetNodeAttribute(root, "flag", flag), CARGoSException);
}

TEST(Argos3Configuration, MissingNodesAndAttributesNameTheirPath) {
  TConfigurationNode root = Tree({{"flocking.gain", "1"}});
  try {
    Real target = 0;
    GetNodeAttribute(GetNode(root, "flocking"), "target_distance", target);
    FAIL();
  } catch (const CARGoSException& e) {
    EXPECT_EQ(e.parameter(), "flocking.target_distance");
  }
  try {
    GetNode(root, "wheel_turning");
    FAIL();
  } catch (CARGoSException& e) {
    // Nesting keeps the parameter and the inner message.
    try {
      THROW_ARGOSEXCEPTION_NESTED("Error parsing the controller parameters.", e);
    } catch (const CARGoSException& outer) {
      EXPECT_EQ(outer.parameter(), "wheel_turning");
      EXPECT_NE(std::string(outer.what()).find("[NESTED] Node 'wheel_turning' not found"),
                std::string::npos)
          << outer.what();
    }
  }
}

// ---------------------------------------------------------------------------
// Controller host and device adapters

struct FakeProximity : colony::ProximitySensor {
  // The readings are a view (values in the simulated sensor's blocks, angles
  // in its ring's list); the fake owns both.
  void Resize(size_t n) {
    values.resize(n);
    angles.resize(n);
    values_ = values.data();
    angles_ = angles.data();
    count_ = static_cast<uint32_t>(n);
  }
  std::vector<float> values, angles;
};
struct FakeGround : colony::GroundSensor {
  std::vector<Reading>& set() { return readings_; }
};
struct FakeCamera : colony::OmnidirectionalCamera {
  std::vector<Blob>& set() { return blobs_; }
};
struct FakeRabSensor : colony::RangeAndBearingSensor {
  std::vector<Packet>& set() { return packets_; }
};
struct FakePositioning : colony::PositioningSensor {
  void Set(double x, double y, double yaw) {
    x_ = x;
    y_ = y;
    yaw_ = yaw;
  }
};
struct FakeLeds : colony::Leds {
  FakeLeds() { colors_.resize(13); }
};
struct FakeRabActuator : colony::RangeAndBearingActuator {
  FakeRabActuator() { data_.resize(4); }
};

// An ARGoS controller whose steps the test writes.
class ProbeController : public CCI_Controller {
 public:
  static inline std::function<void(ProbeController&, TConfigurationNode&)> on_init;
  static inline std::function<void(ProbeController&)> on_step;
  void Init(TConfigurationNode& node) override {
    if (on_init) on_init(*this, node);
  }
  void ControlStep() override {
    if (on_step) on_step(*this);
  }
};

// A robot with fake devices, labelled as in a Colony file, hosting a
// ProbeController.
class HostTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ProbeController::on_init = nullptr;
    ProbeController::on_step = nullptr;
    proximity_.Resize(24);
    for (int i = 0; i < 24; ++i) proximity_.angles[i] = static_cast<float>((i + 0.5) * M_PI / 12);
    ground_.set().resize(8);
    for (int i = 0; i < 8; ++i)
      ground_.set()[i] = {1.0f, static_cast<float>(colony_wrap(i * M_PI / 4))};
    sensors_ = {&proximity_, &ground_, &camera_, &rab_sensor_, &positioning_};
    actuators_ = {&wheels_, &leds_, &rab_actuator_};
    labels_.sensor_labels = &sensor_labels_;
    labels_.actuator_labels = &actuator_labels_;
    table_.robot_id = &id_;
    table_.sensors = sensors_.data();
    table_.actuators = actuators_.data();
    table_.labels = &labels_;
  }
  static double colony_wrap(double a) { return a > M_PI ? a - 2 * M_PI : a; }

  std::unique_ptr<internal::ControllerHost> Start(const colony::Params& params = {},
                                                  uint64_t seed = 1) {
    auto host = std::make_unique<internal::ControllerHostFor<ProbeController>>();
    host->Bind(table_, colony::RandomStream(seed));
    host->Init(params);
    return host;
  }

  std::string id_ = "fb0";
  FakeProximity proximity_;
  FakeGround ground_;
  FakeCamera camera_;
  FakeRabSensor rab_sensor_;
  FakePositioning positioning_;
  colony::DifferentialSteering wheels_;
  FakeLeds leds_;
  FakeRabActuator rab_actuator_;
  std::vector<std::string> sensor_labels_ = {"proximity", "ground", "omnidirectional_camera",
                                             "range_and_bearing", "positioning"};
  std::vector<std::string> actuator_labels_ = {"differential_steering", "leds",
                                               "range_and_bearing"};
  std::vector<colony::Sensor*> sensors_;
  std::vector<colony::Actuator*> actuators_;
  colony::DeviceLabels labels_;
  colony::DeviceTable table_;
};

TEST_F(HostTest, WheelSpeedsGoFromCmPerSecondToMetresPerSecondUnclamped) {
  ProbeController::on_step = [](ProbeController& c) {
    c.GetActuator<CCI_DifferentialSteeringActuator>("differential_steering")
        ->SetLinearVelocity(5, -100);
  };
  auto host = Start();
  host->ControlStep();
  EXPECT_DOUBLE_EQ(wheels_.target_left(), 0.05);
  // 1 m/s is beyond the foot-bot: the layer passes it on; the actuator
  // deals with it.
  EXPECT_DOUBLE_EQ(wheels_.target_right(), -1.0);
}

TEST_F(HostTest, ArgosSensorNamesFindColonyDevicesAndReadingsAreFreshEachStep) {
  std::vector<Real> seen;
  ProbeController::on_step = [&](ProbeController& c) {
    const auto& r = c.GetSensor<CCI_FootBotProximitySensor>("footbot_proximity")->GetReadings();
    ASSERT_EQ(r.size(), 24u);
    seen.push_back(r[3].Value);
    EXPECT_NEAR(r[3].Angle.GetValue(), 3.5 * ARGOS_PI / 12, 1e-6);
  };
  auto host = Start();
  host->ControlStep();
  proximity_.values[3] = 1.0f;
  host->ControlStep();
  EXPECT_EQ(seen, (std::vector<Real>{0.0, 1.0}));
}

TEST_F(HostTest, RangeAndBearingInCentimetresWithPayload) {
  const uint8_t payload[] = {1, 2, 3, 4};
  rab_sensor_.set().push_back({0.5f, 0.25f, 0.0f, std::span<const uint8_t>(payload, 4)});
  ProbeController::on_step = [](ProbeController& c) {
    const auto& packets =
        c.GetSensor<CCI_RangeAndBearingSensor>("range_and_bearing")->GetReadings();
    ASSERT_EQ(packets.size(), 1u);
    EXPECT_NEAR(packets[0].Range, 50, 1e-4);
    EXPECT_NEAR(packets[0].HorizontalBearing.GetValue(), 0.25, 1e-7);
    ASSERT_EQ(packets[0].Data.Size(), 4u);
    EXPECT_EQ(packets[0].Data[2], 3);
    auto* emitter = c.GetActuator<CCI_RangeAndBearingActuator>("range_and_bearing");
    emitter->SetData(1, 42);
    EXPECT_THROW(emitter->SetData(4, 1), CARGoSException);
    EXPECT_THROW(emitter->SetData(CByteArray(5)), CARGoSException);
  };
  auto host = Start();
  host->ControlStep();
  EXPECT_EQ(rab_actuator_.data(), (std::vector<uint8_t>{0, 42, 0, 0}));
}

TEST_F(HostTest, CameraSeesNothingUntilEnabledThenDistancesInCentimetres) {
  camera_.set().push_back({255, 0, 0, 0.3f, -0.5f});
  size_t blobs_before = 99;
  ProbeController::on_step = [&](ProbeController& c) {
    auto* camera = c.GetSensor<CCI_ColoredBlobOmnidirectionalCameraSensor>(
        "colored_blob_omnidirectional_camera");
    if (blobs_before == 99) {
      blobs_before = camera->GetReadings().BlobList.size();
      camera->Enable();
      return;
    }
    const auto& readings = camera->GetReadings();
    ASSERT_EQ(readings.BlobList.size(), 1u);
    EXPECT_EQ(readings.BlobList[0]->Color, CColor::RED);
    EXPECT_NEAR(readings.BlobList[0]->Distance, 30, 1e-4);
    EXPECT_NEAR(readings.BlobList[0]->Angle.GetValue(), -0.5, 1e-7);
    EXPECT_EQ(readings.Counter, 1u);
  };
  auto host = Start();
  host->ControlStep();
  host->ControlStep();
  EXPECT_EQ(blobs_before, 0u);
}

TEST_F(HostTest, GroundSensorsInArgosOrder) {
  // Dark in front of the robot, light behind.
  ground_.set()[0].value = 0.0f;
  ground_.set()[4].value = 0.6f;
  ProbeController::on_step = [](ProbeController& c) {
    const auto& motor =
        c.GetSensor<CCI_FootBotMotorGroundSensor>("footbot_motor_ground")->GetReadings();
    ASSERT_EQ(motor.size(), 4u);
    EXPECT_EQ(motor[0].Value, 0.0);          // front-left
    EXPECT_NEAR(motor[1].Value, 0.6, 1e-6);  // back-left
    EXPECT_NEAR(motor[2].Value, 0.6, 1e-6);  // back-right
    EXPECT_EQ(motor[3].Value, 0.0);          // front-right
    EXPECT_EQ(motor[2].Offset, CVector2(-6.3, -1.16));
    const auto& base =
        c.GetSensor<CCI_FootBotBaseGroundSensor>("footbot_base_ground")->GetReadings();
    ASSERT_EQ(base.size(), 8u);
    EXPECT_EQ(base[0].Value, 0.0);
    EXPECT_EQ(base[4].Value, 1.0);  // 0.6 is light
  };
  auto host = Start();
  host->ControlStep();
}

TEST_F(HostTest, PositioningInMetresWithHeadingQuaternion) {
  positioning_.Set(1.5, -2, 0.75);
  ProbeController::on_step = [](ProbeController& c) {
    const auto& reading = c.GetSensor<CCI_PositioningSensor>("positioning")->GetReading();
    EXPECT_EQ(reading.Position, CVector3(1.5, -2, 0));
    CRadians z, y, x;
    reading.Orientation.ToEulerAngles(z, y, x);
    EXPECT_NEAR(z.GetValue(), 0.75, 1e-12);
  };
  auto host = Start();
  host->ControlStep();
}

TEST_F(HostTest, LedsBeyondTheLastThrow) {
  ProbeController::on_step = [](ProbeController& c) {
    auto* leds = c.GetActuator<CCI_LEDsActuator>("leds");
    EXPECT_EQ(leds->GetNumLEDs(), 13u);
    leds->SetSingleColor(12, CColor::RED);
    EXPECT_THROW(leds->SetSingleColor(13, CColor::RED), CARGoSException);
  };
  auto host = Start();
  host->ControlStep();
  EXPECT_EQ(leds_.colors()[12], (colony::Color{255, 0, 0, 255}));
  EXPECT_EQ(leds_.colors()[11], (colony::Color{0, 0, 0, 255}));
}

TEST_F(HostTest, WrongTypeOrUndeclaredDeviceThrowsNamingIt) {
  ProbeController::on_init = [](ProbeController& c, TConfigurationNode&) {
    try {
      c.GetSensor<CCI_FootBotProximitySensor>("positioning");
      ADD_FAILURE() << "a positioning sensor passed for a proximity sensor";
    } catch (const CARGoSException& e) {
      EXPECT_NE(std::string(e.what()).find("cannot be cast to type argos::CCI_FootBotProximity"),
                std::string::npos)
          << e.what();
    }
    try {
      c.GetSensor<CCI_FootBotProximitySensor>("footbot_light");
      ADD_FAILURE() << "an undeclared sensor was found";
    } catch (const CARGoSException& e) {
      EXPECT_NE(std::string(e.what()).find("Unknown sensor type footbot_light"), std::string::npos)
          << e.what();
    }
    EXPECT_TRUE(c.HasSensor("footbot_proximity"));
    EXPECT_FALSE(c.HasActuator("footbot_gripper"));
  };
  Start();
}

TEST_F(HostTest, MissingParameterBecomesAColonyParameterError) {
  ProbeController::on_init = [](ProbeController&, TConfigurationNode& node) {
    try {
      Real speed;
      GetNodeAttribute(GetNode(node, "wheel_turning"), "max_speed", speed);
    } catch (CARGoSException& e) {
      THROW_ARGOSEXCEPTION_NESTED("Error initializing controller wheel turning parameters.", e);
    }
  };
  colony::Params params;
  params.Set("wheel_turning.max_sped", "10");
  try {
    Start(params);
    FAIL();
  } catch (const colony::ParamError& e) {
    EXPECT_EQ(e.key(), "wheel_turning.max_speed");
  }
}

TEST_F(HostTest, RandomDrawsComeFromTheRobotsStream) {
  std::vector<UInt32> draws;
  ProbeController::on_init = [&](ProbeController&, TConfigurationNode&) {
    CRandom::CRNG* rng = CRandom::CreateRNG("argos");
    for (int i = 0; i < 5; ++i) draws.push_back(rng->Uniform(CRange<UInt32>(0, 1000)));
    rng->Reset();
    EXPECT_EQ(rng->Uniform(CRange<UInt32>(0, 1000)), draws[0]);
    EXPECT_THROW(CRandom::CreateRNG("mine"), CARGoSException);
  };
  Start({}, 7);
  const auto first = draws;
  draws.clear();
  Start({}, 7);
  EXPECT_EQ(draws, first);
  draws.clear();
  Start({}, 8);
  EXPECT_NE(draws, first);
  for (UInt32 d : first) EXPECT_LT(d, 1000u);
  EXPECT_THROW(CRandom::CreateRNG("argos"), CARGoSException);  // outside any robot's code
}

TEST_F(HostTest, LogLinesAreWrittenWholeAndUnreadParametersWarnedOnce) {
  ProbeController::on_init = [](ProbeController& c, TConfigurationNode& node) {
    Real velocity;
    GetNodeAttribute(node, "velocity", velocity);
    LOG << "robot " << c.GetId() << " speed " << velocity << " cm/s " << UInt8(7) << std::endl;
    LOGERR << "left unfinished";
  };
  colony::Params params;
  params.Set("velocity", "5");
  params.Set("state.food_rule.active", "true");
  testing::internal::CaptureStderr();
  Start(params);
  Start(params);  // the second robot of the same configuration: no second warning
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("colony: info: robot fb0 speed 5 cm/s 7\n"), std::string::npos) << err;
  EXPECT_NE(err.find("colony: error: left unfinished\n"), std::string::npos) << err;
  const std::string warning = "does not read parameter 'state.food_rule.active' (ignored)";
  const size_t first = err.find(warning);
  EXPECT_NE(first, std::string::npos) << err;
  EXPECT_EQ(err.find(warning, first + 1), std::string::npos) << err;
  EXPECT_NE(err.find("ProbeController"), std::string::npos) << err;
  // Colony sees every parameter as read: it reports none as unknown.
  EXPECT_TRUE(params.Unread().empty());
}

TEST(Argos3Random, DistributionsHaveTheirMeans) {
  CRandom::CRNG rng(3);
  const int n = 20000;
  double gauss = 0, expo = 0, poisson_small = 0, poisson_large = 0, heads = 0;
  for (int i = 0; i < n; ++i) {
    gauss += rng.Gaussian(2, 10);
    expo += rng.Exponential(4);
    poisson_small += rng.Poisson(3);
    poisson_large += rng.Poisson(100);
    heads += rng.Bernoulli(0.25);
  }
  EXPECT_NEAR(gauss / n, 10, 0.1);
  EXPECT_NEAR(expo / n, 4, 0.15);
  EXPECT_NEAR(poisson_small / n, 3, 0.05);
  EXPECT_NEAR(poisson_large / n, 100, 0.5);
  EXPECT_NEAR(heads / n, 0.25, 0.02);
}

}  // namespace
