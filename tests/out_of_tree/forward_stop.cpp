// Drives forwards and stops for good once a front proximity sensor reads
// more than 0.5 (an obstacle within 2 cm); lights its LEDs red when stopped.
#include <colony/actuators/differential_steering/differential_steering.h>
#include <colony/actuators/leds/leds.h>
#include <colony/core/registry.h>
#include <colony/sensors/proximity/proximity.h>

#include <cmath>

class ForwardStop : public colony::Controller {
 public:
  void Init(const colony::Params& params) override {
    speed_ = params.GetDouble("speed", 0.1, 0, 0.3);
    proximity_ = &GetSensor<colony::ProximitySensor>("proximity");
    wheels_ = &GetActuator<colony::DifferentialSteering>("differential_steering");
    leds_ = &GetActuator<colony::Leds>("leds");
  }
  void ControlStep() override {
    for (const auto& r : proximity_->readings()) {
      if (std::abs(r.angle) < 0.5 && r.value > 0.5) stopped_ = true;
    }
    wheels_->SetLinearVelocity(stopped_ ? 0 : speed_, stopped_ ? 0 : speed_);
    leds_->SetAllColors(stopped_ ? colony::Color{255, 0, 0, 255} : colony::Color{0, 0, 255, 255});
  }

 private:
  double speed_ = 0;
  bool stopped_ = false;
  const colony::ProximitySensor* proximity_ = nullptr;
  colony::DifferentialSteering* wheels_ = nullptr;
  colony::Leds* leds_ = nullptr;
};

COLONY_REGISTER_CONTROLLER(ForwardStop, "forward_stop",
                           "drive forwards, stop in front of an obstacle",
                           {{"speed", "a number in [0, 0.3] (m/s)", "0.1", "forward speed"}});
