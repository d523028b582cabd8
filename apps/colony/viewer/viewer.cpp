#include "apps/colony/viewer/viewer.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <deque>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <random>
#include <sstream>
#include <stdexcept>
#include <type_traits>

#include "actuators/differential_steering/differential_steering.h"
#include "actuators/gripper/gripper.h"
#include "actuators/leds/leds.h"
#include "actuators/range_and_bearing/range_and_bearing.h"
#include "apps/colony/viewer/frame_source.h"
#include "apps/colony/viewer/ws_hub.h"
#include "core/crash_report.h"
#include "core/drawing.h"
#include "core/error.h"
#include "core/log.h"
#include "core/simulation.h"
#include "sensors/battery/battery.h"
#include "sensors/distance_scanner/distance_scanner.h"
#include "sensors/gripper/gripper.h"
#include "sensors/ground/ground.h"
#include "sensors/imu/imu.h"
#include "sensors/light/light.h"
#include "sensors/positioning/positioning.h"
#include "sensors/proximity/proximity.h"
#include "sensors/range_and_bearing/range_and_bearing.h"
#include "sensors/wheel_encoders/wheel_encoders.h"

#ifndef COLONY_INSTALL_VIEWER_DIR
#define COLONY_INSTALL_VIEWER_DIR "/usr/local/share/colony/viewer"
#endif

namespace colony {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;
using viewer::HttpReply;
using viewer::HttpRequest;
using viewer::WebSocketHub;
using Clock = std::chrono::steady_clock;

// A browser's message longer than this closes its connection: commands are
// a few dozen bytes.
constexpr size_t kMaxMessageBytes = 4096;
// Frames are not sent to a connection with more than this waiting to go out.
constexpr size_t kMaxBufferedBytes = 8 << 20;
// Speeds the page may ask for, in multiples of real time ("max": no pacing).
constexpr double kMinSpeed = 0.1, kMaxSpeed = 1000;
// How often the paused loop looks at the stop flag and signals (s).
constexpr auto kIdlePoll = std::chrono::milliseconds(50);

// The binary frame (docs/viewer.md): a 16-byte header, then one 20-byte
// record per mover, in the order of the scene's "movers".
constexpr uint32_t kFrameMagic = 0x31464C43;  // "CLF1" as little-endian bytes
constexpr size_t kFrameHeaderBytes = 16, kFrameRecordBytes = 20;
// What loop functions draw (core/drawing.h) follows the records, when they
// draw anything: "CLD1", four counts, then the points, lines, circles and
// texts (docs/viewer.md).
constexpr uint32_t kDrawingMagic = 0x31444C43;  // "CLD1"
static_assert(std::endian::native == std::endian::little,
              "frames are written as little-endian memory images");

// --- Files -----------------------------------------------------------------

const char* ContentType(const fs::path& path) {
  const std::string ext = path.extension().string();
  if (ext == ".html") return "text/html; charset=utf-8";
  if (ext == ".js") return "text/javascript; charset=utf-8";
  if (ext == ".css") return "text/css; charset=utf-8";
  if (ext == ".png") return "image/png";
  if (ext == ".json") return "application/json";
  return "application/octet-stream";
}

HttpReply NotFound(const std::string& what) {
  return {404, "text/plain; charset=utf-8", "not found: " + what + "\n", ""};
}

// GET `resource`: "/" is the page, "/three/..." three.js, anything else a
// file of the page's folder. Paths that climb out (..) are refused.
HttpReply ServeFile(const std::string& resource, const std::string& web_dir,
                    const std::string& three_dir) {
  std::string path = resource.substr(0, resource.find_first_of("?#"));
  if (path.empty() || path.front() != '/' || path.find("..") != std::string::npos ||
      path.find('\\') != std::string::npos || path.find('\0') != std::string::npos) {
    return NotFound(path);
  }
  if (path == "/") path = "/index.html";
  fs::path file;
  if (path.rfind("/three/", 0) == 0) {
    file = fs::path(three_dir) / path.substr(7);
  } else {
    file = fs::path(web_dir) / path.substr(1);
  }
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) return NotFound(path);
  std::ifstream in(file, std::ios::binary);
  std::ostringstream body;
  body << in.rdbuf();
  if (!in && !in.eof()) return {500, "text/plain", "cannot read " + path + "\n", ""};
  return {200, ContentType(file), body.str(), ""};
}

// --- Access ----------------------------------------------------------------

bool IsLoopback(const std::string& host) {
  return host == "127.0.0.1" || host == "::1" || host == "localhost";
}

// 128 random bits as 32 hexadecimal digits.
std::string RandomToken() {
  std::random_device device;
  std::string token;
  for (int i = 0; i < 4; ++i) {
    char part[9];
    std::snprintf(part, sizeof part, "%08x", static_cast<unsigned>(device()));
    token += part;
  }
  return token;
}

// The value of `key` in "a=1&key=value" or "a=1; key=value" ("" if absent).
std::string FieldOf(const std::string& text, const std::string& key, char separator) {
  size_t begin = 0;
  while (begin <= text.size()) {
    size_t end = text.find(separator, begin);
    if (end == std::string::npos) end = text.size();
    std::string field = text.substr(begin, end - begin);
    field.erase(0, field.find_first_not_of(' '));
    if (field.rfind(key + "=", 0) == 0) return field.substr(key.size() + 1);
    begin = end + 1;
  }
  return "";
}

// Compares in a time that does not depend on where they differ.
bool SameSecret(const std::string& given, const std::string& secret) {
  if (secret.empty() || given.size() != secret.size()) return false;
  unsigned char difference = 0;
  for (size_t i = 0; i < secret.size(); ++i) difference |= given[i] ^ secret[i];
  return difference == 0;
}

