// Foraging: the controller and the loop functions share this class (they are
// built into one library, libforaging.so): the loop functions, which own the
// items, tell a robot's controller when it picked one up or delivered it.
#pragma once

#include "actuators/differential_steering/differential_steering.h"
#include "actuators/leds/leds.h"
#include "controllers/common/steering.h"
#include "core/control_interface.h"
#include "sensors/ground/ground.h"
#include "sensors/light/light.h"

namespace colony::foraging {

// A robot that searches the source area (dark floor) for items and carries
// each one to the nest (under the light). See foraging.cpp for the rule.
class ForagingController : public Controller {
 public:
  void Init(const Params& params) override;
  void ControlStep() override;

  // Called by the foraging loop functions before the control step: the robot
  // now carries an item (it passed over one) or no longer does (delivered).
  void SetCarrying(bool carrying) { carrying_ = carrying; }
  bool carrying() const { return carrying_; }

 private:
  double velocity_ = 0, source_grey_ = 0, avoidance_ = 0;
  bool carrying_ = false;
  swarm::RandomWalk walk_;
  swarm::ObstacleVector obstacles_;
  const GroundSensor* ground_ = nullptr;
  const LightSensor* light_ = nullptr;
  DifferentialSteering* wheels_ = nullptr;
  Leds* leds_ = nullptr;
};

}  // namespace colony::foraging
