// Plugin registries. One registry per plugin kind (entity, engine, physics
// model, sensor, actuator, medium, renderer, controller, loop functions),
// filled by a registration macro placed in the plugin's .cpp. Each entry
// carries its label, implementation, a one-line summary and the XML
// attributes it accepts; `colony query` prints them, so the XML reference is
// generated from the code.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace colony {

enum class PluginKind {
  kEntity,
  kEngine,
  kPhysicsModel,
  kSensor,
  kActuator,
  kMedium,
  kRenderer,
  kController,
  kLoopFunctions,
};
const char* PluginKindName(PluginKind kind);  // "sensor", "loop_functions"...
std::vector<PluginKind> AllPluginKinds();

// One XML attribute a plugin accepts (for controllers: one <params>
// attribute; the name "*" accepts any).
struct AttributeDoc {
  std::string name;
  std::string accepted;       // "a number > 0 (metres)"
  std::string default_value;  // empty when required
  std::string summary;
};

// What a controller sees of a sensor or actuator: the control-interface
// header it includes, the C++ class it asks for (GetSensor<T> /
// GetActuator<T>), and the members it reads or calls, each with its units
// ("readings(): one Reading per sensor: value (0..1), angle (rad)").
struct DeviceInterface {
  std::string header;     // "sensors/proximity/proximity.h"
  std::string cpp_class;  // "colony::ProximitySensor"
  std::vector<std::string> members;
};

struct PluginInfo {
  PluginInfo(PluginKind kind, std::string label, std::string implementation, std::string summary,
             std::vector<AttributeDoc> attributes = {}, std::vector<std::string> aliases = {},
             std::vector<std::string> components = {})
      : kind(kind),
        label(std::move(label)),
        implementation(std::move(implementation)),
        summary(std::move(summary)),
        attributes(std::move(attributes)),
        aliases(std::move(aliases)),
        components(std::move(components)) {}
  PluginKind kind = PluginKind::kEntity;
  std::string label;           // the XML element name
  std::string implementation;  // "default" unless a plugin has several
  std::string summary;
  std::vector<AttributeDoc> attributes;
  std::vector<std::string> aliases;  // other accepted element names
  // Physics models: the components (core/component.h) they simulate.
  std::vector<std::string> components;
  // Sensors and actuators: what a controller includes, uses and reads.
  DeviceInterface control_interface;
  std::string library;  // filled in when loaded from a shared library
  std::vector<std::string> AttributeNames() const;
};

// A sensor's or actuator's PluginInfo: its control interface comes after the
// summary (COLONY_REGISTER_SENSOR and COLONY_REGISTER_ACTUATOR require it).
inline PluginInfo DevicePluginInfo(PluginKind kind, std::string label, std::string implementation,
                                   std::string summary, DeviceInterface control_interface,
                                   std::vector<AttributeDoc> attributes = {},
                                   std::vector<std::string> aliases = {}) {
  PluginInfo info(kind, std::move(label), std::move(implementation), std::move(summary),
                  std::move(attributes), std::move(aliases));
  info.control_interface = std::move(control_interface);
  return info;
}

class Params;
// What a controller that declares its parameters (PluginInfo::attributes)
// did wrong in reading `params` during Init: each read of a parameter it did
// not declare, and each declared default that differs from the default its
// getter gave, one sentence each naming the controller ("controller
// 'diffusion' reads parameter 'gain', which it does not declare; it declares:
// alpha, delta, velocity"). Empty when it declares none or a "*".
std::vector<std::string> UndeclaredParamReads(const PluginInfo& controller, const Params& params);

// Kind-independent view of all registered plugins (for `colony query`).
const std::vector<const PluginInfo*>& AllPlugins();
void RecordPlugin(const PluginInfo* info);
// The library being loaded right now (the loader sets it around dlopen).
void SetLoadingLibrary(const std::string& path);

template <class Base>
class Registry {
 public:
  using Factory = std::unique_ptr<Base> (*)();
  struct Entry {
    PluginInfo info;
    Factory create;
  };

  static Registry& Get();

  const Entry& Add(PluginInfo info, Factory create) {
    entries_.push_back(std::make_unique<Entry>(Entry{std::move(info), create}));
    RecordPlugin(&entries_.back()->info);
    return *entries_.back();
  }
  // The entry with `label` (or alias) and `implementation` ("" = any / the only one).
  const Entry* Find(std::string_view label, std::string_view implementation = "") const {
    for (const auto& e : entries_) {
      bool name_matches = e->info.label == label;
      for (const auto& alias : e->info.aliases) name_matches = name_matches || alias == label;
      if (name_matches && (implementation.empty() || e->info.implementation == implementation)) {
        return e.get();
      }
    }
    return nullptr;
  }
  std::vector<std::string> Labels() const {
    std::vector<std::string> out;
    for (const auto& e : entries_) {
      out.push_back(e->info.label);
      for (const auto& a : e->info.aliases) out.push_back(a);
    }
    return out;
  }
  std::vector<std::string> Implementations(std::string_view label) const {
    std::vector<std::string> out;
    for (const auto& e : entries_)
      if (e->info.label == label) out.push_back(e->info.implementation);
    return out;
  }

