// Sensor noise, declared the same way on every sensor:
//   noise="none|gaussian|uniform" noise_std_dev="0.01" noise_range="-0.01,0.01"
//   drop_probability="0.05"
// Each sensor instance draws from its own random stream.
#pragma once

#include <algorithm>
#include <vector>

#include "core/config.h"
#include "core/random.h"
#include "core/registry.h"

namespace colony {

struct NoiseModel {
  enum class Kind { kNone, kGaussian, kUniform };
  Kind kind = Kind::kNone;
  double std_dev = 0;
  double min = 0, max = 0;
  double drop_probability = 0;

  // The attributes above, to append to a sensor's registered attributes.
  // with_drop: whether the sensor can lose readings (drop_probability).
  static std::vector<AttributeDoc> Attributes(bool with_drop = true);
  static NoiseModel Read(const ConfigNode& node);

  bool enabled() const { return kind != Kind::kNone || drop_probability > 0; }
  // `value` with noise added.
  double Apply(double value, RandomStream& rng) const {
    switch (kind) {
      case Kind::kNone:
        return value;
      case Kind::kGaussian:
        return value + rng.Gaussian(0, std_dev);
      case Kind::kUniform:
        return value + rng.Uniform(min, max);
    }
    return value;
  }
  // `value` (a distance, a force: never negative) with noise added, and at
  // least 0.
  double ApplyNonNegative(double value, RandomStream& rng) const {
    return std::max(0.0, Apply(value, rng));
  }
  // Whether this reading is lost.
  bool Drop(RandomStream& rng) const {
    return drop_probability > 0 && rng.Bernoulli(drop_probability);
  }
};

}  // namespace colony