// Who may use a served run: everyone (no token), or requests carrying the
// token in their query (?token=...) or in the cookie the page's reply sets.
class Access {
 public:
  // The cookie's name is random too, so that viewers on several ports of one
  // host (cookies ignore ports) do not overwrite each other's.
  explicit Access(std::string token)
      : token_(std::move(token)), cookie_name_("colony_viewer_" + RandomToken().substr(0, 8)) {}
  bool required() const { return !token_.empty(); }
  bool Allows(const HttpRequest& request) const {
    if (!required()) return true;
    const size_t query = request.resource.find('?');
    const std::string given =
        query == std::string::npos ? "" : FieldOf(request.resource.substr(query + 1), "token", '&');
    return SameSecret(given, token_) ||
           SameSecret(FieldOf(request.cookie, cookie_name_, ';'), token_);
  }
  // The cookie that lets the page's own requests (scripts, three.js) in.
  std::string Cookie() const {
    return required() ? cookie_name_ + "=" + token_ + "; Path=/; HttpOnly; SameSite=Strict" : "";
  }
  const std::string& token() const { return token_; }

 private:
  std::string token_, cookie_name_;
};

// --- Commands --------------------------------------------------------------

// What the page asks, checked on the network thread; the simulation thread
// only ever sees valid commands. kOpen and kClose come from the hub.
struct Command {
  enum Kind {
    kOpen,
    kClose,
    kPlay,
    kPause,
    kStep,
    kSpeed,
    kReset,
    kQuit,
    kInspect,
    kMove,
    kRays
  } kind = kOpen;
  WebSocketHub::ConnectionId connection = 0;
  double speed = 0;              // kSpeed: multiple of real time, 0 for "max"
  std::optional<uint64_t> seed;  // kReset: a new seed, or the run's own
  std::string id;                // kInspect, kMove: an entity's id
  double x = 0, y = 0;           // kMove: the new place (m)
  std::optional<double> yaw;     // kMove: the new heading (rad), or the entity's own
};

Command Event(Command::Kind kind, WebSocketHub::ConnectionId connection) {
  Command c;
  c.kind = kind;
  c.connection = connection;
  return c;
}

constexpr const char* kCommandsAccepted =
    "{\"cmd\": \"play\" | \"pause\" | \"step\" | \"quit\"}, {\"cmd\": \"speed\", \"value\": a "
    "number from 0.1 to 1000 (times real time) or \"max\"}, {\"cmd\": \"reset\"[, \"seed\": a "
    "whole number from 0 to 9223372036854775807]}, {\"cmd\": \"inspect\", \"id\": an entity's "
    "id}, {\"cmd\": \"move\", \"id\": an entity's id, \"x\": m, \"y\": m[, \"yaw\": rad]} or "
    "{\"cmd\": \"rays\"}";

// The most robots whose proximity rays are all given at once ("rays").
constexpr size_t kMaxAllRaysRobots = 300;

// The longest entity id a command may name.
constexpr size_t kMaxIdBytes = 256;

// Reads the number `key` of `message` into `value`; why not ("" when read).
std::string ReadNumber(const json& message, const std::string& cmd, const char* key,
                       double& value) {
  const json field = message.value(key, json());
  if (!field.is_number() || !std::isfinite(field.get<double>())) {
    return cmd + " " + key + " " + field.dump() + " is not accepted; expected a finite number";
  }
  value = field.get<double>();
  return "";
}

// Parses one message from a browser into `command`; returns why it is not
// a valid command ("" when it is).
std::string ParseCommand(const std::string& payload, bool binary, Command& command) {
  if (binary)
    return "binary messages are not commands; send JSON text: " + std::string(kCommandsAccepted);
  // JSON text holds no NUL byte (in a string it is written \u0000); nlohmann's
  // parser takes one as the end of its input and would ignore what follows.
  if (const size_t nul = payload.find('\0'); nul != std::string::npos) {
    return "a NUL byte at byte " + std::to_string(nul) + ": not JSON; expected " +
           kCommandsAccepted;
  }
  const json message = json::parse(payload, nullptr, /*allow_exceptions=*/false);
  if (message.is_discarded()) return std::string("not JSON; expected ") + kCommandsAccepted;
  if (!message.is_object() || !message.contains("cmd") || !message["cmd"].is_string()) {
    return std::string("expected a JSON object with a string \"cmd\": ") + kCommandsAccepted;
  }
  const std::string cmd = message["cmd"].get<std::string>();
  // Each command and the keys it takes besides "cmd".
  static const std::map<std::string, std::pair<Command::Kind, std::vector<std::string>>> kCommands =
      {{"play", {Command::kPlay, {}}},
       {"pause", {Command::kPause, {}}},
       {"step", {Command::kStep, {}}},
       {"quit", {Command::kQuit, {}}},
       {"speed", {Command::kSpeed, {"value"}}},
       {"reset", {Command::kReset, {"seed"}}},
       {"inspect", {Command::kInspect, {"id"}}},
       {"move", {Command::kMove, {"id", "x", "y", "yaw"}}},
       {"rays", {Command::kRays, {}}}};
  const auto known = kCommands.find(cmd);
  if (known == kCommands.end())
    return "unknown command '" + cmd + "'; expected " + kCommandsAccepted;
  const auto& [kind, keys] = known->second;
  for (const auto& [key, value] : message.items()) {
    if (key != "cmd" && std::find(keys.begin(), keys.end(), key) == keys.end()) {
      return "command '" + cmd + "' takes no \"" + key + "\"; expected " + kCommandsAccepted;
    }
  }
  command.kind = kind;
  if (kind == Command::kInspect || kind == Command::kMove) {
    const json id = message.value("id", json());
    if (!id.is_string() || id.get<std::string>().empty() ||
        id.get<std::string>().size() > kMaxIdBytes) {
      return cmd + " id " + id.dump() + " is not accepted; expected an entity's id (a string)";
    }
    command.id = id.get<std::string>();
  }
  if (kind == Command::kMove) {
    for (auto [key, value] : {std::pair{"x", &command.x}, std::pair{"y", &command.y}}) {
      if (std::string problem = ReadNumber(message, cmd, key, *value); !problem.empty())
        return problem;
    }
    if (message.contains("yaw")) {
      double yaw = 0;
      if (std::string problem = ReadNumber(message, cmd, "yaw", yaw); !problem.empty())
        return problem;
      command.yaw = yaw;
    }
  }
  if (kind == Command::kReset && message.contains("seed")) {
    const json& seed = message["seed"];
    if (!seed.is_number_unsigned() ||
        seed.get<uint64_t>() > static_cast<uint64_t>(std::numeric_limits<int64_t>::max())) {
      return "reset seed " + seed.dump() +
             " is not accepted; expected a whole number from 0 to 9223372036854775807";
    }
    command.seed = seed.get<uint64_t>();
  }
  if (kind == Command::kSpeed) {
    const json value = message.value("value", json());
    if (value.is_string() && value.get<std::string>() == "max") {
      command.speed = 0;
      return "";
    }
    if (!value.is_number() ||
        !(value.get<double>() >= kMinSpeed && value.get<double>() <= kMaxSpeed)) {
      return "speed value " + value.dump() +
             " is not accepted; expected a number from 0.1 to 1000 "
             "(times real time) or \"max\"";
    }
    command.speed = value.get<double>();
  }
  return "";
}

