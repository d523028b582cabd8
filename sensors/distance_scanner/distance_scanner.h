// Rotating distance scanner (control interface): Sharp infrared distance
// sensors on a continuously turning rotor. On the marXbot: 4 sensors, 90
// degrees apart, alternately short range (4-30 cm) and long range
// (20-150 cm), so each type covers 360 degrees every half turn of the rotor
// (one "scan"). Distances are what the robot computes from each sensor's
// voltage, so an object nearer than a sensor's minimum range reads as a wrong,
// larger distance, as on the real robot (see the README for the curves).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/control_interface.h"

namespace colony {

class DistanceScanner : public Sensor {
 public:
  enum SensorType : uint8_t { kShortRange = 0, kLongRange = 1 };
  // The distance of a reading with nothing in range.
  static constexpr float kNoReading = -1.0f;

  struct Reading {
    float
        angle;  // direction of the ray in the robot's frame, ccw from the front, in (-pi, pi] (rad)
    float distance;   // from the robot's axis to what the sensor saw (m), or kNoReading
    uint8_t sensor;   // which sensor on the rotor: 0..3, at rotor angle + sensor x 90 degrees
    SensorType type;  // sensors 0 and 2 are short range, 1 and 3 long range
  };

  // The readings taken during the last tick, in the order they were taken
  // (for each sample instant, sensors 0..3). About 60 samples per second per
  // sensor: 24 readings per tick at 10 ticks per second.
  const std::vector<Reading>& readings() const { return readings_; }

  // The last complete scan of one sensor type: one distance per angle bin,
  // bin i looking at i x bin_width() ccw from the robot's front (as the robot
  // was when that reading was taken), kNoReading where nothing was in range.
  // All bins of a scan were read during the same half turn. Before the first
  // complete scan every bin is kNoReading.
  const std::vector<float>& scan(SensorType type) const { return scans_[type]; }
  // Angle between two bins (rad): 3 degrees at 1 scan/s, 6 at 2 scans/s.
  double bin_width() const { return bin_width_; }
  // Complete scans so far; it grows by one every 1 / scans_per_second seconds.
  uint64_t scans_completed() const { return scans_completed_; }
  // Angle of the rotor (of sensor 0) from the robot's front at the last sample, in [0, 2 pi) (rad).
  double rotor_angle() const { return rotor_angle_; }

 protected:
  std::vector<Reading> readings_;
  std::array<std::vector<float>, 2> scans_;
  double bin_width_ = 0;
  uint64_t scans_completed_ = 0;
  double rotor_angle_ = 0;
};

}  // namespace colony
