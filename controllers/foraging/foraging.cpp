// Foraging: robots carry items from a source area (dark floor) to a nest
// marked by a light. The rule, every tick:
//   - carrying an item: phototaxis, towards the sum of the light ring's
//     readings along their directions;
//   - not carrying, every ground sensor over the source (grey < source_grey):
//     random walk over it (straight ahead, turning on the spot for
//     1..turn_ticks ticks with probability turn_probability per tick);
//   - not carrying, some ground sensors over the source: towards those
//     sensors (back over the source from its edge);
//   - not carrying, none over the source: away from the light.
// To any of these it adds -avoidance x the proximity ring's vector. Its LEDs
// are green while searching and red while carrying. Picking up and
// delivering are the loop functions' business (foraging_loop_functions.cpp):
// they call SetCarrying when the robot passes over an item or enters the nest.
#include "controllers/foraging/foraging.h"

#include "core/registry.h"

namespace colony::foraging {

namespace {
constexpr Color kSearching{0, 255, 0, 255};
constexpr Color kCarrying{255, 0, 0, 255};
}  // namespace

void ForagingController::Init(const Params& params) {
  velocity_ = params.GetDouble("velocity", 0.15, 0, 0.3);
  source_grey_ = params.GetDouble("source_grey", 0.25, 0, 1);
  avoidance_ = params.GetDouble("avoidance", 5, 0, 1e6);
  walk_.Configure(velocity_, params.GetDouble("turn_probability", 0.05, 0, 1),
                  static_cast<int>(params.GetInt("turn_ticks", 20, 1, 1000000)));
  obstacles_.Bind(GetSensor<ProximitySensor>("proximity"));
  ground_ = &GetSensor<GroundSensor>("ground");
  light_ = &GetSensor<LightSensor>("light");
  wheels_ = &GetActuator<DifferentialSteering>("differential_steering");
  leds_ = &GetActuator<Leds>("leds");
}

void ForagingController::ControlStep() {
  leds_->SetAllColors(carrying_ ? kCarrying : kSearching);
  const swarm::Vector obstacle = obstacles_.Read();
  swarm::Vector light;
  for (const auto& r : light_->readings()) light += swarm::Vector::FromPolar(r.value, r.angle);

  swarm::Vector target;
  if (carrying_) {
    target = light;
  } else {
    swarm::Vector source;
    size_t over_source = 0;
    for (const auto& r : ground_->readings()) {
      if (r.value >= source_grey_) continue;
      source += swarm::Vector::FromPolar(1, r.angle);
      ++over_source;
    }
    if (over_source > 0 && over_source == ground_->readings().size()) {
      walk_.Step(obstacle, rng(), *wheels_);
      return;
    }
    target = over_source > 0 ? source : light * -1;
  }
  const double length = target.Length();
  if (length < 1e-9) {
    walk_.Step(obstacle, rng(), *wheels_);
    return;
  }
  swarm::Vector direction = target * (1 / length);
  direction += obstacle * -avoidance_;
  swarm::SteerTowards(direction.Angle(), velocity_, *wheels_);
}

COLONY_REGISTER_CONTROLLER(
    ForagingController, "foraging",
    "carry items from a dark source area to the nest under the light (items and deliveries by the "
    "foraging loop functions)",
    {{"velocity", "0..0.3 (m/s)", "0.15", "speed"},
     {"source_grey", "0..1", "0.25", "ground readings below this are the source"},
     {"avoidance", ">= 0", "5", "weight of the obstacle term"},
     {"turn_probability", "0..1", "0.05", "chance per tick of a random turn while over the source"},
     {"turn_ticks", "1..1e6", "20", "longest random turn (ticks)"}});

}  // namespace colony::foraging