// --- Scene and frames ------------------------------------------------------

json Rgb(Color c) { return json::array({c.r, c.g, c.b}); }
json Xyz(const Vec3& v) { return json::array({v.x(), v.y(), v.z()}); }

const char* ShapeName(ShapeKind shape) {
  switch (shape) {
    case ShapeKind::kBox:
      return "box";
    case ShapeKind::kCylinder:
      return "cylinder";
    default:
      return "none";
  }
}

// What every entity's description shares: id, type, shape, size, colour.
json Describe(const Space& space, uint32_t slot) {
  const Geometry& g = space.geometry(slot);
  return {{"id", space.id(slot)},        {"type", space.TypeLabel(space.type(slot))},
          {"shape", ShapeName(g.shape)}, {"size", Xyz(g.size)},
          {"radius", g.radius},          {"color", Rgb(space.color(slot))}};
}

// The slots of the entities whose pose the frames carry (robots and movable
// objects), in slot order.
void ListMovers(const Space& space, std::vector<uint32_t>& movers) {
  movers.clear();
  for (uint32_t i = 0; i < space.slots(); ++i) {
    if (space.alive(i) && space.movable(i)) movers.push_back(i);
  }
}

// The scene description, sent once per connection and again when the
// entities change: arena, floor, fixed entities (with their poses) and
// movers (without: the frames carry them).
std::string SceneJson(const Simulation& sim, const std::vector<uint32_t>& movers, bool replay) {
  const Space& space = sim.space();
  // The floor's flat colour: ColorAt away from any image is that colour.
  const double far = std::numeric_limits<double>::infinity();
  json ditches = json::array();
  for (const Ditch& d : space.floor().ditches()) {
    ditches.push_back(
        {{"min", {d.min_x, d.min_y}}, {"max", {d.max_x, d.max_y}}, {"depth", d.depth}});
  }
  json objects = json::array();
  for (uint32_t i = 0; i < space.slots(); ++i) {
    if (!space.alive(i) || space.movable(i)) continue;
    json o = Describe(space, i);
    const Pose& pose = space.pose(i);
    o["position"] = Xyz(pose.position);
    o["orientation"] = {pose.orientation.w(), pose.orientation.x(), pose.orientation.y(),
                        pose.orientation.z()};
    if (space.light(i)) {
      o["light"] = true;
      if (!space.leds(i).empty()) o["color"] = Rgb(space.leds(i)[0]);
    }
    objects.push_back(std::move(o));
  }
  json list = json::array();
  for (uint32_t i : movers) {
    json m = Describe(space, i);
    m["robot"] = (space.flags(i) & kRobot) != 0;
    list.push_back(std::move(m));
  }
  json scene = {{"type", "scene"},
                {"protocol", 1},
                {"file", sim.file()},
                {"replay", replay},
                {"dt", sim.dt()},
                {"length_ticks", sim.length_ticks()},
                {"arena", {{"min", Xyz(space.arena_min())}, {"max", Xyz(space.arena_max())}}},
                {"floor",
                 {{"color", Rgb(space.floor().ColorAt(far, far))},
                  {"image", space.floor().has_image()},
                  {"ditches", std::move(ditches)}}},
                {"ceiling", space.ceiling() ? json(space.ceiling()->z) : json()},
                {"objects", std::move(objects)},
                {"movers", std::move(list)}};
  return scene.dump();
}

// Appends little-endian memory images of values to a frame.
class FrameWriter {
 public:
  explicit FrameWriter(std::string& out) : out_(out) {}
  template <class T>
  void Put(T value) {
    static_assert(std::is_trivially_copyable_v<T>);
    const size_t at = out_.size();
    out_.resize(at + sizeof value);
    std::memcpy(out_.data() + at, &value, sizeof value);
  }
  void PutXyz(const Vec3& v) {
    Put(static_cast<float>(v.x()));
    Put(static_cast<float>(v.y()));
    Put(static_cast<float>(v.z()));
  }
  void PutRgba(Color c) {
    for (uint8_t channel : {c.r, c.g, c.b, c.a}) Put(channel);
  }

 private:
  std::string& out_;
};

// The drawing section: "CLD1", the counts of points, lines, circles and
// texts, then each (docs/viewer.md).
void AppendDrawing(const DrawList& drawing, std::string& frame) {
  FrameWriter w(frame);
  w.Put(kDrawingMagic);
  for (size_t n : {drawing.points().size(), drawing.lines().size(), drawing.circles().size(),
                   drawing.texts().size()}) {
    w.Put(static_cast<uint32_t>(n));
  }
  for (const DrawList::Point& p : drawing.points()) {
    w.PutXyz(p.position);
    w.Put(p.size);
    w.PutRgba(p.color);
  }
  for (const DrawList::Line& l : drawing.lines()) {
    w.Put(l.count);
    w.PutRgba(l.color);
    w.Put(static_cast<uint8_t>(l.closed));
    for (uint32_t k = l.first; k < l.first + l.count; ++k) w.PutXyz(drawing.line_points()[k]);
  }
  for (const DrawList::Circle& c : drawing.circles()) {
    w.PutXyz(c.center);
    w.Put(static_cast<float>(c.radius));
    w.PutRgba(c.color);
    w.Put(static_cast<uint8_t>(c.filled));
  }
  for (const DrawList::Text& t : drawing.texts()) {
    w.PutXyz(t.position);
    w.PutRgba(t.color);
    w.Put(static_cast<uint16_t>(t.text.size()));
    frame += t.text;
  }
}

