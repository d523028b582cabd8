// Typed components: the state a kind of part gives an entity (a drive, a
// gripper, a manipulator, later an arm or a rope), kept by the space in one
// dense array per component type. An entity carries only the components it
// has: the space keeps a short list of (type, index) per entity, and nothing
// per entity for types it does not carry, so a wall costs no more whatever
// parts robots have.
//
// A component type is a plain struct with a name, registered on first use by
// whoever uses it (the plugin that owns it defines the struct in its header):
//
//   struct GripperState {
//     static constexpr const char* kComponentName = "gripper";
//     double turret = 0; ...
//     void Hash(StateHasher& h) const;  // optional: what the state hash sees
//   };
//
// Entity types list the components they give an entity in EntityInit's
// ComponentList; devices name the components they need and physics models
// the components they simulate (core/device.h, core/engine.h), and the host
// checks those against each other in one place (core/simulation.cpp).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/huge_pages.h"
#include "core/state_hash.h"

namespace colony {

using ComponentType = uint16_t;

// The id of the component type called `name`, registered on first use. Ids
// are process-wide, so every plugin sees the same id for a name.
ComponentType ComponentTypeNamed(std::string_view name);
const std::string& ComponentName(ComponentType type);

// The id of component type T: set when the program (or the plugin using T)
// is loaded, so reading it costs no check of whether it is set yet.
template <class T>
inline const ComponentType kComponentTypeOf = ComponentTypeNamed(T::kComponentName);
template <class T>
ComponentType ComponentTypeOf() {
  return kComponentTypeOf<T>;
}

// The dense array of one component type. Items stay where they were put
// (an entity's removal frees its item but does not move the others), so
// indexes stay valid and iteration order is the order of addition.
class ComponentPoolBase {
 public:
  static constexpr uint32_t kNoOwner = 0xFFFFFFFFu;
  virtual ~ComponentPoolBase() = default;
  virtual void HashItem(uint32_t index, StateHasher& h) const = 0;
  virtual size_t item_bytes() const = 0;
  // Space slot of the entity that owns item `index`, or kNoOwner.
  uint32_t owner(uint32_t index) const { return owners_[index]; }
  const std::vector<uint32_t>& owners() const { return owners_; }
  void Release(uint32_t index) { owners_[index] = kNoOwner; }

 protected:
  std::vector<uint32_t> owners_;
};

template <class T>
class ComponentPool final : public ComponentPoolBase {
 public:
  uint32_t Add(uint32_t owner, T value) {
    items_.push_back(std::move(value));
    owners_.push_back(owner);
    return static_cast<uint32_t>(items_.size() - 1);
  }
  // Room for `more` items beyond those there are (no doubling slack).
  void Reserve(size_t more) {
    items_.reserve(items_.size() + more);
    owners_.reserve(owners_.size() + more);
    AdviseHugePages(items_, Prefault::kInBackground);
    AdviseHugePages(owners_, Prefault::kInBackground);
  }
  T& operator[](uint32_t index) { return items_[index]; }
  const T& operator[](uint32_t index) const { return items_[index]; }
  size_t size() const { return items_.size(); }
  void HashItem(uint32_t index, StateHasher& h) const override {
    if constexpr (requires(const T& t) { t.Hash(h); }) items_[index].Hash(h);
  }
  size_t item_bytes() const override { return sizeof(T); }

 private:
  std::vector<T> items_;
};

class Space;

// The components an entity is made with, in the order they are added (the
// state hash sees them in that order). Copyable: a <distribute> template is
// copied for every robot it places.
class ComponentList {
 public:
  ComponentList() = default;
  ComponentList(const ComponentList& other) { *this = other; }
  ComponentList& operator=(const ComponentList& other) {
    if (this == &other) return *this;
    items_.clear();
    for (const auto& item : other.items_) items_.push_back(item->Clone());
    return *this;
  }
  ComponentList(ComponentList&&) = default;
  ComponentList& operator=(ComponentList&&) = default;

  // Adds a component of type T (or replaces the one there is) and returns it
  // for further setting.
  template <class T>
  T& Add(T value = T{}) {
    if (T* existing = Find<T>()) return *existing = std::move(value);
    auto item = std::make_unique<Item<T>>(std::move(value));
    T& ref = item->value;
    items_.push_back(std::move(item));
    return ref;
  }
  template <class T>
  T* Find() {
    for (auto& item : items_) {
      if (item->type() == ComponentTypeOf<T>()) return &static_cast<Item<T>&>(*item).value;
    }
    return nullptr;
  }
  template <class T>
  const T* Find() const {
    return const_cast<ComponentList*>(this)->Find<T>();
  }
  bool Has(ComponentType type) const {
    for (const auto& item : items_)
      if (item->type() == type) return true;
    return false;
  }
  size_t size() const { return items_.size(); }
  bool empty() const { return items_.empty(); }
  // Sum of the components' sizes (bytes), for memory estimates.
  size_t bytes() const {
    size_t total = 0;
    for (const auto& item : items_) total += item->bytes();
    return total;
  }

 private:
  friend class Space;
  struct ItemBase {
    virtual ~ItemBase() = default;
    virtual std::unique_ptr<ItemBase> Clone() const = 0;
    virtual ComponentType type() const = 0;
    virtual size_t bytes() const = 0;
    // Puts the value into the space's pool of its type, owned by `slot`;
    // returns its index there.
    virtual uint32_t AddTo(Space& space, uint32_t slot) const = 0;
    // Makes room in the space's pool of its type for `more` items.
    virtual void ReserveIn(Space& space, size_t more) const = 0;
  };
  template <class T>
  struct Item final : ItemBase {
    explicit Item(T v) : value(std::move(v)) {}
    std::unique_ptr<ItemBase> Clone() const override { return std::make_unique<Item<T>>(value); }
    ComponentType type() const override { return ComponentTypeOf<T>(); }
    size_t bytes() const override { return sizeof(T); }
    uint32_t AddTo(Space& space, uint32_t slot) const override;  // space.h
    void ReserveIn(Space& space, size_t more) const override;    // space.h
    T value;
  };
  std::vector<std::unique_ptr<ItemBase>> items_;
};

}  // namespace colony
