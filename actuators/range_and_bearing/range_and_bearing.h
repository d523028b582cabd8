// Range-and-bearing emitter (control interface): the payload a robot
// broadcasts to every receiver within range, once per tick, until changed.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

#include "core/control_interface.h"

namespace colony {

class RangeAndBearingActuator : public Actuator {
 public:
  // Payload size in bytes (fixed by the experiment file).
  size_t size() const { return data_.size(); }
  // Sets the payload: copies min(size(), bytes.size()) bytes; the rest is zeroed.
  void SetData(std::span<const uint8_t> bytes) {
    const size_t n = std::min(bytes.size(), data_.size());
    if (n) std::memcpy(data_.data(), bytes.data(), n);
    std::fill(data_.begin() + static_cast<std::ptrdiff_t>(n), data_.end(), uint8_t{0});
    sending_ = true;
  }
  // Sets one byte (ignored beyond size()).
  void SetByte(size_t i, uint8_t value) {
    if (i < data_.size()) data_[i] = value;
    sending_ = true;
  }
  // Stops sending until SetData/SetByte is called again.
  void Clear() { sending_ = false; }
  const std::vector<uint8_t>& data() const { return data_; }
  bool sending() const { return sending_; }

 protected:
  std::vector<uint8_t> data_;
  bool sending_ = true;
};

}  // namespace colony