// One frame: header (magic, mover count, tick), then per mover x, y, z, yaw
// (float32) and the colour it shows (its first LED, else its body colour);
// then what the loop functions drew, if anything.
std::string EncodeFrame(const Simulation& sim, uint64_t tick, const std::vector<uint32_t>& movers,
                        const DrawList& drawing) {
  const Space& space = sim.space();
  std::string frame(kFrameHeaderBytes + kFrameRecordBytes * movers.size(), '\0');
  char* out = frame.data();
  const uint32_t count = static_cast<uint32_t>(movers.size());
  std::memcpy(out, &kFrameMagic, 4);
  std::memcpy(out + 4, &count, 4);
  std::memcpy(out + 8, &tick, 8);
  out += kFrameHeaderBytes;
  for (uint32_t i : movers) {
    const Pose& pose = space.pose(i);
    const float values[4] = {
        static_cast<float>(pose.position.x()), static_cast<float>(pose.position.y()),
        static_cast<float>(pose.position.z()), static_cast<float>(YawOf(pose.orientation))};
    std::memcpy(out, values, sizeof values);
    const auto leds = space.leds(i);
    const Color c = leds.empty() ? space.color(i) : leds[0];
    out[16] = static_cast<char>(c.r);
    out[17] = static_cast<char>(c.g);
    out[18] = static_cast<char>(c.b);
    out += kFrameRecordBytes;
  }
  if (!drawing.empty()) AppendDrawing(drawing, frame);
  return frame;
}

// --- Inspection ------------------------------------------------------------

// A ring of readings (proximity, light, ground): values and directions.
template <class Readings>
void AddRing(json& out, const Readings& readings) {
  json values = json::array(), angles = json::array();
  for (const auto& r : readings) {
    values.push_back(r.value);
    angles.push_back(r.angle);
  }
  out["values"] = std::move(values);
  out["angles"] = std::move(angles);
}

// What a sensor reads now, as the controller sees it; sensors of other kinds
// than these are listed by label with "shown": false.
json DescribeSensor(const Sensor* sensor) {
  json out = json::object();
  if (const auto* p = dynamic_cast<const ProximitySensor*>(sensor)) {
    out["kind"] = "proximity";
    AddRing(out, p->readings());
  } else if (const auto* l = dynamic_cast<const LightSensor*>(sensor)) {
    out["kind"] = "light";
    AddRing(out, l->readings());
  } else if (const auto* g = dynamic_cast<const GroundSensor*>(sensor)) {
    out["kind"] = "ground";
    AddRing(out, g->readings());
  } else if (const auto* pos = dynamic_cast<const PositioningSensor*>(sensor)) {
    out = {
        {"kind", "positioning"}, {"position", {pos->x(), pos->y(), pos->z()}}, {"yaw", pos->yaw()}};
  } else if (const auto* w = dynamic_cast<const WheelEncoders*>(sensor)) {
    out = {
        {"kind", "wheel_encoders"}, {"left", w->distance_left()}, {"right", w->distance_right()}};
  } else if (const auto* rab = dynamic_cast<const RangeAndBearingSensor*>(sensor)) {
    json packets = json::array();
    for (const auto& packet : rab->packets()) {
      packets.push_back({{"range", packet.range},
                         {"bearing", packet.bearing},
                         {"elevation", packet.elevation},
                         {"data", std::vector<int>(packet.data.begin(), packet.data.end())}});
    }
    out = {{"kind", "range_and_bearing"}, {"packets", std::move(packets)}};
  } else if (const auto* b = dynamic_cast<const Battery*>(sensor)) {
    out = {{"kind", "battery"}, {"level", b->level()}, {"empty", b->empty()}};
  } else if (const auto* d = dynamic_cast<const DistanceScanner*>(sensor)) {
    json readings = json::array();
    for (const auto& r : d->readings()) readings.push_back({r.angle, r.distance});
    out = {{"kind", "distance_scanner"},
           {"rotor_angle", d->rotor_angle()},
           {"readings", std::move(readings)}};
  } else if (const auto* gr = dynamic_cast<const GripperSensor*>(sensor)) {
    out = {{"kind", "gripper"}, {"turret_angle", gr->turret_angle()}, {"holding", gr->holding()}};
  } else if (const auto* imu = dynamic_cast<const Imu*>(sensor)) {
    out = {{"kind", "imu"},
           {"angular_velocity", imu->angular_velocity()},
           {"acceleration", imu->acceleration()}};
  } else {
    out["shown"] = false;
  }
  return out;
}

// The last commands the controller gave an actuator.
json DescribeActuator(const Actuator* actuator) {
  json out = json::object();
  if (const auto* d = dynamic_cast<const DifferentialSteering*>(actuator)) {
    out = {{"kind", "differential_steering"},
           {"left", d->target_left()},
           {"right", d->target_right()}};
  } else if (const auto* leds = dynamic_cast<const Leds*>(actuator)) {
    json colors = json::array();
    for (Color c : leds->colors()) colors.push_back(Rgb(c));
    out = {{"kind", "leds"}, {"colors", std::move(colors)}};
  } else if (const auto* g = dynamic_cast<const GripperActuator*>(actuator)) {
    out = {{"kind", "gripper"}, {"turret_target", g->turret_target()}, {"gripping", g->gripping()}};
  } else if (const auto* rab = dynamic_cast<const RangeAndBearingActuator*>(actuator)) {
    out = {{"kind", "range_and_bearing"},
           {"sending", rab->sending()},
           {"data", std::vector<int>(rab->data().begin(), rab->data().end())}};
  } else {
    out["shown"] = false;
  }
  return out;
}

// Collects a controller's RecordValues into a JSON object.
class JsonValues : public RobotValues {
 public:
  void Set(std::string_view name, double value) override {
    values_[std::string(name)] = std::isfinite(value) ? json(value) : json(std::to_string(value));
  }
  void SetLabel(std::string_view name, std::string_view label) override {
    values_[std::string(name)] = std::string(label);
  }
  json& values() { return values_; }

 private:
  json values_ = json::object();
};

// Each robot's last log lines (core/log.h: lines about a robot, its
// controller's own and LogFor's), kept while a run is served, for the
// inspect reply. Lines come from any thread (controllers log from the pool).
class RobotLog {
 public:
  static constexpr size_t kLinesPerRobot = 10, kMaxLineBytes = 300;