 private:
  std::vector<std::unique_ptr<Entry>> entries_;
};

template <class Base>
struct Registrar {
  Registrar(PluginInfo info, typename Registry<Base>::Factory create) {
    Registry<Base>::Get().Add(std::move(info), create);
  }
};

class Controller;
class LoopFunctions;
class EntityType;
class PhysicsEngine;
class PhysicsModel;
class SensorSystem;
class ActuatorSystem;
class Medium;
class Renderer;

#define COLONY_PLUGIN_CONCAT2(a, b) a##b
#define COLONY_PLUGIN_CONCAT(a, b) COLONY_PLUGIN_CONCAT2(a, b)
#define COLONY_REGISTER_PLUGIN_(BASE, KIND, CLASS, ...)                                     \
  static const ::colony::Registrar<BASE> COLONY_PLUGIN_CONCAT(colony_registrar_, __LINE__)( \
      ::colony::PluginInfo{KIND, __VA_ARGS__},                                              \
      []() -> std::unique_ptr<BASE> { return std::make_unique<CLASS>(); })
#define COLONY_REGISTER_DEVICE_(BASE, KIND, CLASS, ...)                                     \
  static const ::colony::Registrar<BASE> COLONY_PLUGIN_CONCAT(colony_registrar_, __LINE__)( \
      ::colony::DevicePluginInfo(KIND, __VA_ARGS__),                                        \
      []() -> std::unique_ptr<BASE> { return std::make_unique<CLASS>(); })

// COLONY_REGISTER_CONTROLLER(MyController, "my_controller", "summary",
//                            {{"param", "accepted", "default", "doc"}, ...});
// The list declares the <params> the controller reads, as loop functions do:
// `colony query` prints it, and a controller that declares any parameter
// fails to load when it reads one it did not declare, or reads a declared
// one with another default (so the list cannot drift from the code). A
// controller that declares none is not checked.
#define COLONY_REGISTER_CONTROLLER(CLASS, LABEL, SUMMARY, ...)                                   \
  COLONY_REGISTER_PLUGIN_(::colony::Controller, ::colony::PluginKind::kController, CLASS, LABEL, \
                          "default", SUMMARY __VA_OPT__(, ) __VA_ARGS__)
// COLONY_REGISTER_LOOP_FUNCTIONS(MyLoop, "my_loop", "summary", {{"param", "accepted", "default",
// "doc"}});
#define COLONY_REGISTER_LOOP_FUNCTIONS(CLASS, LABEL, SUMMARY, ...)                              \
  COLONY_REGISTER_PLUGIN_(::colony::LoopFunctions, ::colony::PluginKind::kLoopFunctions, CLASS, \
                          LABEL, "default", SUMMARY, __VA_ARGS__)
#define COLONY_REGISTER_ENTITY(CLASS, LABEL, SUMMARY, ATTRIBUTES, ALIASES)                   \
  COLONY_REGISTER_PLUGIN_(::colony::EntityType, ::colony::PluginKind::kEntity, CLASS, LABEL, \
                          "default", SUMMARY, ATTRIBUTES, ALIASES)
#define COLONY_REGISTER_ENGINE(CLASS, LABEL, SUMMARY, ...)                                      \
  COLONY_REGISTER_PLUGIN_(::colony::PhysicsEngine, ::colony::PluginKind::kEngine, CLASS, LABEL, \
                          "default", SUMMARY, __VA_ARGS__)
// Label "engine:entity", e.g. "kinematics2d:marxbot"; COMPONENTS, the
// components it simulates, e.g. (std::vector<std::string>{"drive", "gripper"}).
#define COLONY_REGISTER_PHYSICS_MODEL(CLASS, LABEL, SUMMARY, COMPONENTS)                      \
  COLONY_REGISTER_PLUGIN_(::colony::PhysicsModel, ::colony::PluginKind::kPhysicsModel, CLASS, \
                          LABEL, "default", SUMMARY, {}, {}, COMPONENTS)
// COLONY_REGISTER_SENSOR(MySystem, "my_sensor", "default", "summary",
//     ::colony::DeviceInterface{"sensors/my_sensor/my_sensor.h", "colony::MySensor",
//                               {"value(): ... (units)"}},
//     MyAttributes(), {"alias"});  (actuators likewise)
#define COLONY_REGISTER_SENSOR(CLASS, LABEL, IMPLEMENTATION, SUMMARY, ...)                     \
  COLONY_REGISTER_DEVICE_(::colony::SensorSystem, ::colony::PluginKind::kSensor, CLASS, LABEL, \
                          IMPLEMENTATION, SUMMARY, __VA_ARGS__)
#define COLONY_REGISTER_ACTUATOR(CLASS, LABEL, IMPLEMENTATION, SUMMARY, ...)                       \
  COLONY_REGISTER_DEVICE_(::colony::ActuatorSystem, ::colony::PluginKind::kActuator, CLASS, LABEL, \
                          IMPLEMENTATION, SUMMARY, __VA_ARGS__)

}  // namespace colony
