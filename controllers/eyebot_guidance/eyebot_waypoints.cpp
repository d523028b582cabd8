// eyebot_waypoints: an eye-bot flies from one random waypoint to the next, in
// position mode, inside a box of the arena (the flyers of the mixed-engines
// benchmark, experiments/benchmarks/mixed_11000.xml).
//   params: area ("x0,y0,z0,x1,y1,z1", m, where waypoints are drawn; default
//           -2,-2,1,2,2,2), reached (m, 0.1: how close counts as there)
#include <array>
#include <cmath>
#include <vector>

#include "actuators/eyebot_propulsion/eyebot_propulsion.h"
#include "core/registry.h"
#include "sensors/positioning/positioning.h"

namespace colony {
namespace {

class EyebotWaypoints : public Controller {
 public:
  void Init(const Params& params) override {
    const std::vector<double> area = params.GetNumbers("area", "-2,-2,1,2,2,2", 6);
    for (size_t i = 0; i < 6; ++i) area_[i] = area[i];
    if (area_[0] >= area_[3] || area_[1] >= area_[4] || area_[2] > area_[5]) {
      throw ParamError("area", params.GetString("area", ""),
                       "parameter 'area': x0 < x1, y0 < y1 and z0 <= z1 needed");
    }
    reached_ = params.GetDouble("reached", 0.1, 0.001, 100);
    position_ = &GetSensor<PositioningSensor>("positioning");
    rotors_ = &GetActuator<EyebotPropulsionActuator>("eyebot_propulsion");
    NextWaypoint();
  }

  void ControlStep() override {
    const double dx = position_->x() - waypoint_[0], dy = position_->y() - waypoint_[1],
                 dz = position_->z() - waypoint_[2];
    if (dx * dx + dy * dy + dz * dz < reached_ * reached_) NextWaypoint();
  }

 private:
  void NextWaypoint() {
    for (int i = 0; i < 3; ++i) waypoint_[i] = rng().Uniform(area_[i], area_[i + 3]);
    rotors_->SetTargetPosition(waypoint_[0], waypoint_[1], waypoint_[2]);
  }

  std::array<double, 6> area_{};
  std::array<double, 3> waypoint_{};
  double reached_ = 0;
  const PositioningSensor* position_ = nullptr;
  EyebotPropulsionActuator* rotors_ = nullptr;
};

COLONY_REGISTER_CONTROLLER(EyebotWaypoints, "eyebot_waypoints",
                           "an eye-bot flying from one random waypoint to the next",
                           {{"area", "\"x0,y0,z0,x1,y1,z1\" (m), x0 < x1, y0 < y1, z0 < z1",
                             "-2,-2,1,2,2,2", "the box the waypoints are drawn in"},
                            {"reached", "a number in [0.001, 100] (m)", "0.1",
                             "a waypoint this close is reached"}});

}  // namespace
}  // namespace colony