  RobotLog() { SetRobotLogListener(&RobotLog::Listen, this); }
  ~RobotLog() { SetRobotLogListener(nullptr, nullptr); }
  RobotLog(const RobotLog&) = delete;
  RobotLog& operator=(const RobotLog&) = delete;

  // The lines of robot `id`, oldest first.
  json LinesOf(const std::string& id) const {
    std::lock_guard lock(mutex_);
    json out = json::array();
    if (const auto it = lines_.find(id); it != lines_.end()) {
      for (const std::string& line : it->second) out.push_back(line);
    }
    return out;
  }
  void Clear() {
    std::lock_guard lock(mutex_);
    lines_.clear();
  }

 private:
  static void Listen(void* context, std::string_view robot, int64_t tick, LogLevel level,
                     std::string_view message) {
    auto* self = static_cast<RobotLog*>(context);
    std::string line = (tick >= 0 ? "[tick " + std::to_string(tick) + "] " : std::string()) +
                       LogLevelName(level) + ": " + std::string(message.substr(0, kMaxLineBytes));
    std::lock_guard lock(self->mutex_);
    auto& lines = self->lines_[std::string(robot)];
    lines.push_back(std::move(line));
    if (lines.size() > kLinesPerRobot) lines.pop_front();
  }

  mutable std::mutex mutex_;
  std::map<std::string, std::deque<std::string>, std::less<>> lines_;
};

// The proximity ring's rays of the robot in `slot` (CastProximityRays),
// for the page's "rays" overlay: [x0, y0, z, x1, y1, hit] each; none without
// a proximity ring.
json ProximityRays(const Simulation& sim, uint32_t slot) {
  std::vector<ProximityRay> cast;
  CastProximityRays(sim, slot, cast);
  json rays = json::array();
  for (const ProximityRay& r : cast)
    rays.push_back({r.from.x(), r.from.y(), r.from.z(), r.to.x(), r.to.y(), r.hit ? 1 : 0});
  return rays;
}

// A camera's field of view (FieldOfView, core/drawing.h) as segments
// [x0, y0, z0, x1, y1, z1] (world frame), for the page's "fov" overlay;
// null for a sensor without one.
json FieldOfViewSegments(const Simulation& sim, const Sensor* sensor) {
  const auto* camera = dynamic_cast<const FieldOfView*>(sensor);
  if (!camera) return json();
  DrawList drawn;
  camera->DrawFieldOfView(sim, drawn);
  json segments = json::array();
  auto add = [&](const Vec3& a, const Vec3& b) {
    segments.push_back({a.x(), a.y(), a.z(), b.x(), b.y(), b.z()});
  };
  const auto& points = drawn.line_points();
  for (const DrawList::Line& line : drawn.lines()) {
    for (uint32_t k = line.first + 1; k < line.first + line.count; ++k)
      add(points[k - 1], points[k]);
    if (line.closed && line.count > 2) add(points[line.first + line.count - 1], points[line.first]);
  }
  constexpr int kSides = 48;
  for (const DrawList::Circle& c : drawn.circles()) {
    auto rim = [&](int k) {
      const double a = 2 * M_PI * k / kSides;
      return Vec3(c.center + c.radius * Vec3(std::cos(a), std::sin(a), 0));
    };
    for (int k = 0; k < kSides; ++k) add(rim(k), rim(k + 1));
  }
  return segments;
}

// Everything the page shows of entity `slot`: where it is and, for a robot,
// its sensors' readings, its actuators' last commands and its controller's
// values (Controller::RecordValues).
std::string InspectJson(const Simulation& sim, uint32_t slot, const RobotLog& log) {
  const Space& space = sim.space();
  const Pose& pose = space.pose(slot);
  json out = Describe(space, slot);
  out["type"] = "inspect";
  out["entity_type"] = space.TypeLabel(space.type(slot));
  out["tick"] = sim.tick();
  out["robot"] = (space.flags(slot) & kRobot) != 0;
  out["movable"] = space.movable(slot);
  out["position"] = Xyz(pose.position);
  out["yaw"] = YawOf(pose.orientation);
  const Controller* controller = sim.ControllerOf(space.HandleOf(slot));
  if (!controller) return out.dump(-1, ' ', false, json::error_handler_t::replace);
  out["controller"] = sim.ControllerLabelOf(space.HandleOf(slot));
  const DeviceTable& devices = controller->devices();
  json sensors = json::array(), actuators = json::array();
  for (size_t i = 0; devices.labels && i < devices.labels->sensor_labels->size(); ++i) {
    json sensor = DescribeSensor(devices.sensors[i]);
    sensor["label"] = (*devices.labels->sensor_labels)[i];
    if (sensor["kind"] == "proximity") sensor["rays"] = ProximityRays(sim, slot);
    if (json fov = FieldOfViewSegments(sim, devices.sensors[i]); !fov.is_null())
      sensor["fov"] = std::move(fov);
    sensors.push_back(std::move(sensor));
  }
  for (size_t i = 0; devices.labels && i < devices.labels->actuator_labels->size(); ++i) {
    json actuator = DescribeActuator(devices.actuators[i]);
    actuator["label"] = (*devices.labels->actuator_labels)[i];
    actuators.push_back(std::move(actuator));
  }
  JsonValues values;
  controller->RecordValues(values);
  out["sensors"] = std::move(sensors);
  out["actuators"] = std::move(actuators);
  out["values"] = std::move(values.values());
  out["log"] = log.LinesOf(space.id(slot));
  return out.dump(-1, ' ', false, json::error_handler_t::replace);
}

// --- The served run --------------------------------------------------------

class Server {
 public:
  Server(Simulation& sim, FrameSource& source, const ServeOptions& options, std::string web_dir)
      : sim_(sim),
        source_(source),
        options_(options),
        access_(options.token.empty() && !IsLoopback(options.host) ? RandomToken() : options.token),
        hub_(Handlers(std::move(web_dir)), kMaxMessageBytes, kMaxBufferedBytes) {}

  // The network thread calls into this object: it stops before the members go.
  ~Server() { hub_.Stop(); }

