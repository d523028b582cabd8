#include "core/registry.h"

#include "core/control_interface.h"
#include "core/device.h"
#include "core/engine.h"
#include "core/entity_type.h"
#include "core/loop_functions.h"

namespace colony {

const char* PluginKindName(PluginKind kind) {
  switch (kind) {
    case PluginKind::kEntity:
      return "entity";
    case PluginKind::kEngine:
      return "engine";
    case PluginKind::kPhysicsModel:
      return "physics_model";
    case PluginKind::kSensor:
      return "sensor";
    case PluginKind::kActuator:
      return "actuator";
    case PluginKind::kMedium:
      return "medium";
    case PluginKind::kRenderer:
      return "renderer";
    case PluginKind::kController:
      return "controller";
    case PluginKind::kLoopFunctions:
      return "loop_functions";
  }
  return "?";
}

std::vector<PluginKind> AllPluginKinds() {
  return {PluginKind::kEntity,   PluginKind::kEngine,     PluginKind::kPhysicsModel,
          PluginKind::kSensor,   PluginKind::kActuator,   PluginKind::kMedium,
          PluginKind::kRenderer, PluginKind::kController, PluginKind::kLoopFunctions};
}

std::vector<std::string> PluginInfo::AttributeNames() const {
  std::vector<std::string> names;
  for (const auto& a : attributes) names.push_back(a.name);
  return names;
}

namespace {
std::vector<const PluginInfo*>& Plugins() {
  static std::vector<const PluginInfo*> plugins;
  return plugins;
}
std::string& LoadingLibrary() {
  static std::string library;
  return library;
}
}  // namespace

const std::vector<const PluginInfo*>& AllPlugins() { return Plugins(); }

void RecordPlugin(const PluginInfo* info) {
  const_cast<PluginInfo*>(info)->library = LoadingLibrary();
  Plugins().push_back(info);
}

void SetLoadingLibrary(const std::string& path) { LoadingLibrary() = path; }

template <class Base>
Registry<Base>& Registry<Base>::Get() {
  static Registry<Base> registry;
  return registry;
}

template class Registry<Controller>;
template class Registry<LoopFunctions>;
template class Registry<EntityType>;
template class Registry<PhysicsEngine>;
template class Registry<PhysicsModel>;
template class Registry<SensorSystem>;
template class Registry<ActuatorSystem>;
template class Registry<Medium>;
template class Registry<Renderer>;

}  // namespace colony
