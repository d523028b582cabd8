// The threshold watches of one sensor instance (Sensor::Watch) and the
// events they emitted since the host last took them. A sensor simulation
// that emits events keeps one of these per instance, allocated only when
// its controller first calls Watch (most instances never do), and calls
// Check after each sample.
#pragma once

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/control_interface.h"

namespace colony {

class ThresholdWatches {
 public:
  // Adds a watch over a sensor of `count` readings whose values now are
  // value(i). Throws std::invalid_argument naming what is wrong.
  template <class Value>
  int Add(const ThresholdWatch& watch, int count, Value value) {
    if (watch.reading < -1 || watch.reading >= count) {
      throw std::invalid_argument("Watch: reading " + std::to_string(watch.reading) +
                                  " does not exist; this sensor has readings 0.." +
                                  std::to_string(count - 1) + " (or -1: each of them)");
    }
    if (!std::isfinite(watch.threshold))
      throw std::invalid_argument("Watch: the threshold must be a finite number");
    if (!(watch.hysteresis >= 0) || !std::isfinite(watch.hysteresis))
      throw std::invalid_argument("Watch: the hysteresis must be a finite number >= 0");
    const int id = static_cast<int>(watches_.size());
    const int first = watch.reading < 0 ? 0 : watch.reading;
    const int last = watch.reading < 0 ? count - 1 : watch.reading;
    for (int i = first; i <= last; ++i) {
      watches_.push_back({watch, id, i, value(i) >= watch.threshold});
    }
    return id;
  }

  // After a sample: records an event for each watched reading that crossed.
  template <class Value>
  void Check(const Sensor* sensor, Value value) {
    for (Entry& w : watches_) {
      const double v = value(w.reading);
      const ThresholdWatch& spec = w.spec;
      if (!w.above && v >= spec.threshold) {
        w.above = true;
        if (spec.crossing != Crossing::kFalling)
          pending_.push_back({sensor, w.id, w.reading, v, true});
      } else if (w.above && v < spec.threshold - spec.hysteresis) {
        w.above = false;
        if (spec.crossing != Crossing::kRising)
          pending_.push_back({sensor, w.id, w.reading, v, false});
      }
    }
  }

  // Moves the events recorded since the last call to the end of `out`.
  void Take(std::vector<SensorEvent>& out) {
    out.insert(out.end(), pending_.begin(), pending_.end());
    pending_.clear();
  }

 private:
  struct Entry {
    ThresholdWatch spec;
    int id;
    int reading;
    bool above;
  };
  std::vector<Entry> watches_;
  std::vector<SensorEvent> pending_;
};

}  // namespace colony