  int Run() {
    int port = 0;
    try {
      port = hub_.Start(options_.host, options_.port);
    } catch (const std::runtime_error& e) {
      throw RuntimeFailure(std::string("viewer: ") + e.what());
    }
    const bool v6 = options_.host.find(':') != std::string::npos;
    const std::string url = "http://" + (v6 ? "[" + options_.host + "]" : options_.host) + ":" +
                            std::to_string(port) + "/" +
                            (access_.required() ? "?token=" + access_.token() : "");
    if (options_.on_listening) {
      options_.on_listening(url);
    } else {
      std::printf("viewer: open %s in a browser (paused at tick %llu; Ctrl-C ends it)\n",
                  url.c_str(), static_cast<unsigned long long>(source_.tick()));
      std::fflush(stdout);
    }
    playing_ = options_.start_playing;
    speed_ = options_.speed;
    RestartPacing();
    frame_interval_ = std::chrono::duration_cast<Clock::duration>(
        std::chrono::duration<double>(1.0 / options_.updates_per_second));
    const int status = Loop();
    hub_.Stop();
    // What serving cost the simulation thread, for measuring it (docs/viewer.md).
    if (frames_sent_ > 0) {
      char line[200];
      std::snprintf(line, sizeof line,
                    "viewer: %llu frames sent, %.3f ms each to encode on the simulation thread; "
                    "%llu not sent to stalled connections",
                    static_cast<unsigned long long>(frames_sent_),
                    1e3 * frame_seconds_ / frames_sent_,
                    static_cast<unsigned long long>(hub_.dropped()));
      LogInfo(line);
    }
    return status;
  }

 private:
  WebSocketHub::Handlers Handlers(std::string web_dir) {
    WebSocketHub::Handlers h;
    h.http = [this, web_dir, three = options_.three_dir](const HttpRequest& request) {
      if (!access_.Allows(request)) {
        return HttpReply{403, "text/plain; charset=utf-8",
                         "forbidden: this viewer needs the token of the URL it printed "
                         "(http://HOST:PORT/?token=...)\n",
                         ""};
      }
      HttpReply reply = ServeFile(request.resource, web_dir, three);
      reply.set_cookie = access_.Cookie();
      return reply;
    };
    h.accept = [this](const HttpRequest& request) {
      const bool allowed = access_.Allows(request);
      if (!allowed) LogWarning("viewer: refused a WebSocket connection without the right token");
      return allowed;
    };
    h.open = [this](WebSocketHub::ConnectionId id) { Push(Event(Command::kOpen, id)); };
    h.close = [this](WebSocketHub::ConnectionId id) { Push(Event(Command::kClose, id)); };
    h.message = [this](WebSocketHub::ConnectionId id, const std::string& payload, bool binary) {
      Command command = Event(Command::kOpen, id);
      const std::string problem = ParseCommand(payload, binary, command);
      if (problem.empty()) return Push(command);
      // The message is shown cut short: it may be long and binary.
      std::string shown = binary ? "(binary, " + std::to_string(payload.size()) + " bytes)"
                                 : payload.substr(0, 200);
      LogWarning("viewer: connection " + std::to_string(id) + ": " + problem +
                 " (received: " + shown + ")");
      const json reply = {{"type", "error"}, {"message", problem}, {"received", shown}};
      hub_.Send(id,
                std::make_shared<const std::string>(
                    reply.dump(-1, ' ', false, json::error_handler_t::replace)),
                false);
    };
    return h;
  }

  void Push(const Command& command) {
    {
      std::lock_guard lock(mutex_);
      queue_.push_back(command);
    }
    pending_.store(true, std::memory_order_release);
    wake_.notify_one();
  }

  // The simulation thread's loop: apply commands, step when playing (paced
  // to the speed) or asked to, send a frame when one is due.
  int Loop() {
    for (;;) {
      if (options_.stop && options_.stop->load()) return 0;
      if (const int signal_number = StopSignal()) return 128 + signal_number;
      if (pending_.load(std::memory_order_acquire) && !ApplyCommands()) return 0;
      const bool can_step = !source_.Done() && (playing_ || steps_ > 0);
      if (!can_step) {
        if (playing_) SetPlaying(false);  // the run ended while playing
        Wait(Clock::now() + kIdlePoll);
        continue;
      }
      if (playing_ && speed_ > 0) {
        const double ahead =
            static_cast<double>(source_.next_tick() - paced_from_tick_) * sim_.dt();
        const auto due = paced_from_ + std::chrono::duration_cast<Clock::duration>(
                                           std::chrono::duration<double>(ahead / speed_));
        if (Clock::now() < due) {
          Wait(due);
          continue;
        }
      }
      source_.Step();
      const bool stepped = steps_ > 0;
      if (stepped) --steps_;
      if (hub_.connections() == 0) continue;
      const auto now = Clock::now();
      if (stepped || source_.Done() || now >= next_frame_) {
        SendFrame();
        next_frame_ = now + frame_interval_;
      }
      if (stepped || source_.Done()) SendStatus();
    }
  }

  // Waits until `until` or a command arrives.
  void Wait(Clock::time_point until) {
    std::unique_lock lock(mutex_);
    wake_.wait_until(lock, until, [this] { return !queue_.empty(); });
  }

  // Applies the queued commands; false on "quit".
  bool ApplyCommands() {
    std::deque<Command> commands;
    {
      std::lock_guard lock(mutex_);
      commands.swap(queue_);
      pending_.store(false, std::memory_order_relaxed);
    }
    for (auto it = commands.begin(); it != commands.end(); ++it) {
      const Command& c = *it;
      // What follows a step sees the stepped run: it waits for the step.
      if (steps_ > 0) {
        std::lock_guard lock(mutex_);
        queue_.insert(queue_.begin(), it, commands.end());
        pending_.store(true, std::memory_order_relaxed);
        return true;
      }
      switch (c.kind) {
        case Command::kOpen:
          LogInfo("viewer: connection " + std::to_string(c.connection) + " opened");
          ListMovers(sim_.space(), movers_);
          SendTo(c.connection, SceneJson(sim_, movers_, source_.replay()), false);
          SendTo(c.connection, StatusJson(), false);
          SendTo(c.connection, Frame(), true);
          break;
        case Command::kClose:
          LogInfo("viewer: connection " + std::to_string(c.connection) + " closed");
          break;
        case Command::kPlay:
          SetPlaying(!source_.Done());
          break;
        case Command::kPause:
          SetPlaying(false);
          break;
        case Command::kStep:
          SetPlaying(false);
          if (source_.Done())
            SendStatus();
          else
            ++steps_;
          break;
        case Command::kSpeed:
          speed_ = c.speed;
          RestartPacing();
          SendStatus();
          break;
        case Command::kReset:
          Reset(c);
          break;
        case Command::kQuit:
          LogInfo("viewer: connection " + std::to_string(c.connection) + " ended the run");
          return false;
        case Command::kInspect:
          Inspect(c);
          break;
        case Command::kMove:
          Move(c);
          break;
        case Command::kRays:
          Rays(c);
          break;
      }
    }
    return true;
  }

