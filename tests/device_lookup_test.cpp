// A controller finds its devices by the label written in the experiment file
// or by the registered name it stands for (DeviceLabels), and a device it
// asks for that is not declared, or not of the type it asks for, is named.
#include "actuators/differential_steering/differential_steering.h"
#include "sensors/light/light.h"
#include "sensors/proximity/proximity.h"
#include "tests/test_util.h"

namespace colony {
namespace {

// The message of the std::logic_error `lookup` throws ("" when none).
template <class F>
std::string ErrorOf(F lookup) {
  try {
    lookup();
  } catch (const std::logic_error& e) {
    return e.what();
  }
  return "";
}

class LookupProbe : public Controller {
 public:
  void ControlStep() override {}
};
COLONY_REGISTER_CONTROLLER(LookupProbe, "lookup_probe", "test: finds its devices");

TEST(DeviceLookup, ByLabelOrRegisteredNameAndNamedWhenMissingOrOfAnotherType) {
  auto sim = testing::LoadXml(testing::Experiment(
      "<marxbot id=\"mb\"><body position=\"0,0,0\"/><controller config=\"p\"/></marxbot>",
      "<lookup_probe id=\"p\"><sensors><footbot_proximity/></sensors>"
      "<actuators><differential_steering/></actuators></lookup_probe>"));
  const Controller& c = *sim->ControllerOf(sim->space().Find("mb"));

  const DeviceLabels& labels = *c.devices().labels;
  EXPECT_EQ((*labels.sensor_labels)[0], "footbot_proximity");
  EXPECT_EQ(labels.SensorName(0), "proximity");
  EXPECT_EQ(labels.SensorIndex("footbot_proximity"), 0u);
  EXPECT_EQ(labels.SensorIndex("proximity"), 0u);
  EXPECT_EQ(labels.SensorIndex("light"), std::nullopt);
  EXPECT_EQ(labels.ActuatorName(0), "differential_steering");
  EXPECT_EQ(labels.ActuatorIndex("differential_steering"), 0u);
  EXPECT_EQ(labels.ActuatorIndex("footbot_proximity"), std::nullopt);

  EXPECT_EQ(&c.GetSensor<ProximitySensor>("footbot_proximity"),
            &c.GetSensor<ProximitySensor>("proximity"));
  EXPECT_EQ(&c.GetSensor<ProximitySensor>("proximity"), c.devices().sensors[0]);
  EXPECT_EQ(&c.GetActuator<DifferentialSteering>("differential_steering"),
            c.devices().actuators[0]);
  EXPECT_TRUE(testing::Mentions(ErrorOf([&] { c.GetSensor<LightSensor>("light"); }),
                                {"sensor 'light'", "not declared", "<sensors>"}));
  EXPECT_TRUE(testing::Mentions(ErrorOf([&] { c.GetSensor<LightSensor>("footbot_proximity"); }),
                                {"sensor 'footbot_proximity'", "not of the type"}));
  EXPECT_TRUE(testing::Mentions(ErrorOf([&] { c.GetActuator<DifferentialSteering>("leds"); }),
                                {"actuator 'leds'", "not declared", "<actuators>"}));
}

}  // namespace
}  // namespace colony
