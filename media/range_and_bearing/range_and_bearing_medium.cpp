#include "media/range_and_bearing/range_and_bearing_medium.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/simulation.h"

namespace colony {

void RangeAndBearingMedium::Configure(const ConfigNode& node) {
  check_occlusions_ = node.GetBool("check_occlusions", true);
  range_ = node.GetDouble("range", kDefaultRange, Range::Positive());
  cell_size_ = node.GetDouble("cell_size", 0, Range::Positive());
}

uint32_t RangeAndBearingMedium::AddEmitter(EntityHandle robot, double range, size_t data_size) {
  Emitter e;
  e.robot = robot;
  e.range = range;
  const uint32_t size = static_cast<uint32_t>(data_size);
  e.data_offset = static_cast<uint32_t>(staged_data_.size() + sizeof size);
  e.data_size = size;
  emitters_.push_back(e);
  staged_sending_.push_back(0);
  staged_data_.resize(staged_data_.size() + sizeof size + data_size, 0);
  std::memcpy(staged_data_.data() + e.data_offset - sizeof size, &size, sizeof size);
  return static_cast<uint32_t>(emitters_.size() - 1);
}

void RangeAndBearingMedium::RemoveEmitter(uint32_t emitter) {
  emitters_[emitter].alive = false;
  staged_sending_[emitter] = 0;
}

void RangeAndBearingMedium::Update() {
  const Space& space = sim().space();
  // The messages of this tick: staged by a live sender.
  active_.clear();
  max_range_ = 0;
  for (uint32_t e = 0; e < emitters_.size(); ++e) {
    const Emitter& em = emitters_[e];
    if (!staged_sending_[e] || !em.alive || !space.IsAlive(em.robot)) continue;
    active_.push_back(e);
    max_range_ = std::max(max_range_, em.range);
  }
  grid_.Configure(space, cell_size_ > 0 ? cell_size_ : (max_range_ > 0 ? max_range_ : range_),
                  active_.size());

  // Counting sort by cell, stable in emitter order: positions are computed
  // once into unsorted_ (in parallel), then scattered.
  const size_t n = active_.size();
  unsorted_.resize(n);
  cell_of_.resize(n);
  sim().pool().ParallelFor(n, 2048, [&](size_t b, size_t e) {
    for (size_t k = b; k < e; ++k) {
      const Emitter& em = emitters_[active_[k]];
      const Vec3 p = RangeAndBearingPoint(space, em.robot.index);
      unsorted_[k] = {p.x(),
                      p.y(),
                      static_cast<float>(p.z()),
                      static_cast<float>(em.range * em.range),
                      em.robot.index,
                      em.data_offset};
      cell_of_[k] = grid_.CellOf(p.x(), p.y());
    }
  });
  grid_.Sort(unsorted_, cell_of_, n, messages_);
  // The payloads as they are now: the actuators overwrite the staging area
  // next tick while receivers may still hold spans into this copy.
  payload_.assign(staged_data_.begin(), staged_data_.end());
  if (check_occlusions_ && n > 0) occluders_.Build(space, grid_.cell_size());
}

COLONY_REGISTER_MEDIUM(
    RangeAndBearingMedium, "range_and_bearing",
    "carries range-and-bearing messages: each robot's payload reaches the receivers within its "
    "range, "
    "with the sender's distance and bearing; blocked by solid bodies unless check_occlusions is "
    "false",
    (std::vector<AttributeDoc>{
        {"check_occlusions", "true, false", "true",
         "a solid body between sender and receiver (other than those two) blocks the message"},
        {"range", "a number > 0 (m)", "3", "range of senders whose actuator sets none"},
        {"cell_size", "a number > 0 (m)", "the largest range of the tick's messages",
         "side of the index's grid cells (a speed knob: which messages are received does not "
         "depend on it, "
         "their order does)"},
    }));

}  // namespace colony
