// ARGoS compatibility layer (Colony): CRange<T>, a closed interval [min, max]
// of numbers, angles or vectors. Read from XML as "min:max".
#pragma once

#include <cmath>
#include <iostream>
#include <sstream>
#include <string>
#include <type_traits>

#include "argos3/core/utility/datatypes/datatypes.h"
#include "argos3/core/utility/math/general.h"

namespace argos {

template <typename T>
class CRange {
 public:
  CRange(const T& min = T(), const T& max = T()) : min_(min), max_(max), span_(max - min) {}

  T GetMin() const { return min_; }
  void SetMin(const T& min) {
    min_ = min;
    span_ = max_ - min_;
  }
  T GetMax() const { return max_; }
  void SetMax(const T& max) {
    max_ = max;
    span_ = max_ - min_;
  }
  T GetSpan() const { return span_; }
  void Set(const T& min, const T& max) {
    min_ = min;
    max_ = max;
    span_ = max_ - min_;
  }

  bool WithinMinBoundIncludedMaxBoundIncluded(const T& value) const {
    return min_ <= value && value <= max_;
  }
  bool WithinMinBoundIncludedMaxBoundExcluded(const T& value) const {
    return min_ <= value && value < max_;
  }
  bool WithinMinBoundExcludedMaxBoundIncluded(const T& value) const {
    return min_ < value && value <= max_;
  }
  bool WithinMinBoundExcludedMaxBoundExcluded(const T& value) const {
    return min_ < value && value < max_;
  }

  // Clamps `value` into the range.
  void TruncValue(T& value) const {
    if (value > max_) value = max_;
    if (value < min_) value = min_;
  }
  // Where `value` (clamped into the range) lies: 0 at min, 1 at max.
  Real NormalizeValue(const T& value) const {
    T clamped(value);
    TruncValue(clamped);
    if constexpr (std::is_arithmetic_v<T>) {
      return static_cast<Real>(clamped - min_) / static_cast<Real>(span_);
    } else {
      return (clamped - min_) / span_;
    }
  }
  // Maps `input` from this range linearly onto `range`.
  template <typename U>
  void MapValueIntoRange(U& output, const T& input, const CRange<U>& range) const {
    output = static_cast<U>(range.GetMin() + NormalizeValue(input) * range.GetSpan());
  }
  // Brings `value` into the range by adding or subtracting whole spans
  // (angles: 370 degrees in [-180, 180] is 10). A value already inside is
  // left as it is.
  void WrapValue(T& value) const {
    if (WithinMinBoundIncludedMaxBoundIncluded(value)) return;
    if constexpr (std::is_floating_point_v<T>) {
      value = min_ + std::fmod(value - min_, span_);
      if (value < min_) value += span_;
    } else {
      while (value > max_) value = value - span_;
      while (value < min_) value = value + span_;
    }
  }

  friend std::ostream& operator<<(std::ostream& os, const CRange& range) {
    return os << range.min_ << ":" << range.max_;
  }
  // Reads "min:max".
  friend std::istream& operator>>(std::istream& is, CRange& range) {
    std::string text;
    is >> text;
    const size_t colon = text.find(':', 1);
    if (colon == std::string::npos) {
      is.setstate(std::ios::failbit);
      return is;
    }
    std::istringstream min_text(text.substr(0, colon)), max_text(text.substr(colon + 1));
    T min{}, max{};
    if (!(min_text >> min) || !(max_text >> max) || !(min_text >> std::ws).eof() ||
        !(max_text >> std::ws).eof()) {
      is.setstate(std::ios::failbit);
      return is;
    }
    range.Set(min, max);
    return is;
  }

 private:
  T min_;
  T max_;
  T span_;
};

}  // namespace argos
