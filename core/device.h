// Simulated sensors and actuators (plugin kinds "sensor" and "actuator").
// One system object exists per (controller configuration, device element);
// it owns the instances of every robot using that configuration and updates
// them all in one batch, in parallel chunks, instead of one virtual call per
// robot. Each instance is the control-interface object the controller reads.
#pragma once

#include <algorithm>
#include <cstddef>
#include <memory>
#include <new>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "core/config.h"
#include "core/control_interface.h"
#include "core/huge_pages.h"
#include "core/noise.h"
#include "core/registry.h"
#include "core/simulation_bound.h"
#include "core/space.h"

namespace colony {

class PhysicsEngine;

class Simulation;

// A robot cannot carry a device (e.g. it has no proximity ring).
class AttachError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Bookkeeping every instance carries besides its control interface.
// A device that never draws random numbers (or draws them only with noise
// configured, keeping its streams aside) derives from this one and spares
// each robot a 32-byte stream.
struct InstanceBaseWithoutStream {
  EntityHandle robot;
  bool alive = true;
};
struct InstanceBase : InstanceBaseWithoutStream {
  RandomStream rng;
};

// Small arrays of many robots (device tables, readings) carved from shared
// blocks, with stable addresses: a heap array per robot costs malloc's
// header and rounding, and a call to malloc at load. T is trivially
// copyable; what Take returns is value-initialised.
template <class T>
class ArrayBlocks {
 public:
  std::span<T> Take(size_t n) {
    if (n == 0) return {};
    if (blocks_.empty() || used_ + n > size_) {
      // Past kSmallBlocks blocks (a big swarm), blocks of 8 MB on huge pages
      // (core/huge_pages.h); memory is touched only as it is taken.
      const bool large = blocks_.size() >= kSmallBlocks;
      size_ = std::max<size_t>(n, large ? kLargeBytes / sizeof(T) : kBlock);
      blocks_.push_back(std::make_unique_for_overwrite<T[]>(size_));
      if (large) AdviseHugePages(blocks_.back().get(), size_ * sizeof(T));
      used_ = 0;
    }
    used_ += n;
    T* taken = blocks_.back().get() + used_ - n;
    std::fill_n(taken, n, T{});
    return {taken, n};
  }

 private:
  static_assert(std::is_trivially_copyable_v<T>);
  static constexpr size_t kBlock = 4096, kSmallBlocks = 256, kLargeBytes = size_t{8} << 20;
  std::vector<std::unique_ptr<T[]>> blocks_;
  size_t used_ = 0, size_ = 0;
};

// Instances with stable addresses (controllers keep pointers to them), in
// blocks of kBlock: the first from malloc, touched only as instances are
// added; the next ones (swarms of more than kBlock robots) aligned on and
// advised for huge pages (core/huge_pages.h).
template <class Instance>
class InstanceStore {
 public:
  InstanceStore() = default;
  InstanceStore(const InstanceStore&) = delete;
  InstanceStore& operator=(const InstanceStore&) = delete;
  ~InstanceStore() {
    for (size_t i = 0; i < size_; ++i) (*this)[i].~Instance();
    for (size_t b = 0; b < blocks_.size(); ++b)
      ::operator delete (blocks_[b], std::align_val_t{AlignmentOf(b)});
  }

  Instance& Add(EntityHandle robot, const RandomStream& rng) {
    if (size_ == blocks_.size() * kBlock) {
      const size_t b = blocks_.size();
      blocks_.reserve(b + 1);
      void* block = ::operator new (kBlock * sizeof(Instance), std::align_val_t{AlignmentOf(b)});
      if (b > 0) AdviseHugePages(block, kBlock * sizeof(Instance));
      blocks_.push_back(static_cast<Instance*>(block));
    }
    Instance& item = *::new (static_cast<void*>(blocks_.back() + size_ % kBlock)) Instance();
    ++size_;
    item.robot = robot;
    if constexpr (std::is_base_of_v<InstanceBase, Instance>) {
      item.rng = rng;
    } else {
      (void)rng;
    }
    return item;
  }
  void Remove(const void* interface) {
    for (size_t i = 0; i < size_; ++i) {
      auto& item = (*this)[i];
      if (static_cast<const void*>(static_cast<const typename Instance::Interface*>(&item)) ==
          interface) {
        item.alive = false;
      }
    }
  }
  size_t size() const { return size_; }
  Instance& operator[](size_t i) { return blocks_[i / kBlock][i % kBlock]; }
  const Instance& operator[](size_t i) const { return blocks_[i / kBlock][i % kBlock]; }

