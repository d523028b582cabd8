// The range-and-bearing medium: the messages robots broadcast this tick,
// indexed by where their senders are. The range-and-bearing actuator stages
// each robot's payload here during the act step (tick step 1); Update (step
// 3, after physics) files every message by its sender's position in a
// uniform grid; receivers (the range-and-bearing sensor, step 5) read the
// cells around them. See media/range_and_bearing/README.md.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

#include "core/medium.h"
#include "core/space.h"
#include "media/cell_grid.h"
#include "media/occlusion.h"

namespace colony {

// Where an entity's range-and-bearing device sits: on its vertical axis, at
// mid-height of its body (marXbot: 7.35 cm above the floor). Senders and
// receivers alike.
inline Vec3 RangeAndBearingPoint(const Space& space, uint32_t slot) {
  const Pose& p = space.pose(slot);
  return p.position + p.orientation * Vec3(0, 0, 0.5 * space.geometry(slot).height());
}

class RangeAndBearingMedium : public Medium {
 public:
  static constexpr double kDefaultRange = 3.0;  // m

  void Configure(const ConfigNode& node) override;
  void Update() override;

  bool check_occlusions() const { return check_occlusions_; }
  // Range of senders whose actuator sets none (m).
  double default_range() const { return range_; }

  // --- Senders (the actuator). One emitter per actuator instance.
  uint32_t AddEmitter(EntityHandle robot, double range, size_t data_size);
  void RemoveEmitter(uint32_t emitter);
  // Stages what `emitter` sends this tick: `size` bytes as given at
  // AddEmitter, or nothing (sending false). Called from the act step in
  // parallel chunks; each emitter writes only its own bytes.
  void Stage(uint32_t emitter, bool sending, const uint8_t* data) {
    const Emitter& e = emitters_[emitter];
    staged_sending_[emitter] = sending;
    if (!sending) return;
    uint8_t* to = staged_data_.data() + e.data_offset;
    if (e.data_size <= 16) {
      for (uint32_t i = 0; i < e.data_size; ++i) to[i] = data[i];  // a call to memcpy costs more
    } else {
      std::memcpy(to, data, e.data_size);
    }
  }

  // --- The index, rebuilt by Update; read by receivers until the next Update.
  // A message as receivers read it: where its sender is, the square of its
  // range (a float: the range limit holds to 1e-7 relative), who sent it and
  // where its payload is. Read for every candidate of every query, so 32
  // bytes, two per cache line, and nothing else to read for a message that
  // is received but its payload (whose size sits just before its bytes).
  struct Message {
    double x, y;
    float z;
    float range2;
    uint32_t slot;  // the sender's slot in the space
    uint32_t data;  // offset of its payload in the payload copy
  };
  size_t message_count() const { return messages_.size(); }
  const Message* messages() const { return messages_.data(); }
  const uint8_t* payload_bytes() const { return payload_.data(); }
  std::span<const uint8_t> payload(const Message& m) const {
    uint32_t size;
    std::memcpy(&size, payload_.data() + m.data - sizeof size, sizeof size);
    return {payload_.data() + m.data, size};
  }
  // The largest range of this tick's messages (m): no sender farther away
  // than this can be heard.
  double max_range() const { return max_range_; }

  // Calls visit(begin, end) for runs [begin, end) of message indices that
  // together hold every message whose sender lies within `reach`
  // horizontally of (x, y) (and others near it). Runs come in a fixed order:
  // grid rows, then cells, then senders in emitter order.
  template <class Visit>
  void ForEachCandidateRun(double x, double y, double reach, Visit&& visit) const {
    if (messages_.empty()) return;
    grid_.ForEachRun(x, y, reach, visit);
  }

  double cell_size() const { return grid_.cell_size(); }
  // The solid bodies, rebuilt with the index when occlusions are checked.
  const OccluderGrid& occluders() const { return occluders_; }

 private:
  struct Emitter {
    EntityHandle robot;
    double range = 0;
    uint32_t data_offset = 0;
    uint32_t data_size = 0;
    bool alive = true;
  };

  // Settings.
  bool check_occlusions_ = true;
  double range_ = kDefaultRange;
  double cell_size_ = 0;  // 0: the largest range of the tick's messages

  // Staging, by emitter (written during the act step).
  std::vector<Emitter> emitters_;
  std::vector<uint8_t> staged_sending_;
  // Each emitter's payload, preceded by its size (4 bytes, native order).
  std::vector<uint8_t> staged_data_;

  // The index. Messages are sorted by grid cell (cells row by row), so the
  // candidates of a query are a few contiguous runs, one per grid row.
  std::vector<Message> messages_;
  std::vector<uint8_t> payload_;  // a copy of staged_data_ taken at Update
  CellGrid grid_;
  std::vector<uint32_t> active_;   // emitters sending this tick
  std::vector<uint32_t> cell_of_;  // per active emitter
  std::vector<Message> unsorted_;  // per active emitter
  double max_range_ = 0;
  OccluderGrid occluders_;
};

}  // namespace colony