  // Tells one page why its command was refused (and logs it).
  void SendError(WebSocketHub::ConnectionId to, const std::string& problem) {
    LogWarning("viewer: connection " + std::to_string(to) + ": " + problem);
    SendTo(to,
           json({{"type", "error"}, {"message", problem}})
               .dump(-1, ' ', false, json::error_handler_t::replace),
           false);
  }

  // The slot of entity `id`, or none (the asking page is told).
  std::optional<uint32_t> Slot(const Command& c, const char* what) {
    const EntityHandle h = sim_.space().Find(c.id);
    if (h.valid() && sim_.space().IsAlive(h)) return h.index;
    SendError(c.connection, std::string(what) + ": there is no entity '" + c.id + "'");
    return std::nullopt;
  }

  void Inspect(const Command& c) {
    if (const std::string refused = source_.Refuses("inspect"); !refused.empty())
      return SendError(c.connection, refused);
    if (const auto slot = Slot(c, "inspect"))
      SendTo(c.connection, InspectJson(sim_, *slot, robot_log_), false);
  }

  // Every robot's proximity rays, for the page's "all rays" overlay: up to
  // kMaxAllRaysRobots robots (beyond, the page shows the selected robot's).
  void Rays(const Command& c) {
    if (const std::string refused = source_.Refuses("rays"); !refused.empty())
      return SendError(c.connection, refused);
    const Space& space = sim_.space();
    std::vector<uint32_t> robots;
    for (uint32_t i = 0; i < space.slots(); ++i) {
      if (space.alive(i) && (space.flags(i) & kRobot)) robots.push_back(i);
    }
    if (robots.size() > kMaxAllRaysRobots) {
      return SendError(c.connection, "rays: every robot's rays are given up to " +
                                         std::to_string(kMaxAllRaysRobots) +
                                         " robots; this run has " + std::to_string(robots.size()) +
                                         " (select a robot for its rays)");
    }
    json of = json::object();
    for (uint32_t i : robots) {
      json rays = ProximityRays(sim_, i);
      if (!rays.empty()) of[space.id(i)] = std::move(rays);
    }
    SendTo(c.connection,
           json({{"type", "rays"}, {"tick", source_.tick()}, {"robots", std::move(of)}})
               .dump(-1, ' ', false, json::error_handler_t::replace),
           false);
  }

  // Moves a robot or a movable object (Simulation::MoveEntity) while
  // paused; every page gets the new frame and a status saying the run was
  // moved.
  void Move(const Command& c) {
    if (const std::string refused = source_.Refuses("move"); !refused.empty())
      return SendError(c.connection, refused);
    const auto slot = Slot(c, "move");
    if (!slot) return;
    const Space& space = sim_.space();
    const std::string what =
        "move '" + c.id + "' to (" + std::to_string(c.x) + ", " + std::to_string(c.y) + ")";
    if (playing_ || steps_ > 0) return SendError(c.connection, what + ": pause the run first");
    if (!space.movable(*slot)) return SendError(c.connection, what + ": it is fixed");
    const Vec3& min = space.arena_min();
    const Vec3& max = space.arena_max();
    if (!(c.x >= min.x() && c.x <= max.x() && c.y >= min.y() && c.y <= max.y())) {
      return SendError(c.connection, what + ": outside the arena");
    }
    Pose pose = space.pose(*slot);
    pose.position.x() = c.x;
    pose.position.y() = c.y;
    if (c.yaw) pose.orientation = FromYaw(*c.yaw);
    if (const std::string problem = sim_.MoveEntity(space.HandleOf(*slot), pose);
        !problem.empty()) {
      return SendError(c.connection, what + ": " + problem);
    }
    LogInfo("viewer: connection " + std::to_string(c.connection) + " moved '" + c.id + "' to (" +
            std::to_string(c.x) + ", " + std::to_string(c.y) + ") at tick " +
            std::to_string(source_.tick()));
    moved_ = true;
    if (hub_.connections() > 0) SendFrame();
    SendStatus();
  }

  // Back to tick 0 (Simulation::Reset), paused; every page gets the scene
  // again. A failed reset is the asking page's error.
  void Reset(const Command& c) {
    playing_ = false;
    steps_ = 0;
    try {
      source_.Reset(c.seed);
    } catch (const std::exception& e) {
      const std::string problem = std::string("reset failed: ") + e.what();
      LogWarning("viewer: connection " + std::to_string(c.connection) + ": " + problem);
      SendTo(c.connection, json({{"type", "error"}, {"message", problem}}).dump(), false);
      SendStatus();
      return;
    }
    moved_ = false;
    robot_log_.Clear();
    LogInfo("viewer: connection " + std::to_string(c.connection) + " reset the run (seed " +
            std::to_string(sim_.seed()) + ")");
    ListMovers(sim_.space(), movers_);
    hub_.Broadcast(std::make_shared<const std::string>(SceneJson(sim_, movers_, source_.replay())),
                   false, false);
    RestartPacing();
    SendStatus();
    hub_.Broadcast(std::make_shared<const std::string>(Frame()), true, false);
  }

  void SetPlaying(bool playing) {
    const bool paused_now = playing_ && !playing;
    playing_ = playing;
    RestartPacing();
    if (paused_now && hub_.connections() > 0) SendFrame();
    SendStatus();
  }
  void RestartPacing() {
    paced_from_ = Clock::now();
    paced_from_tick_ = source_.tick();
  }

  std::string StatusJson() const {
    const json status = {
        {"type", "status"},       {"tick", source_.tick()},
        {"seed", sim_.seed()},    {"playing", playing_},
        {"done", source_.Done()}, {"speed", speed_ > 0 ? json(speed_) : json("max")},
        {"moved", moved_}};
    return status.dump();
  }
  void SendStatus() {
    hub_.Broadcast(std::make_shared<const std::string>(StatusJson()), false, false);
  }