 private:
  static constexpr size_t kBlock = size_t{1} << 15;
  static constexpr size_t kHugePage = size_t{2} << 20;
  static constexpr size_t AlignmentOf(size_t block) {
    return block > 0 ? kHugePage : std::max(alignof(Instance), alignof(std::max_align_t));
  }
  std::vector<Instance*> blocks_;
  size_t size_ = 0;
};

class SensorSystem : public SimulationBound {
 public:
  virtual ~SensorSystem() = default;
  // Reads the sensor's element in a controller's <sensors>.
  virtual void Configure(const ConfigNode& node) = 0;
  // Adds the instance for `robot`; throws AttachError if it cannot carry it.
  virtual Sensor* Attach(EntityHandle robot, const RandomStream& rng) = 0;
  virtual void Detach(Sensor* instance) = 0;
  virtual size_t size() const = 0;
  // Updates instances [begin, end) from the space; chunks run in parallel.
  virtual void Update(size_t begin, size_t end) = 0;
  // Adds what controllers read to the state hash.
  virtual void Hash(StateHasher& h) const { (void)h; }
  // Events (Sensor::Watch): whether a controller asked an instance for
  // events (the host takes them only then), and moving the events
  // `instance` emitted since the last call to the end of `out`.
  virtual bool HasWatches() const { return false; }
  virtual void TakeEvents(Sensor* instance, std::vector<SensorEvent>& out) {
    (void)instance;
    (void)out;
  }
  // Bus accounting (<sensor bus="true">, docs/events.md): the number of
  // values one poll of `instance` carries on the robot's bus (C in the
  // seed's formula), or 0 when this sensor has no bus model.
  virtual size_t BusValues(const Sensor* instance) const {
    (void)instance;
    return 0;
  }
  // The components (core/component.h) of the robot this device reads or
  // writes, e.g. {"gripper"}. The host checks, before Attach and whenever the
  // robot migrates into another engine's region, that the robot carries
  // them and that its engine's model simulates them (core/simulation.cpp:
  // AttachController, Migrate).
  virtual std::vector<std::string> NeededComponents() const { return {}; }
  // Memory one robot's instance holds beyond a few hundred bytes (an image,
  // a scan), in bytes: the loader adds it to its memory estimate before
  // creating robots (core/bounds.h).
  virtual size_t BytesPerRobot() const { return 0; }
};

class ActuatorSystem : public SimulationBound {
 public:
  virtual ~ActuatorSystem() = default;
  virtual void Configure(const ConfigNode& node) = 0;
  virtual Actuator* Attach(EntityHandle robot, const RandomStream& rng) = 0;
  virtual void Detach(Actuator* instance) = 0;
  virtual size_t size() const = 0;
  // Writes the commands of instances [begin, end) into the space.
  virtual void Act(size_t begin, size_t end) = 0;
  // The components (core/component.h) of the robot this device reads or
  // writes, e.g. {"gripper"}. The host checks, before Attach and whenever the
  // robot migrates into another engine's region, that the robot carries
  // them and that its engine's model simulates them (core/simulation.cpp:
  // AttachController, Migrate).
  virtual std::vector<std::string> NeededComponents() const { return {}; }
  // As SensorSystem::BytesPerRobot (a message payload, its copies in a medium).
  virtual size_t BytesPerRobot() const { return 0; }
};

}  // namespace colony
