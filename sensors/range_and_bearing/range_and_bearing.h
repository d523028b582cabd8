// Range-and-bearing receiver (control interface): the messages robots within
// range sent during the last tick, each with where its sender is. On the
// marXbot an IR ring on top; in simulation a medium (media/range_and_bearing).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/control_interface.h"

namespace colony {

class RangeAndBearingSensor : public Sensor {
 public:
  struct Packet {
    float range;      // distance between the sender's and the receiver's centres (m)
    float bearing;    // horizontal direction of the sender in the receiver's frame, ccw from the
                      // front (rad, (-pi, pi])
    float elevation;  // vertical angle of the sender above the receiver's horizontal plane (rad)
    std::span<const uint8_t> data;  // the sender's payload; valid until the next tick
  };
  // Every message received this tick, in a deterministic order.
  const std::vector<Packet>& packets() const { return packets_; }

 protected:
  std::vector<Packet> packets_;
};

}  // namespace colony