  // Sends the current poses to every connection (a new scene first if the
  // movers changed: entities added or removed while running).
  void SendFrame() {
    const auto start = Clock::now();
    ListMovers(sim_.space(), scratch_);
    if (scratch_ != movers_) {
      movers_.swap(scratch_);
      hub_.Broadcast(
          std::make_shared<const std::string>(SceneJson(sim_, movers_, source_.replay())), false,
          false);
    }
    hub_.Broadcast(std::make_shared<const std::string>(Frame()), true, true);
    ++frames_sent_;
    frame_seconds_ += std::chrono::duration<double>(Clock::now() - start).count();
  }
  // The current frame, with what the loop functions draw now (a replay's
  // loop functions never ran: it shows none).
  std::string Frame() {
    drawing_.Clear();
    if (!source_.replay()) DrawLoopFunctions(sim_, drawing_);
    return EncodeFrame(sim_, source_.tick(), movers_, drawing_);
  }
  void SendTo(WebSocketHub::ConnectionId id, std::string data, bool binary) {
    hub_.Send(id, std::make_shared<const std::string>(std::move(data)), binary);
  }

  Simulation& sim_;
  FrameSource& source_;
  const ServeOptions& options_;
  const Access access_;  // before hub_: its handlers read it
  WebSocketHub hub_;
  // Commands from the network thread.
  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<Command> queue_;
  std::atomic<bool> pending_{false};
  // Simulation thread only.
  bool playing_ = false;
  double speed_ = 1;    // times real time; 0: as fast as possible
  int steps_ = 0;       // single steps asked for and not yet taken
  bool moved_ = false;  // an entity was moved since the start or the last reset
  Clock::time_point paced_from_;
  uint64_t paced_from_tick_ = 0;
  Clock::time_point next_frame_;
  Clock::duration frame_interval_{};
  std::vector<uint32_t> movers_, scratch_;
  DrawList drawing_;  // reused from frame to frame
  RobotLog robot_log_;
  uint64_t frames_sent_ = 0;
  double frame_seconds_ = 0;  // in SendFrame
};

}  // namespace

void ParseServeAddress(const std::string& text, ServeOptions& options) {
  const std::string accepted =
      "expected [HOST:]PORT with PORT from 0 to 65535 (0: any free port), e.g. 8080, "
      "127.0.0.1:8080, 0.0.0.0:8080 or [::1]:8080";
  std::string host = options.host, port = text;
  if (!text.empty() && text.front() == '[') {
    const size_t close = text.find("]:");
    if (close == std::string::npos) throw std::invalid_argument("'" + text + "': " + accepted);
    host = text.substr(1, close - 1);
    port = text.substr(close + 2);
  } else if (const size_t colon = text.rfind(':'); colon != std::string::npos) {
    host = text.substr(0, colon);
    port = text.substr(colon + 1);
  }
  const bool digits = !port.empty() && port.size() <= 5 &&
                      port.find_first_not_of("0123456789") == std::string::npos;
  if (host.empty() || !digits || std::stoi(port) > 65535) {
    throw std::invalid_argument("'" + text + "': " + accepted);
  }
  options.host = host;
  options.port = std::stoi(port);
}

std::string ViewerWebDir() {
  if (const char* env = std::getenv("COLONY_VIEWER_DIR"); env && *env) return env;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path dir = exe.parent_path().parent_path() / "share" / "colony" / "viewer";
    if (fs::is_regular_file(dir / "index.html", ec)) return dir.string();
  }
  return COLONY_INSTALL_VIEWER_DIR;
}

namespace {

// The live run: steps the simulation itself.
class LiveSource : public FrameSource {
 public:
  LiveSource(Simulation& sim, const ServeOptions& options) : sim_(sim), options_(options) {}
  uint64_t tick() const override { return sim_.tick(); }
  uint64_t next_tick() const override { return sim_.tick() + 1; }
  bool Done() const override { return sim_.Done(); }
  void Step() override {
    sim_.Step();
    if (options_.after_tick) options_.after_tick(sim_);
  }
  void Reset(std::optional<uint64_t> seed) override { sim_.Reset(seed); }

 private:
  Simulation& sim_;
  const ServeOptions& options_;
};

}  // namespace

int ServeRun(Simulation& sim, const ServeOptions& options) {
  LiveSource live(sim, options);
  return ServeFrames(sim, live, options);
}

int ServeFrames(Simulation& sim, FrameSource& source, const ServeOptions& options) {
  const std::string web_dir = options.web_dir.empty() ? ViewerWebDir() : options.web_dir;
  std::error_code ec;
  if (!fs::is_regular_file(fs::path(web_dir) / "index.html", ec)) {
    throw RuntimeFailure("the viewer's page is missing: no index.html in " + web_dir +
                         " (install Colony, or set COLONY_VIEWER_DIR to apps/colony/viewer/web)");
  }
  if (!fs::is_regular_file(fs::path(options.three_dir) / "build" / "three.module.js", ec)) {
    throw RuntimeFailure("the viewer needs three.js: no build/three.module.js in " +
                         options.three_dir + " (Debian: apt-get install libjs-three)");
  }
  if (!(options.updates_per_second > 0)) {
    throw RuntimeFailure("the viewer's updates_per_second must be > 0, not " +
                         std::to_string(options.updates_per_second));
  }
  if (!(options.speed == 0 || (options.speed >= kMinSpeed && options.speed <= kMaxSpeed))) {
    throw RuntimeFailure(
        "the viewer's speed must be 0 (as fast as possible) or from 0.1 to 1000, not " +
        std::to_string(options.speed));
  }
  if (options.token.find_first_not_of(
          "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789-_") !=
      std::string::npos) {
    throw RuntimeFailure("the viewer's token '" + options.token +
                         "' is not accepted; expected letters, digits, '-' and '_'");
  }
  if (!IsLoopback(options.host)) {
    LogWarning("viewer: listening on " + options.host +
               ": anyone who can reach this address and has the URL's token can watch and "
               "control the run");
  }
  Server server(sim, source, options, web_dir);
  return server.Run();
}

}  // namespace colony
