// Aggregation: probabilistic aggregation after Jeanson et al. (2005), as
// swarm robotics uses it. A robot is walking or staying; it shows which in
// byte 0 of its range-and-bearing payload (1 = staying) and with its LEDs
// (green walking, red staying). Every tick it counts n, the staying robots it
// hears within `sense_range`, then:
//   - walking: it stops with probability
//       p_join(n) = join_spontaneous + join_max (1 - exp(-join_slope n)),
//     which rises with n; otherwise it walks on: straight ahead, turning on
//     the spot for 1..turn_ticks ticks with probability turn_probability per
//     tick, and away from whatever its proximity ring sees in front;
//   - staying: it leaves with probability
//       p_leave(n) = leave_max exp(-leave_slope n),
//     which falls with n, and then walks at least leave_ticks ticks before it
//     may stop again (so that it gets away from the group it left).
// Probabilities are per control step (per tick).
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "actuators/leds/leds.h"
#include "actuators/range_and_bearing/range_and_bearing.h"
#include "controllers/common/steering.h"
#include "core/registry.h"
#include "sensors/range_and_bearing/range_and_bearing.h"

namespace {

constexpr colony::Color kWalking{0, 255, 0, 255};
constexpr colony::Color kStaying{255, 0, 0, 255};

class Aggregation : public colony::Controller {
 public:
  void Init(const colony::Params& params) override {
    velocity_ = params.GetDouble("velocity", 0.15, 0, 0.3);
    sense_range_ = params.GetDouble("sense_range", 0.5, 0, 100);
    join_spontaneous_ = params.GetDouble("join_spontaneous", 0.002, 0, 1);
    join_max_ = params.GetDouble("join_max", 0.3, 0, 1);
    join_slope_ = params.GetDouble("join_slope", 1, 0, 1e3);
    leave_max_ = params.GetDouble("leave_max", 0.2, 0, 1);
    leave_slope_ = params.GetDouble("leave_slope", 3, 0, 1e3);
    leave_ticks_ = static_cast<int>(params.GetInt("leave_ticks", 50, 0, 1000000));
    walk_.Configure(velocity_, params.GetDouble("turn_probability", 0.01, 0, 1),
                    static_cast<int>(params.GetInt("turn_ticks", 20, 1, 1000000)));
    if (join_spontaneous_ + join_max_ > 1) {
      throw colony::ParamError("join_max", params.GetString("join_max", ""),
                               "parameter 'join_max': join_spontaneous + join_max must be <= 1 "
                               "(a probability)");
    }
    obstacles_.Bind(GetSensor<colony::ProximitySensor>("proximity"));
    receiver_ = &GetSensor<colony::RangeAndBearingSensor>("range_and_bearing");
    emitter_ = &GetActuator<colony::RangeAndBearingActuator>("range_and_bearing");
    wheels_ = &GetActuator<colony::DifferentialSteering>("differential_steering");
    leds_ = &GetActuator<colony::Leds>("leds");
  }

  void ControlStep() override {
    int n = 0;
    for (const auto& packet : receiver_->packets()) {
      n += packet.range <= sense_range_ && !packet.data.empty() && packet.data[0] == 1;
    }
    if (staying_) {
      if (rng().Bernoulli(leave_max_ * std::exp(-leave_slope_ * n))) {
        staying_ = false;
        cooldown_ = leave_ticks_;
      }
    } else if (cooldown_ > 0) {
      --cooldown_;
    } else if (rng().Bernoulli(join_spontaneous_ + join_max_ * (1 - std::exp(-join_slope_ * n)))) {
      staying_ = true;
    }
    emitter_->SetByte(0, staying_ ? 1 : 0);
    leds_->SetAllColors(staying_ ? kStaying : kWalking);
    if (staying_) {
      wheels_->SetLinearVelocity(0, 0);
    } else {
      walk_.Step(obstacles_.Read(), rng(), *wheels_);
    }
  }

 private:
  double velocity_ = 0, sense_range_ = 0, join_spontaneous_ = 0, join_max_ = 0, join_slope_ = 0,
         leave_max_ = 0, leave_slope_ = 0;
  int leave_ticks_ = 0;
  bool staying_ = false;
  int cooldown_ = 0;
  colony::swarm::RandomWalk walk_;
  colony::swarm::ObstacleVector obstacles_;
  const colony::RangeAndBearingSensor* receiver_ = nullptr;
  colony::RangeAndBearingActuator* emitter_ = nullptr;
  colony::DifferentialSteering* wheels_ = nullptr;
  colony::Leds* leds_ = nullptr;
};

COLONY_REGISTER_CONTROLLER(
    Aggregation, "aggregation",
    "probabilistic aggregation: walk, stop with a probability rising with the staying neighbours "
    "heard through range-and-bearing, leave with one falling with them",
    {{"velocity", "0..0.3 (m/s)", "0.15", "walking speed"},
     {"sense_range", "0..100 (m)", "0.5", "staying robots heard within this range count"},
     {"join_spontaneous", "0..1", "0.002", "p_join(0)"},
     {"join_max", "0..1", "0.3",
      "p_join rises by up to this; join_spontaneous + join_max must be <= 1"},
     {"join_slope", "0..1000", "1", "how fast p_join rises with n"},
     {"leave_max", "0..1", "0.2", "p_leave(0)"},
     {"leave_slope", "0..1000", "3", "how fast p_leave falls with n"},
     {"leave_ticks", "0..1e6", "50", "ticks of walking after leaving before it may stop again"},
     {"turn_probability", "0..1", "0.01", "chance per tick of a random turn"},
     {"turn_ticks", "1..1e6", "20", "longest random turn (ticks)"}});

}  // namespace
