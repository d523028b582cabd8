#include "core/component.h"

#include <deque>
#include <mutex>
#include <stdexcept>

namespace colony {
namespace {

struct ComponentNames {
  std::mutex mutex;
  std::deque<std::string> names;  // by type id; a deque keeps references valid
};
ComponentNames& Names() {
  static ComponentNames names;
  return names;
}

}  // namespace

ComponentType ComponentTypeNamed(std::string_view name) {
  ComponentNames& table = Names();
  std::lock_guard lock(table.mutex);
  for (size_t i = 0; i < table.names.size(); ++i) {
    if (table.names[i] == name) return static_cast<ComponentType>(i);
  }
  if (table.names.size() >= 0xFFFF) throw std::length_error("too many component types");
  table.names.emplace_back(name);
  return static_cast<ComponentType>(table.names.size() - 1);
}

const std::string& ComponentName(ComponentType type) {
  ComponentNames& table = Names();
  std::lock_guard lock(table.mutex);
  return table.names.at(type);
}

}  // namespace colony
