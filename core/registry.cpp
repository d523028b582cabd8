#include "core/registry.h"

#include <algorithm>
#include <cstdlib>

#include "core/control_interface.h"
#include "core/device.h"
#include "core/engine.h"
#include "core/entity_type.h"
#include "core/loop_functions.h"
#include "core/text.h"

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
// "a , b" -> "a,b": declared lists of numbers may be spaced.
std::string WithoutSpaces(std::string text) {
  std::erase(text, ' ');
  return text;
}

// Whether a declared default says what the getter's does.
bool SameDefault(const std::string& declared, const Params::Default& asked) {
  switch (asked.kind) {
    case Params::Default::kRequired:  // "" or prose: "required when task is bridge"
      return declared.empty() || declared.find("required") != std::string::npos;
    case Params::Default::kText:
      return WithoutSpaces(declared) == WithoutSpaces(asked.text);
    case Params::Default::kNumber: {
      // A default that is not a plain number ("velocity / 2") is prose: not compared.
      char* end = nullptr;
      const double value = std::strtod(declared.c_str(), &end);
      if (declared.empty() || *end != '\0') return !declared.empty();
      return value == std::strtod(asked.text.c_str(), nullptr);
    }
  }
  return false;
}
}  // namespace

std::vector<std::string> UndeclaredParamReads(const PluginInfo& controller, const Params& params) {
  std::vector<std::string> problems;
  if (controller.attributes.empty()) return problems;
  const auto names = controller.AttributeNames();
  if (std::find(names.begin(), names.end(), "*") != names.end()) return problems;
  const std::string who = "controller '" + controller.label + "'";
  for (const auto& key : params.Asked()) {
    if (std::find(names.begin(), names.end(), key) != names.end()) continue;
    problems.push_back(
        who + " reads parameter '" + key +
        "', which it does not declare (COLONY_REGISTER_CONTROLLER); it declares: " + Join(names));
  }
  for (const auto& asked : params.Defaults()) {
    for (const auto& a : controller.attributes) {
      if (a.name != asked.key || SameDefault(a.default_value, asked)) continue;
      const std::string given =
          asked.kind == Params::Default::kRequired ? "as required" : "with default " + asked.text;
      problems.push_back(
          who + " reads parameter '" + a.name + "' " + given + ", but declares it " +
          (a.default_value.empty() ? "required" : "with default " + a.default_value));
    }
  }
  return problems;
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
