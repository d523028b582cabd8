// Proximity sensors (control interface): a ring of short-range IR sensors.
// On the marXbot: 24 sensors, 15 degrees apart, 6 cm above the floor.
#pragma once

#include <bit>
#include <compare>
#include <cstddef>
#include <cstdint>
#include <iterator>

#include "core/control_interface.h"

namespace colony {

class ProximitySensor : public Sensor {
 public:
  struct Reading {
    float value;  // 0: nothing in range; rises as an object nears; 1: touching (within 1 cm)
    float angle;  // direction of the sensor in the robot's frame, counter-clockwise from the front
                  // (rad)
  };
  class Readings;
  // One reading per sensor, in ring order. Reading them is a poll of the
  // ring, counted on the robot's bus when it has bus accounting (docs/events.md).
  // The view stays valid as long as the robot (the values live in one array
  // of the simulated sensor's, the angles in one list per ring, shared by
  // every robot that has it).
  Readings readings() const;
  bool TakeRead() override {
    const bool read = read_;
    read_ = false;
    return read;
  }
  // Watch (Sensor::Watch): events when a reading's value crosses a
  // threshold; `reading` is the sensor's index in ring order.

 protected:
  // The robot's values and its ring's angles, `count_` of each.
  float* values_ = nullptr;
  const float* angles_ = nullptr;
  uint32_t count_ = 0;

 private:
  mutable bool read_ = false;  // readings() was called since TakeRead
};

// The readings of one ring, as a random-access range of Reading (by value):
// index it, loop over it, take its size(); copy it into a
// std::vector<Reading> to keep it past the robot. Only the values are the
// robot's own: a ring's angles are the same for every robot that has it.
class ProximitySensor::Readings {
 public:
  class Iterator {
   public:
    using iterator_concept = std::random_access_iterator_tag;
    using iterator_category = std::input_iterator_tag;  // operator* returns a value
    using value_type = Reading;
    using difference_type = std::ptrdiff_t;
    using reference = Reading;

    Iterator() = default;
    Iterator(const float* value, const float* angle) : value_(value), angle_(angle) {}
    Reading operator*() const { return {*value_, *angle_}; }
    Reading operator[](difference_type n) const { return {value_[n], angle_[n]}; }
    Iterator& operator++() { return *this += 1; }
    Iterator operator++(int) {
      Iterator was = *this;
      ++*this;
      return was;
    }
    Iterator& operator--() { return *this -= 1; }
    Iterator operator--(int) {
      Iterator was = *this;
      --*this;
      return was;
    }
    Iterator& operator+=(difference_type n) {
      value_ += n;
      angle_ += n;
      return *this;
    }
    Iterator& operator-=(difference_type n) { return *this += -n; }
    friend Iterator operator+(Iterator it, difference_type n) { return it += n; }
    friend Iterator operator+(difference_type n, Iterator it) { return it += n; }
    friend Iterator operator-(Iterator it, difference_type n) { return it -= n; }
    friend difference_type operator-(const Iterator& a, const Iterator& b) {
      return a.value_ - b.value_;
    }
    friend bool operator==(const Iterator& a, const Iterator& b) { return a.value_ == b.value_; }
    friend auto operator<=>(const Iterator& a, const Iterator& b) { return a.value_ <=> b.value_; }

   private:
    const float* value_ = nullptr;
    const float* angle_ = nullptr;
  };

  Readings() = default;
  Readings(const float* values, const float* angles, size_t size)
      : values_(values), angles_(angles), size_(size) {}
  size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  Reading operator[](size_t i) const { return {values_[i], angles_[i]}; }
  Reading front() const { return (*this)[0]; }
  Reading back() const { return (*this)[size_ - 1]; }
  Iterator begin() const { return {values_, angles_}; }
  Iterator end() const { return {values_ + size_, angles_ + size_}; }
  // Whether every value is 0 (nothing in range of any sensor, as for most
  // robots of a sparse swarm): the bits of all values but their signs, or'ed
  // together (one vectorized pass; a NaN is not 0).
  bool AllZero() const {
    uint32_t bits = 0;
    for (size_t i = 0; i < size_; ++i) bits |= std::bit_cast<uint32_t>(values_[i]) << 1;
    return bits == 0;
  }

 private:
  const float* values_ = nullptr;
  const float* angles_ = nullptr;
  size_t size_ = 0;
};

inline ProximitySensor::Readings ProximitySensor::readings() const {
  read_ = true;
  return {values_, angles_, count_};
}

}  // namespace colony
