#include "core/argos_compat.h"

#include <tinyxml2.h>

#include <cmath>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/log.h"
#include "core/registry.h"
#include "core/text.h"

namespace colony {
namespace {

// What a headless run leaves out, grouped for the one notice.
struct Ignored {
  std::map<std::string, std::vector<int>> items;  // "<qt-opengl>" -> lines
  void Add(const std::string& what, int line) { items[what].push_back(line); }
  std::string ToString() const {
    std::string out;
    for (const auto& [what, lines] : items) {
      if (!out.empty()) out += "; ";
      out += what + " (line" + (lines.size() > 1 ? "s " : " ");
      for (size_t i = 0; i < lines.size(); ++i) out += (i ? ", " : "") + std::to_string(lines[i]);
      out += ")";
    }
    return out;
  }
};

// ARGoS's visualisations: drawn in a window or a browser, never headless.
bool IsGuiSection(const std::string& name) {
  return name == "qt-opengl" || name == "webviz" || name == "lua_editor";
}

template <class System>
void AdaptDevice(tinyxml2::XMLElement* d, Ignored& ignored) {
  const std::string name = d->Name();
  if (d->Attribute("show_rays")) {
    d->DeleteAttribute("show_rays");
    ignored.Add("show_rays", d->GetLineNum());
  }
  // ARGoS names its implementations after how they are simulated
  // (rot_z_only, medium); Colony has one for each of these devices.
  if (const char* impl = d->Attribute("implementation")) {
    const auto& registry = Registry<System>::Get();
    if (registry.Find(name) && !registry.Find(name, impl)) d->DeleteAttribute("implementation");
  }
  // ARGoS's noise_level: uniform noise in [-level, level] added to each reading.
  if (const char* level = d->Attribute("noise_level")) {
    char* end = nullptr;
    const double v = std::strtod(level, &end);
    if (end != level && *end == '\0' && std::isfinite(v) && v >= 0 && !d->Attribute("noise")) {
      if (v > 0) {
        d->SetAttribute("noise", "uniform");
        d->SetAttribute("noise_range", (FormatNumber(-v) + "," + FormatNumber(v)).c_str());
      }
      d->DeleteAttribute("noise_level");
    }
    // Otherwise (not a number >= 0, or beside Colony's own noise attribute)
    // left as it is: the device reports it as an unknown attribute.
  }
  // ARGoS's LEDs name the medium that shows them; Colony's LED medium sees
  // every robot's LEDs.
  if (name == "leds" && d->Attribute("medium")) d->DeleteAttribute("medium");
}

void AdaptControllers(tinyxml2::XMLElement* controllers, Ignored& ignored) {
  if (!controllers) return;
  for (auto* c = controllers->FirstChildElement(); c; c = c->NextSiblingElement()) {
    if (auto* sensors = c->FirstChildElement("sensors")) {
      for (auto* d = sensors->FirstChildElement(); d; d = d->NextSiblingElement())
        AdaptDevice<SensorSystem>(d, ignored);
    }
    if (auto* actuators = c->FirstChildElement("actuators")) {
      for (auto* d = actuators->FirstChildElement(); d; d = d->NextSiblingElement())
        AdaptDevice<ActuatorSystem>(d, ignored);
    }
  }
}

// A device element of controller `config`'s <sensors> or <actuators> with
// element name `name` (or null).
tinyxml2::XMLElement* FindDevice(tinyxml2::XMLElement* root, const std::string& config,
                                 const char* section, const char* name) {
  auto* controllers = root->FirstChildElement("controllers");
  if (!controllers) return nullptr;
  for (auto* c = controllers->FirstChildElement(); c; c = c->NextSiblingElement()) {
    const char* id = c->Attribute("id");
    if (!id || config != id) continue;
    auto* s = c->FirstChildElement(section);
    return s ? s->FirstChildElement(name) : nullptr;
  }
  return nullptr;
}

// ARGoS sets some devices' figures on the robot (<foot-bot rab_range="3">);
// Colony on the device. Each moves to the device of the robot's controller.
struct RobotAttribute {
  const char* robot_attribute;
  const char* section;
  const char* device;
  const char* device_attribute;
};
constexpr RobotAttribute kRobotAttributes[] = {
    {"rab_range", "actuators", "range_and_bearing", "range"},
    {"rab_data_size", "actuators", "range_and_bearing", "data_size"},
    {"omnidirectional_camera_aperture", "sensors", "colored_blob_omnidirectional_camera",
     "aperture"},
};

void AdaptRobot(tinyxml2::XMLElement* root, tinyxml2::XMLElement* robot, const std::string& file) {
  const auto* controller = robot->FirstChildElement("controller");
  const char* config = controller ? controller->Attribute("config") : nullptr;
  for (const RobotAttribute& a : kRobotAttributes) {
    const char* value = robot->Attribute(a.robot_attribute);
    if (!value) continue;
    const std::string v = value;
    robot->DeleteAttribute(a.robot_attribute);
    tinyxml2::XMLElement* device = config ? FindDevice(root, config, a.section, a.device) : nullptr;
    if (!device) continue;  // the robot's controller does not use that device
    const char* set = device->Attribute(a.device_attribute);
    if (!set) {
      device->SetAttribute(a.device_attribute, v.c_str());
    } else if (v != set) {
      LogWarning(file + ":" + std::to_string(robot->GetLineNum()) + ": <" + robot->Name() + "> " +
                 a.robot_attribute + "=\"" + v + "\" differs from " + set +
                 ", set for controller '" + config + "' (line " +
                 std::to_string(device->GetLineNum()) + "); every robot of that controller uses " +
                 set);
    }
  }
}

void AdaptArena(tinyxml2::XMLElement* root, tinyxml2::XMLElement* e, const std::string& file) {
  for (auto* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
    const std::string name = c->Name();
    if (name == "foot-bot") AdaptRobot(root, c, file);
    if (name == "distribute" || name == "entity") AdaptArena(root, c, file);
  }
}

// ARGoS's media take the spatial index's layout (index="grid",
// grid_size="x,y,z"); Colony's media size their own.
void AdaptMedia(tinyxml2::XMLElement* media, Ignored& ignored) {
  if (!media) return;
  for (auto* m = media->FirstChildElement(); m; m = m->NextSiblingElement()) {
    for (const char* a : {"index", "grid_size"}) {
      if (!m->Attribute(a)) continue;
      m->DeleteAttribute(a);
      ignored.Add(std::string("<media> ") + a, m->GetLineNum());
    }
  }
}

// ARGoS's parameters nest (<params><wheel_turning max_speed="10"/></params>,
// <loop_functions ...><foraging items="15"/></loop_functions>); Colony's are
// the attributes of one <params>. Nested elements become dotted names
// (wheel_turning.max_speed="10"; an element with no attributes "name." = "");
// two siblings of one name cannot, and are an error.
void Flatten(const tinyxml2::XMLElement* e, const std::string& prefix, tinyxml2::XMLElement* params,
             const std::string& file, std::vector<Diagnostic>& errors) {
  std::map<std::string, int> seen;
  for (const auto* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
    const std::string name = prefix + c->Name();
    if (const auto [it, fresh] = seen.emplace(c->Name(), c->GetLineNum()); !fresh) {
      errors.push_back(Diagnostic{file, c->GetLineNum(), c->Name(), "", "",
                                  "a second <" + std::string(c->Name()) + "> (first at line " +
                                      std::to_string(it->second) +
                                      "): Colony gives parameters dotted names (" + name +
                                      ".attribute), so repeated elements cannot be told apart; "
                                      "accepted: one element of each name"});
      continue;
    }
    if (!c->FirstAttribute() && !c->FirstChildElement())
      params->SetAttribute((name + ".").c_str(), "");
    for (const auto* a = c->FirstAttribute(); a; a = a->Next())
      params->SetAttribute((name + "." + a->Name()).c_str(), a->Value());
    Flatten(c, name + ".", params, file, errors);
  }
}

// Moves every child element of `owner` but those named in `keep` into
// `params` (created if missing) as dotted attributes.
void FlattenInto(tinyxml2::XMLElement* owner, tinyxml2::XMLElement* params,
                 std::initializer_list<const char*> keep, const std::string& file,
                 std::vector<Diagnostic>& errors) {
  tinyxml2::XMLDocument* doc = owner->GetDocument();
  tinyxml2::XMLElement* holder = doc->NewElement("nested");
  for (auto* c = owner->FirstChildElement(); c;) {
    auto* next = c->NextSiblingElement();
    bool kept = false;
    for (const char* k : keep) kept = kept || std::string(c->Name()) == k;
    if (!kept) holder->InsertEndChild(c);  // moves it
    c = next;
  }
  if (holder->FirstChildElement()) {
    if (!params) {
      params = doc->NewElement("params");
      owner->InsertEndChild(params);
    }
    Flatten(holder, "", params, file, errors);
  }
  doc->DeleteNode(holder);
}

void FlattenParameters(tinyxml2::XMLElement* root, const std::string& file) {
  std::vector<Diagnostic> errors;
  if (auto* controllers = root->FirstChildElement("controllers")) {
    for (auto* c = controllers->FirstChildElement(); c; c = c->NextSiblingElement()) {
      if (auto* params = c->FirstChildElement("params"))
        FlattenInto(params, params, {}, file, errors);
    }
  }
  if (auto* lf = root->FirstChildElement("loop_functions")) {
    auto* params = lf->FirstChildElement("params");
    if (params) FlattenInto(params, params, {}, file, errors);
    FlattenInto(lf, params, {"params"}, file, errors);
  }
  if (!errors.empty()) throw ConfigError(std::move(errors));
}

void AdaptVisualization(tinyxml2::XMLElement* root, Ignored& ignored) {
  auto* vis = root->FirstChildElement("visualization");
  if (!vis) return;
  for (auto* v = vis->FirstChildElement(); v;) {
    auto* next = v->NextSiblingElement();
    if (IsGuiSection(v->Name())) {
      ignored.Add("<" + std::string(v->Name()) + ">", v->GetLineNum());
      vis->DeleteChild(v);
    }
    v = next;
  }
  if (!vis->FirstChildElement()) root->DeleteChild(vis);
}

}  // namespace

void AdaptArgosDocument(tinyxml2::XMLDocument& doc, const std::string& file) {
  tinyxml2::XMLElement* root = doc.RootElement();
  if (!root || std::string(root->Name()) != "argos-configuration") return;
  Ignored ignored;
  AdaptVisualization(root, ignored);
  if (auto* arena = root->FirstChildElement("arena")) AdaptArena(root, arena, file);
  AdaptControllers(root->FirstChildElement("controllers"), ignored);
  AdaptMedia(root->FirstChildElement("media"), ignored);
  FlattenParameters(root, file);
  if (!ignored.items.empty()) {
    LogInfo(file + ": an ARGoS file; ignored: " + ignored.ToString() +
            " (GUI-only in a headless run: colony run --frames draws frames; Colony sizes its "
            "media's spatial index itself)");
  }
}

}  // namespace colony
