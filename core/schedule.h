// When a device that runs at its own rate acts in a simulation of fixed
// ticks: a sensor sampled every `period` seconds (<proximity period="0.015">),
// a controller stepped `rate` times a second (<controllers><x rate="25">).
//
// The rule (docs/experiment-files.md, "Sampling periods and controller
// rates"): with P = period / tick length (in ticks, >= 1) and a phase of
// F ticks (>= 0, < P), run k (k = 0, 1, 2, ...) happens on tick
//     floor(F + k P) + 1
// (ticks numbered from 1, as Simulation::tick() reads after the step), that
// is on the first tick that starts at or after the time F + k P ticks. So
// 67 Hz (P = 200 / 67 = 2.985) at 200 ticks/s runs on ticks 1, 3, 6, 9, ...,
// 198, 201, ...: 67 runs a second, 3 ticks apart but for one gap of 2 ticks a
// second; a period of 15 ms (P = 3) runs on ticks 1, 4, 7, ...: every third
// tick exactly. P and F within 1e-9 of a whole number are taken as that
// number, so 0.015 s / 0.005 s counts as 3 ticks, not 2.9999999999999996.
#pragma once

#include <cmath>
#include <cstdint>

namespace colony {

class Schedule {
 public:
  Schedule() = default;  // every tick
  // `period_ticks` >= 1; `phase_ticks` in [0, period_ticks).
  Schedule(double period_ticks, double phase_ticks)
      : period_(Snap(period_ticks)), phase_(Snap(phase_ticks)), next_(TickOf(0)) {}

  bool every_tick() const { return period_ == 1 && phase_ == 0; }
  double period_ticks() const { return period_; }
  // Whether the device runs on `tick` (asked for every tick, in order).
  bool Due(uint64_t tick) {
    if (tick < next_) return false;
    next_ = TickOf(++runs_);
    return true;
  }
  // The tick of run k.
  uint64_t TickOf(uint64_t k) const {
    return static_cast<uint64_t>(std::floor(phase_ + static_cast<double>(k) * period_ + 1e-9)) + 1;
  }

  // A whole number when `ticks` is within 1e-9 (relative) of one.
  static double Snap(double ticks) {
    const double whole = std::round(ticks);
    return std::abs(ticks - whole) <= 1e-9 * std::max(1.0, std::abs(ticks)) ? whole : ticks;
  }

 private:
  double period_ = 1, phase_ = 0;
  uint64_t runs_ = 0, next_ = 1;
};

}  // namespace colony
