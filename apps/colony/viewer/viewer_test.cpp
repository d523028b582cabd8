// The live viewer, end to end: a served run seen through a real WebSocket
// client (the scene, frames, commands, bad messages), its HTTP files, and
// the page itself drawn by headless Chromium when it is installed.
#include "apps/colony/viewer/viewer.h"

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <future>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <thread>

#include "actuators/differential_steering/differential_steering.h"
#include "apps/colony/sweep.h"
#include "apps/colony/viewer/ws_client.h"
#include "core/error.h"
#include "core/log.h"
#include "core/registry.h"
#include "core/simulation.h"
#include "sensors/proximity/proximity.h"
#include "tests/test_util.h"

// Built with AddressSanitizer (GCC defines __SANITIZE_ADDRESS__, clang 14 only has the feature
// test).
#if defined(__SANITIZE_ADDRESS__)
#define COLONY_VIEWER_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define COLONY_VIEWER_TEST_ASAN 1
#endif
#endif
#ifndef COLONY_VIEWER_TEST_ASAN
#define COLONY_VIEWER_TEST_ASAN 0
#endif
namespace colony {
namespace {

using json = nlohmann::json;
using viewer::WebSocketClient;
using namespace std::chrono_literals;

constexpr int kRobots = 20;

std::unique_ptr<Simulation> LoadDiffusion(int robots = kRobots, int length_seconds = 60) {
  ExperimentOptions options;
  options.file = COLONY_SOURCE_DIR "/experiments/diffusion.xml";
  options.overrides = {"arena.distribute.entity.quantity=" + std::to_string(robots),
                       "framework.experiment.length=" + std::to_string(length_seconds)};
  options.threads = 1;
  return Simulation::Load(options);
}

// One decoded binary frame (docs/viewer.md), with what the loop functions
// drew when the frame carries it.
struct Frame {
  uint32_t magic = 0, count = 0;
  uint64_t tick = 0;
  struct Record {
    float x, y, z, yaw;
    uint8_t r, g, b;
  };
  std::vector<Record> records;
  bool drawn = false;  // a drawing section follows the records
  struct Shape {
    std::vector<std::array<float, 3>> points;
    float size = 0;  // a point's pixels, a circle's radius
    std::array<uint8_t, 4> rgba{};
    bool flag = false;  // a line closed, a circle filled
    std::string text;
  };
  std::vector<Shape> points, lines, circles, texts;
};

// Reads little-endian values from a frame's bytes, failing the test when
// they run out.
class FrameReader {
 public:
  FrameReader(const std::string& data, size_t at) : data_(data), at_(at) {}
  template <class T>
  T Get() {
    T value{};
    if (at_ + sizeof value > data_.size()) {
      ADD_FAILURE() << "the frame ends at " << data_.size() << " bytes, inside a value at " << at_;
      at_ = data_.size();
      return value;
    }
    std::memcpy(&value, data_.data() + at_, sizeof value);
    at_ += sizeof value;
    return value;
  }
  std::array<float, 3> Xyz() { return {Get<float>(), Get<float>(), Get<float>()}; }
  std::array<uint8_t, 4> Rgba() {
    return {Get<uint8_t>(), Get<uint8_t>(), Get<uint8_t>(), Get<uint8_t>()};
  }
  std::string Bytes(size_t n) {
    std::string out = data_.substr(std::min(at_, data_.size()), n);
    at_ += n;
    return out;
  }
  size_t at() const { return at_; }

 private:
  const std::string& data_;
  size_t at_;
};

Frame Decode(const std::string& data) {
  Frame f;
  EXPECT_GE(data.size(), 16u);
  std::memcpy(&f.magic, data.data(), 4);
  std::memcpy(&f.count, data.data() + 4, 4);
  std::memcpy(&f.tick, data.data() + 8, 8);
  EXPECT_GE(data.size(), 16u + 20u * f.count);
  for (uint32_t i = 0; i < f.count && 16 + 20 * (i + 1) <= data.size(); ++i) {
    const char* p = data.data() + 16 + 20 * i;
    Frame::Record r;
    std::memcpy(&r, p, 16);
    r.r = static_cast<uint8_t>(p[16]);
    r.g = static_cast<uint8_t>(p[17]);
    r.b = static_cast<uint8_t>(p[18]);
    f.records.push_back(r);
  }
  if (data.size() <= 16u + 20u * f.count) return f;
  FrameReader in(data, 16u + 20u * f.count);
  EXPECT_EQ(in.Get<uint32_t>(), 0x31444C43u) << "the drawing section's magic (CLD1)";
  f.drawn = true;
  const uint32_t points = in.Get<uint32_t>(), lines = in.Get<uint32_t>(),
                 circles = in.Get<uint32_t>(), texts = in.Get<uint32_t>();
  for (uint32_t k = 0; k < points; ++k) {
    Frame::Shape s;
    s.points = {in.Xyz()};
    s.size = in.Get<float>();
    s.rgba = in.Rgba();
    f.points.push_back(s);
  }
  for (uint32_t k = 0; k < lines; ++k) {
    Frame::Shape s;
    const uint32_t n = in.Get<uint32_t>();
    s.rgba = in.Rgba();
    s.flag = in.Get<uint8_t>() != 0;
    for (uint32_t j = 0; j < n && in.at() < data.size(); ++j) s.points.push_back(in.Xyz());
    f.lines.push_back(s);
  }
  for (uint32_t k = 0; k < circles; ++k) {
    Frame::Shape s;
    s.points = {in.Xyz()};
    s.size = in.Get<float>();
    s.rgba = in.Rgba();
    s.flag = in.Get<uint8_t>() != 0;
    f.circles.push_back(s);
  }
  for (uint32_t k = 0; k < texts; ++k) {
    Frame::Shape s;
    s.points = {in.Xyz()};
    s.rgba = in.Rgba();
    s.text = in.Bytes(in.Get<uint16_t>());
    f.texts.push_back(s);
  }
  EXPECT_EQ(in.at(), data.size()) << "bytes after the drawing section";
  return f;
}

// A run served on a free port in a thread, for as long as the object lives.
class Served {
 public:
  explicit Served(Simulation& sim, ServeOptions options = {}) {
    std::promise<std::string> url;
    auto listening = url.get_future();
    options.port = 0;
    options.stop = &stop_;
    options.on_listening = [&url](const std::string& u) { url.set_value(u); };
    thread_ = std::thread([this, &sim, options] {
      try {
        status_ = ServeRun(sim, options);
      } catch (const std::exception& e) {
        error_ = e.what();
        stop_ = true;
      }
    });
    if (listening.wait_for(10s) == std::future_status::ready) url_ = listening.get();
  }
  ~Served() { Stop(); }
  int Stop() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
    return status_;
  }
  const std::string& url() const { return url_; }  // http://127.0.0.1:PORT/
  std::string ws() const { return "ws" + url_.substr(4); }
  int port() const { return std::stoi(url_.substr(url_.rfind(':') + 1)); }  // stops at "/"

 private:
  std::atomic<bool> stop_{false};
  std::thread thread_;
  std::string url_, error_;
  int status_ = -1;
};

// Reads messages until one of the JSON `type`, or a binary frame when
// `type` is "frame"; fails after a few seconds.
std::optional<WebSocketClient::Message> Next(WebSocketClient& client, const std::string& type) {
  const auto deadline = std::chrono::steady_clock::now() + 10s;
  while (std::chrono::steady_clock::now() < deadline) {
    auto m = client.Receive(200ms);
    if (!m) continue;
    if (type == "frame" ? m->binary : !m->binary && json::parse(m->payload)["type"] == type)
      return m;
  }
  ADD_FAILURE() << "no '" << type << "' message";
  return std::nullopt;
}

void Connect(WebSocketClient& client, const std::string& uri) {
  std::string error;
  ASSERT_TRUE(client.Connect(uri, 5s, error)) << uri << ": " << error;
}

// A WebSocket client on a bare socket, for what a browser never does: stop
// reading (a stalled page) or send text that is not UTF-8 (websocketpp's own
// client refuses to).
class RawWebSocket {
 public:
  RawWebSocket() = default;
  RawWebSocket(const RawWebSocket&) = delete;
  RawWebSocket& operator=(const RawWebSocket&) = delete;
  ~RawWebSocket() {
    if (fd_ >= 0) close(fd_);
  }
  // Connects to 127.0.0.1:`port`, with a receive buffer of about
  // `receive_buffer` bytes when > 0 (the kernel's default otherwise), and
  // completes the handshake; false when it cannot.
  bool Connect(int port, int receive_buffer = 0) {
    fd_ = socket(AF_INET, SOCK_STREAM, 0);
    if (fd_ < 0) return false;
    if (receive_buffer > 0)
      setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &receive_buffer, sizeof receive_buffer);
    const timeval timeout{10, 0};
    setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
    setsockopt(fd_, SOL_SOCKET, SO_SNDTIMEO, &timeout, sizeof timeout);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(static_cast<uint16_t>(port));
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (connect(fd_, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) return false;
    const std::string request = "GET / HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) +
                                "\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
                                "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n"
                                "Sec-WebSocket-Version: 13\r\n\r\n";
    if (!SendAll(request)) return false;
    // The reply's head, byte by byte: what follows it is the server's first frames.
    std::string head;
    char c;
    while (head.find("\r\n\r\n") == std::string::npos && recv(fd_, &c, 1, 0) == 1) head += c;
    return head.rfind("HTTP/1.1 101", 0) == 0;
  }
  // Sends `payload` as one masked frame (opcode 1: text); false when the
  // connection is gone (errno says why) or nothing went for 10 s.
  bool Send(const std::string& payload, uint8_t opcode = 1) {
    std::string frame(1, static_cast<char>(0x80 | opcode));
    const uint64_t n = payload.size();
    if (n < 126) {
      frame += static_cast<char>(0x80 | n);
    } else {
      frame += static_cast<char>(0x80 | 127);
      for (int shift = 56; shift >= 0; shift -= 8) frame += static_cast<char>((n >> shift) & 0xFF);
    }
    const char mask[4] = {0x37, 0x5a, 0x12, 0x6c};
    frame.append(mask, 4);
    for (size_t i = 0; i < payload.size(); ++i)
      frame += static_cast<char>(payload[i] ^ mask[i % 4]);
    return SendAll(frame);
  }
  // The next frame from the server: its opcode and payload; false when the
  // connection ends or nothing comes for 10 s.
  bool Receive(int& opcode, std::string& payload) {
    unsigned char head[2];
    if (!ReceiveAll(head, 2)) return false;
    opcode = head[0] & 0x0F;
    uint64_t n = head[1] & 0x7F;
    if (n >= 126) {
      unsigned char extended[8];
      const int bytes = n == 126 ? 2 : 8;
      if (!ReceiveAll(extended, bytes)) return false;
      n = 0;
      for (int i = 0; i < bytes; ++i) n = (n << 8) | extended[i];
    }
    payload.assign(n, '\0');
    return ReceiveAll(payload.data(), n);
  }
  // Reads until the server's close frame: its status code and reason; 0 when
  // the connection ends without one.
  int CloseCode(std::string& reason) {
    int opcode = 0;
    std::string payload;
    while (Receive(opcode, payload)) {
      if (opcode != 8) continue;
      if (payload.size() < 2) return 0;
      reason = payload.substr(2);
      return (static_cast<unsigned char>(payload[0]) << 8) | static_cast<unsigned char>(payload[1]);
    }
    return 0;
  }

 private:
  bool SendAll(const std::string& data) {
    for (size_t sent = 0; sent < data.size();) {
      const ssize_t k = ::send(fd_, data.data() + sent, data.size() - sent, MSG_NOSIGNAL);
      if (k <= 0) return false;
      sent += static_cast<size_t>(k);
    }
    return true;
  }
  bool ReceiveAll(void* out, size_t n) {
    char* p = static_cast<char*>(out);
    for (size_t got = 0; got < n;) {
      const ssize_t k = recv(fd_, p + got, n - got, 0);
      if (k <= 0) return false;
      got += static_cast<size_t>(k);
    }
    return true;
  }

  int fd_ = -1;
};

// This process's resident memory (VmRSS, bytes).
size_t ResidentBytes() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stoull(line.substr(6)) * 1024;
  }
  return 0;
}

// Turns on the spot (wheels 0.01 and 0.02 m/s... then reversed each tick)
// and gives its step count and a state label.
class ViewerProbe : public Controller {
 public:
  void Init(const Params&) override {
    steering_ = &GetActuator<DifferentialSteering>("differential_steering");
  }
  void ControlStep() override {
    ++steps_;
    steering_->SetLinearVelocity(0.01 * steps_, -0.01 * steps_);
  }
  void RecordValues(RobotValues& values) const override {
    values.Set("steps", steps_);
    values.SetLabel("state", steps_ % 2 ? "odd" : "even");
  }

 private:
  int steps_ = 0;
  DifferentialSteering* steering_ = nullptr;
};
COLONY_REGISTER_CONTROLLER(ViewerProbe, "viewer_probe", "test only: turns and gives its steps");

// Logs "step N" every step (its robot's log lines, core/log.h).
class ViewerLogger : public Controller {
 public:
  void ControlStep() override { LogInfo("step " + std::to_string(++steps_)); }

 private:
  int steps_ = 0;
};
COLONY_REGISTER_CONTROLLER(ViewerLogger, "viewer_logger", "test only: logs its steps");

// Robots a and b facing each other 0.25 m apart (their rings see each
// other), c farther, a fixed box and a movable one, in a 4 x 4 m arena.
std::unique_ptr<Simulation> LoadProbes() {
  const std::string controllers =
      "<viewer_probe id=\"p\"><actuators><differential_steering/><leds color=\"red\"/>"
      "</actuators><sensors><proximity/></sensors></viewer_probe>";
  const std::string arena =
      "<marxbot id=\"a\"><body position=\"0,0,0\"/><controller config=\"p\"/></marxbot>"
      "<marxbot id=\"b\"><body position=\"0.25,0,0\" orientation=\"180,0,0\"/>"
      "<controller config=\"p\"/></marxbot>"
      "<marxbot id=\"c\"><body position=\"-1,1,0\"/><controller config=\"p\"/></marxbot>"
      "<box id=\"fixed\" size=\"0.4,0.4,0.2\"><body position=\"1,1,0\"/></box>"
      "<box id=\"crate\" size=\"0.2,0.2,0.2\" movable=\"true\"><body position=\"-1,-1,0\"/></box>";
  return testing::LoadXml(testing::Experiment(arena, controllers), {}, 1);
}

TEST(Viewer, SendsTheSceneOnceThenAFramePerStep) {
  auto sim = LoadDiffusion();
  Served served(*sim);
  ASSERT_FALSE(served.url().empty());
  WebSocketClient client;
  Connect(client, served.ws());

  // The scene: the 8 x 8 m arena, its floor, walls, boxes, cylinders and the
  // light as fixed objects, and every robot.
  auto scene_message = Next(client, "scene");
  ASSERT_TRUE(scene_message);
  const json scene = json::parse(scene_message->payload);
  EXPECT_EQ(scene["arena"]["min"], json({-4.0, -4.0, 0.0}));
  EXPECT_EQ(scene["arena"]["max"], json({4.0, 4.0, 1.0}));
  EXPECT_EQ(scene["floor"]["color"], json({204, 204, 204}));  // gray80
  EXPECT_DOUBLE_EQ(scene["dt"].get<double>(), 0.1);
  std::set<std::string> objects;
  for (const auto& o : scene["objects"]) objects.insert(o["id"].get<std::string>());
  for (const char* id : {"box1", "box2", "box3", "cyl1", "cyl2", "light"}) {
    EXPECT_TRUE(objects.count(id)) << id;
  }
  EXPECT_GE(objects.size(), 6u + 4u);  // and the 4 walls
  ASSERT_EQ(scene["movers"].size(), static_cast<size_t>(kRobots));
  for (const auto& m : scene["movers"]) {
    EXPECT_EQ(m["type"], "marxbot");
    EXPECT_EQ(m["robot"], true);
    EXPECT_GT(m["radius"].get<double>(), 0.05);
  }
  // Paused at tick 0, with a frame of it.
  const json status = json::parse(Next(client, "status")->payload);
  EXPECT_EQ(status["tick"], 0);
  EXPECT_EQ(status["playing"], false);
  Frame first = Decode(Next(client, "frame")->payload);
  EXPECT_EQ(first.magic, 0x31464C43u);
  EXPECT_EQ(first.tick, 0u);
  EXPECT_EQ(first.count, static_cast<uint32_t>(kRobots));

  // One step: a frame of tick 1 with every robot, then a status saying so.
  client.Send(R"({"cmd":"step"})");
  Frame one = Decode(Next(client, "frame")->payload);
  EXPECT_EQ(one.tick, 1u);
  ASSERT_EQ(one.count, static_cast<uint32_t>(kRobots));
  EXPECT_EQ(json::parse(Next(client, "status")->payload)["tick"], 1);
  // Paused again: no more frames come.
  EXPECT_FALSE(client.Receive(500ms));

  client.Close();
  EXPECT_EQ(served.Stop(), 0);
  // The frame showed the robots where the simulation has them, LEDs green
  // (the diffusion controller's colour).
  EXPECT_EQ(sim->tick(), 1u);
  for (int i = 0; i < kRobots; ++i) {
    const uint32_t slot = sim->space().Find(scene["movers"][i]["id"].get<std::string>()).index;
    const Pose& pose = sim->space().pose(slot);
    EXPECT_NEAR(one.records[i].x, pose.position.x(), 1e-5);
    EXPECT_NEAR(one.records[i].y, pose.position.y(), 1e-5);
    EXPECT_NEAR(one.records[i].yaw, YawOf(pose.orientation), 1e-5);
    EXPECT_EQ(one.records[i].g, 255);
    EXPECT_EQ(one.records[i].r, 0);
  }
}

TEST(Viewer, PlayAdvancesPauseStops) {
  auto sim = LoadDiffusion();
  Served served(*sim);
  WebSocketClient client;
  Connect(client, served.ws());
  Next(client, "frame");
  client.Send(R"({"cmd":"speed","value":"max"})");
  EXPECT_EQ(json::parse(Next(client, "status")->payload)["speed"], "max");
  client.Send(R"({"cmd":"play"})");
  EXPECT_EQ(json::parse(Next(client, "status")->payload)["playing"], true);
  uint64_t tick = 0;
  for (int k = 0; k < 3; ++k) tick = Decode(Next(client, "frame")->payload).tick;
  EXPECT_GT(tick, 1u);
  client.Send(R"({"cmd":"pause"})");
  // Statuses sent while playing may still be on their way: the first one
  // that says paused answers the pause.
  json paused;
  for (int k = 0; k < 20; ++k) {
    const auto status = Next(client, "status");
    if (!status) break;
    paused = json::parse(status->payload);
    if (paused["playing"] == false) break;
  }
  ASSERT_EQ(paused["playing"], false);
  // Nothing moves while paused.
  std::this_thread::sleep_for(300ms);
  while (client.Receive(100ms)) {
  }
  client.Close();
  served.Stop();
  EXPECT_EQ(sim->tick(), paused["tick"].get<uint64_t>());
}

TEST(Viewer, BadMessagesGetAnErrorReplyAndChangeNothing) {
  auto sim = LoadDiffusion();
  Served served(*sim);
  WebSocketClient client;
  Connect(client, served.ws());
  Next(client, "frame");
  using namespace std::string_literals;
  const std::pair<std::string, const char*> bad[] = {
      {"garbage", "not JSON"},
      {"", "not JSON"},
      {" \t\r\n", "not JSON"},
      {R"({"cmd":"play"} {"cmd":"step"})", "not JSON"},
      // A NUL ends the parser's input: what follows a command must not be ignored.
      {"{\"cmd\":\"play\"}\0garbage"s, "a NUL byte"},
      {"{\"cmd\":\"play\"}\0"s, "a NUL byte"},
      {R"({"cmd":"\ud800"})", "not JSON"},  // half a UTF-16 surrogate pair
      {R"({"cmd":"pl\u00e4y"})", "unknown command 'pl\xc3\xa4y'"},
      {"{\"cmd\":\"\xf0\x9f\x90\x9c\"}", "unknown command '\xf0\x9f\x90\x9c'"},
      {std::string(3000, '['), "not JSON"},
      {std::string(2000, '[') + std::string(2000, ']'), "expected a JSON object"},
      {R"({"cmd":"speed","value":1e999})", "not JSON"},
      {R"({"cmd":"play","cmd":"fly"})", "unknown command 'fly'"},
      {R"({"cmd":"reset","seed":1.5})", "reset seed 1.5 is not accepted"},
      {R"({"cmd":"move","id":"mb3","x":"1","y":0})", "move x \"1\" is not accepted"},
      {R"({"cmd":"inspect","id":"\u0000"})", "there is no entity"},
      {R"({"cmd":"inspect","id":["mb3"]})", "inspect id [\"mb3\"] is not accepted"},
      {"[1,2,3]", "expected a JSON object with a string \"cmd\""},
      {R"({"cmd":"fly"})", "unknown command 'fly'"},
      {R"({"cmd":42})", "expected a JSON object with a string \"cmd\""},
      {R"({"cmd":"speed","value":5000})", "speed value 5000 is not accepted"},
      {R"({"cmd":"speed","value":0})", "speed value 0 is not accepted"},
      {R"({"cmd":"speed"})", "speed value null is not accepted"},
      {R"({"cmd":"step","count":"lots"})", "command 'step' takes no \"count\""},
  };
  for (const auto& [message, expected] : bad) {
    client.Send(message);
    auto reply = Next(client, "error");
    ASSERT_TRUE(reply) << message;
    EXPECT_NE(json::parse(reply->payload)["message"].get<std::string>().find(expected),
              std::string::npos)
        << message << " -> " << reply->payload;
  }
  // Binary messages, even a frame's bytes, are not commands.
  client.Send(std::string("CLF1\0\0\0\0\xff\xfe", 10), true);
  auto reply = Next(client, "error");
  ASSERT_TRUE(reply);
  EXPECT_NE(reply->payload.find("binary messages are not commands"), std::string::npos);
  // Text that is not UTF-8 (sent from a bare socket: websocketpp's client
  // will not) fails that connection with status 1007 and a reason, as
  // WebSocket requires (RFC 6455, 8.1); before it, that client's garbage got
  // the usual error reply.
  for (const std::string& not_utf8 : {"{\"cmd\":\"\xff\xfe\"}"s, "{\"cmd\":\"pl\xc3\"}"s,
                                      "{\"cmd\":\"\xc0\xaf\"}"s, "{\"cmd\":\"\xed\xa0\x80\"}"s}) {
    RawWebSocket raw;
    ASSERT_TRUE(raw.Connect(served.port()));
    ASSERT_TRUE(raw.Send(R"({"cmd":"fly"})"));
    int opcode = 0;
    std::string payload;
    while (raw.Receive(opcode, payload) && payload.find("\"error\"") == std::string::npos) {
    }
    EXPECT_NE(payload.find("unknown command 'fly'"), std::string::npos) << payload;
    ASSERT_TRUE(raw.Send(not_utf8));
    std::string reason;
    EXPECT_EQ(raw.CloseCode(reason), 1007) << not_utf8;
    EXPECT_FALSE(reason.empty());
  }
  // An oversized message closes that connection ("message too big"); the
  // run goes on serving others.
  client.Send("{\"cmd\":\"" + std::string(10000, 'x') + "\"}");
  for (int k = 0; k < 50 && !client.closed(); ++k) std::this_thread::sleep_for(20ms);
  EXPECT_TRUE(client.closed());
  EXPECT_EQ(client.close_code(), 1009);
  WebSocketClient other;
  Connect(other, served.ws());
  Next(other, "frame");
  other.Send(R"({"cmd":"step"})");
  EXPECT_EQ(Decode(Next(other, "frame")->payload).tick, 1u);
  other.Close();
  served.Stop();
  // The bad messages changed nothing: the run is a plain run stepped once.
  EXPECT_EQ(sim->tick(), 1u);
  auto plain = LoadDiffusion();
  plain->Step();
  EXPECT_EQ(sim->StateHash(), plain->StateHash());
}

// A page that stops reading never holds the run back: a bare socket with a
// tiny receive buffer completes the handshake and reads nothing more while
// the run plays as fast as it can, sending a frame per tick. Another page
// keeps getting frames of ever later ticks, each second; the server drops
// the stalled page's frames (and says so when it ends) instead of queueing
// them, so the process's memory stays well under what it sent meanwhile.
TEST(Viewer, AStalledPageNeitherSlowsTheRunNorFillsTheMemory) {
  ExperimentOptions experiment;
  experiment.file = COLONY_SOURCE_DIR "/experiments/benchmarks/diffusion_10000.xml";
  experiment.overrides = {"framework.experiment.length=100000"};
  experiment.threads = 1;
  auto sim = Simulation::Load(experiment);  // 10,000 robots: 200 KB frames
  ServeOptions options;
  options.start_playing = true;
  options.speed = 0;                    // as fast as possible
  options.updates_per_second = 100000;  // a frame after every tick
  const std::string log = COLONY_BINARY_DIR "/tests/viewer_stalled.log";
  std::filesystem::create_directories(COLONY_BINARY_DIR "/tests");
  OpenLogFile(log);
  Served served(*sim, options);
  RawWebSocket stalled;
  ASSERT_TRUE(stalled.Connect(served.port(), 2048));
  WebSocketClient client;
  Connect(client, served.ws());
  // Reads what comes for `seconds`: the last frame's tick and the bytes of frames received.
  uint64_t tick = 0, bytes = 0;
  auto read_for = [&](std::chrono::milliseconds seconds) {
    const auto until = std::chrono::steady_clock::now() + seconds;
    while (std::chrono::steady_clock::now() < until) {
      const auto m = client.Receive(100ms);
      if (!m || !m->binary) continue;
      bytes += m->payload.size();
      std::memcpy(&tick, m->payload.data() + 8, 8);
    }
  };
  read_for(1500ms);  // the stalled socket's buffers fill up
  const size_t memory_before = ResidentBytes();
  const uint64_t bytes_before = bytes;
  // At least 4 s, and until 96 MB of frames went to the reading page (the
  // stalled one would hold as much if they were queued for it).
  constexpr uint64_t kEnough = 96u << 20;
  std::vector<uint64_t> ticks = {tick};
  // Under AddressSanitizer frames come several times slower and 96 MB would
  // take half a minute: there, until 60 more ticks were sent (12 MB of frames,
  // more than the 8 MB the stalled page may hold, so some were dropped).
  auto more_wanted = [&] {
    return COLONY_VIEWER_TEST_ASAN ? tick < ticks.front() + 60 : bytes - bytes_before < kEnough;
  };
  while (ticks.size() < 5 || (more_wanted() && ticks.size() < 31)) {
    read_for(1000ms);
    ticks.push_back(tick);
  }
  const size_t memory_after = ResidentBytes();
  const uint64_t sent = bytes - bytes_before;
  client.Close();
  EXPECT_EQ(served.Stop(), 0);
  CloseLogFile();
#if !COLONY_VIEWER_TEST_ASAN
  for (size_t k = 1; k < ticks.size(); ++k)
    EXPECT_GT(ticks[k], ticks[k - 1]) << "the run did not advance in second " << k;
#else
  // A tick of 10,000 robots and its frame take long enough there, on a
  // machine shared with other tests, that one second may see no new frame:
  // the run advances over the seconds, never going back.
  for (size_t k = 1; k < ticks.size(); ++k) EXPECT_GE(ticks[k], ticks[k - 1]) << "second " << k;
  EXPECT_GE(ticks.back(), ticks.front() + 60) << "the run did not advance in 30 s";
#endif
  std::smatch dropped;
  const std::string text = testing::ReadFile(log);
  ASSERT_TRUE(std::regex_search(text, dropped, std::regex("(\\d+) not sent to stalled"))) << text;
#if !COLONY_VIEWER_TEST_ASAN
  EXPECT_GE(sent, kEnough) << "too few frames in " << ticks.size() - 1 << " s to tell";
  // The server may hold 8 MB queued for the stalled page, a write in flight
  // and the kernel's buffers.
  EXPECT_LT(memory_after, memory_before + (32u << 20)) << "after " << sent << " bytes of frames";
  EXPECT_GT(std::stoull(dropped[1]), 100u);
#else
  // AddressSanitizer keeps freed memory aside (no bound on the process's
  // memory holds) and frames come several times slower: the run advancing
  // and some frames dropped is what can be told there.
  (void)memory_after;
  EXPECT_GT(std::stoull(dropped[1]), 0u);
#endif
}

// A page that reads nothing but keeps asking (each speed command is answered
// with a status to every page, which is never dropped) is cut off once 16 MB
// of answers wait for it, instead of holding them without bound; the run
// goes on serving others.
TEST(Viewer, APageThatAsksButNeverReadsIsCutOff) {
  auto sim = LoadDiffusion();
  Served served(*sim);
  RawWebSocket stalled;
  ASSERT_TRUE(stalled.Connect(served.port(), 2048));
  const std::string ask = R"({"cmd":"speed","value":"max"})";
  const auto deadline = std::chrono::steady_clock::now() + 60s;
  int sent = 0;
  while (std::chrono::steady_clock::now() < deadline && stalled.Send(ask)) ++sent;
  const int error = errno;
  EXPECT_TRUE(error == EPIPE || error == ECONNRESET)
      << "still connected after " << sent << " commands (" << std::strerror(error) << ")";
  WebSocketClient other;
  Connect(other, served.ws());
  Next(other, "frame");
  other.Send(R"({"cmd":"step"})");
  EXPECT_EQ(Decode(Next(other, "frame")->payload).tick, 1u);
  other.Close();
  served.Stop();
  EXPECT_EQ(sim->tick(), 1u);
}

// Commands out of place (a move while playing, a step's count, a reset
// seed as text, a move out of the arena or with no id) and garbage, sent
// between steps, are refused one by one; the run stepped around them is
// the plain run, hash for hash.
TEST(Viewer, MalformedAndOutOfPlaceMessagesLeaveTheRunAsAPlainRun) {
  auto sim = LoadDiffusion();
  auto plain = LoadDiffusion();
  Served served(*sim);
  WebSocketClient client;
  Connect(client, served.ws());
  Next(client, "frame");
  const char* refused[] = {R"({"cmd":"move","id":"mb3","x":0,"y":0})",  // sent while playing
                           R"({"cmd":"step","count":2})",
                           R"({"cmd":"reset","seed":"1"})",
                           R"({"cmd":"reset","seed":-1})",
                           R"({"cmd":"move","id":"mb3","x":100,"y":0})",
                           R"({"cmd":"move","x":0,"y":0})",
                           R"({"cmd":"inspect","id":""})",
                           R"({"cmd":"speed","value":"fast"})",
                           R"({"cmd":"move","id":"mb3","x":0,"y":0,"z":1})",
                           "{\"cmd\":\"play\"",
                           "\x01\x02\x03"};
  client.Send(R"({"cmd":"play"})");
  for (const char* message : refused) {
    client.Send(message);
    ASSERT_TRUE(Next(client, "error")) << message;
    if (message == refused[0]) {
      client.Send(R"({"cmd":"pause"})");
      json status;
      do {
        status = json::parse(Next(client, "status")->payload);
      } while (status["playing"] == true);
    }
    client.Send(R"({"cmd":"step"})");
    Next(client, "frame");
  }
  client.Send(R"({"cmd":"pause"})");
  json status;
  do {
    status = json::parse(Next(client, "status")->payload);
  } while (status["playing"] == true);
  EXPECT_EQ(status["moved"], false);
  client.Close();
  served.Stop();
  ASSERT_GE(sim->tick(), 11u);
  while (plain->tick() < sim->tick()) plain->Step();
  EXPECT_EQ(sim->StateHash(), plain->StateHash());
}

TEST(Viewer, ResetGoesBackToTickZeroWithTheSameOrANewSeed) {
  auto sim = LoadDiffusion();
  Served served(*sim);
  WebSocketClient client;
  Connect(client, served.ws());
  const Frame start = Decode(Next(client, "frame")->payload);
  for (int k = 0; k < 3; ++k) {
    client.Send(R"({"cmd":"step"})");
    EXPECT_EQ(Decode(Next(client, "frame")->payload).tick, k + 1u);
  }
  // The same seed: the robots stand where they started.
  client.Send(R"({"cmd":"reset"})");
  ASSERT_TRUE(Next(client, "scene"));
  Frame again = Decode(Next(client, "frame")->payload);
  EXPECT_EQ(again.tick, 0u);
  ASSERT_EQ(again.count, start.count);
  for (uint32_t i = 0; i < start.count; ++i) {
    EXPECT_EQ(again.records[i].x, start.records[i].x);
    EXPECT_EQ(again.records[i].y, start.records[i].y);
  }
  // A new seed: placed elsewhere; a bad one is refused.
  client.Send(R"({"cmd":"reset","seed":-3})");
  EXPECT_NE(Next(client, "error")->payload.find("reset seed -3 is not accepted"),
            std::string::npos);
  client.Send(R"({"cmd":"reset","seed":99})");
  EXPECT_EQ(json::parse(Next(client, "status")->payload)["seed"], 99);
  Frame other = Decode(Next(client, "frame")->payload);
  EXPECT_EQ(other.tick, 0u);
  EXPECT_NE(other.records[0].x, start.records[0].x);
  client.Close();
  served.Stop();
  EXPECT_EQ(sim->seed(), 99u);
}

// Clicking a robot asks for it: the reply carries what its controller
// reads and last commanded, and its RecordValues, as the simulation holds them.
TEST(Viewer, InspectShowsTheRobotsSensorsCommandsAndValues) {
  auto sim = LoadProbes();
  Served served(*sim);
  WebSocketClient client;
  Connect(client, served.ws());
  const json scene = json::parse(Next(client, "scene")->payload);
  EXPECT_EQ(scene["movers"].size(), 4u);  // a, b, c and the crate
  Next(client, "status");
  Next(client, "frame");
  for (int k = 0; k < 2; ++k) {
    client.Send(R"({"cmd":"step"})");
    Next(client, "frame");
    Next(client, "status");
  }
  client.Send(R"({"cmd":"inspect","id":"a"})");
  const json a = json::parse(Next(client, "inspect")->payload);
  EXPECT_EQ(a["id"], "a");
  EXPECT_EQ(a["tick"], 2);
  EXPECT_EQ(a["entity_type"], "marxbot");
  EXPECT_EQ(a["robot"], true);
  EXPECT_EQ(a["controller"], "viewer_probe");
  ASSERT_EQ(a["sensors"].size(), 1u);
  const json& proximity = a["sensors"][0];
  EXPECT_EQ(proximity["label"], "proximity");
  EXPECT_EQ(proximity["kind"], "proximity");
  ASSERT_EQ(proximity["values"].size(), 24u);
  ASSERT_EQ(a["actuators"].size(), 2u);
  EXPECT_EQ(a["actuators"][0]["kind"], "differential_steering");
  EXPECT_DOUBLE_EQ(a["actuators"][0]["left"].get<double>(), 0.02);
  EXPECT_DOUBLE_EQ(a["actuators"][0]["right"].get<double>(), -0.02);
  EXPECT_EQ(a["actuators"][1]["kind"], "leds");
  EXPECT_EQ(a["actuators"][1]["colors"][0], json({255, 0, 0}));
  EXPECT_EQ(a["values"], json({{"steps", 2}, {"state", "even"}}));
  // Objects: where they are, nothing more.
  client.Send(R"({"cmd":"inspect","id":"fixed"})");
  const json box = json::parse(Next(client, "inspect")->payload);
  EXPECT_EQ(box["robot"], false);
  EXPECT_EQ(box["movable"], false);
  EXPECT_EQ(box["position"], json({1.0, 1.0, 0.0}));
  EXPECT_FALSE(box.contains("sensors"));
  // An id that is not there: an error, nothing changes.
  for (const char* bad : {R"({"cmd":"inspect","id":"zz"})", R"({"cmd":"inspect","id":3})",
                          R"({"cmd":"inspect"})", R"({"cmd":"inspect","id":"a","x":1})"}) {
    client.Send(bad);
    const auto reply = Next(client, "error");
    ASSERT_TRUE(reply) << bad;
    EXPECT_NE(reply->payload.find("inspect"), std::string::npos) << reply->payload;
  }
  client.Close();
  served.Stop();
  EXPECT_EQ(sim->tick(), 2u);
  // The readings are the device's own; b, facing a 0.25 m away, is seen.
  const auto& readings =
      sim->ControllerOf(sim->space().Find("a"))->GetSensor<ProximitySensor>("proximity").readings();
  float strongest = 0;
  for (size_t i = 0; i < readings.size(); ++i) {
    EXPECT_EQ(proximity["values"][i].get<float>(), readings[i].value) << i;
    EXPECT_EQ(proximity["angles"][i].get<float>(), readings[i].angle) << i;
    strongest = std::max(strongest, readings[i].value);
  }
  EXPECT_GT(strongest, 0.1f);
}

// The inspect reply carries the robot's last 10 log lines (its own, not
// another robot's), and, for a proximity ring, its rays: a's rays that face
// b, 0.25 m ahead, end on b.
TEST(Viewer, InspectShowsTheRobotsLastLogLinesAndItsProximityRays) {
  const std::string controllers =
      "<viewer_logger id=\"l\"><actuators><differential_steering/></actuators>"
      "<sensors><proximity/></sensors></viewer_logger>";
  auto sim = testing::LoadXml(
      testing::Experiment("<marxbot id=\"a\"><body position=\"0,0,0\"/><controller "
                          "config=\"l\"/></marxbot><marxbot id=\"b\"><body "
                          "position=\"0.25,0,0\"/><controller config=\"l\"/></marxbot>",
                          controllers),
      {}, 1);
  Served served(*sim);
  WebSocketClient client;
  Connect(client, served.ws());
  Next(client, "frame");
  for (int k = 0; k < 12; ++k) {
    client.Send(R"({"cmd":"step"})");
    Next(client, "frame");
  }
  client.Send(R"({"cmd":"inspect","id":"a"})");
  const auto reply = Next(client, "inspect");
  ASSERT_TRUE(reply);
  const json a = json::parse(reply->payload);
  ASSERT_EQ(a["log"].size(), 10u) << a["log"];
  EXPECT_EQ(a["log"][0], "[tick 3] info: step 3");
  EXPECT_EQ(a["log"][9], "[tick 12] info: step 12");
  const json& rays = a["sensors"][0]["rays"];
  ASSERT_EQ(rays.size(), 24u);
  int hits = 0;
  for (const json& r : rays) {
    const double x0 = r[0], y0 = r[1], x1 = r[3];
    EXPECT_NEAR(std::hypot(x0, y0), 0.085, 0.02) << r;  // from the ring
    if (r[5] == 1) {
      ++hits;
      EXPECT_GT(x1, 0.12) << "a hit ray ends on b: " << r;
      EXPECT_LT(x1, 0.25) << r;
    }
  }
  EXPECT_GE(hits, 1);
  client.Close();
  served.Stop();
}

// Dragging while paused moves the entity through the simulation: the next
// frame shows it there, stepping goes on from there, the status says the run
// was moved; bad places and ids are refused and change nothing.
// The cameras' fields of view, for the page's "fov" overlay, where the
// cameras see: the eye-bot's pan-tilt camera a cone (60 degrees, 3 m: its rim
// 3 m from the head, and four sides from the head), a foot-bot's
// omnidirectional camera a circle of its range (2.5 m) around its axis.
TEST(Viewer, InspectGivesTheCamerasFieldsOfView) {
  ExperimentOptions options;
  options.file = COLONY_SOURCE_DIR "/experiments/eyebot_guidance.xml";
  options.threads = 1;
  auto sim = Simulation::Load(options);
  sim->Step();
  Served served(*sim);
  WebSocketClient client;
  Connect(client, served.ws());
  Next(client, "frame");
  auto fov_of = [&](const std::string& id, const std::string& kind) {
    client.Send(R"({"cmd":"inspect","id":")" + id + R"("})");
    const json reply = json::parse(Next(client, "inspect")->payload);
    for (const auto& sensor : reply["sensors"]) {
      if (sensor["label"] == kind) return sensor.value("fov", json());
    }
    ADD_FAILURE() << id << " has no " << kind;
    return json();
  };
  const json cone = fov_of("eye0", "eyebot_pan_tilt_camera");
  ASSERT_TRUE(cone.is_array());
  ASSERT_EQ(cone.size(), 32u + 4u);
  const Eigen::Vector3d head(cone[32][0], cone[32][1], cone[32][2]);
  const Vec3 eye = testing::PositionOf(*sim, "eye0");
  EXPECT_LT((head - eye).norm(), 0.2) << "the head is on the eye-bot";
  for (size_t k = 0; k < cone.size(); ++k) {
    const Eigen::Vector3d end(cone[k][3], cone[k][4], cone[k][5]);
    EXPECT_NEAR((end - head).norm(), 3.0, 1e-6) << k;
  }
  const json circle = fov_of("fb2", "omnidirectional_camera");
  ASSERT_TRUE(circle.is_array());
  ASSERT_EQ(circle.size(), 48u);
  const Vec3 fb2 = testing::PositionOf(*sim, "fb2");
  for (const auto& segment : circle) {
    EXPECT_NEAR(std::hypot(segment[0].get<double>() - fb2.x(), segment[1].get<double>() - fb2.y()),
                2.5, 1e-6);
    EXPECT_GT(segment[2].get<double>(), fb2.z() + 0.1) << "at the camera's height";
  }
  // Sensors that see no region have none.
  client.Send(R"({"cmd":"inspect","id":"fb2"})");
  const json inspect = json::parse(Next(client, "inspect")->payload);
  for (const auto& sensor : inspect["sensors"]) {
    if (sensor["label"] != "omnidirectional_camera") {
      EXPECT_FALSE(sensor.contains("fov")) << sensor;
    }
  }
  client.Close();
}

// Every robot's proximity rays at once ("rays", the page's "all rays"
// overlay): 24 per robot, the same as each robot's inspection gives; up to
// 300 robots, beyond which the command is refused with the reason.
TEST(Viewer, RaysGivesEveryRobotsProximityRaysUpTo300Robots) {
  auto sim = LoadDiffusion(300);
  sim->Step();
  Served served(*sim);
  WebSocketClient client;
  Connect(client, served.ws());
  Next(client, "frame");
  client.Send(R"({"cmd":"rays"})");
  const json reply = json::parse(Next(client, "rays")->payload);
  EXPECT_EQ(reply["tick"], 1);
  ASSERT_EQ(reply["robots"].size(), 300u);
  int hits = 0;
  for (const auto& [id, rays] : reply["robots"].items()) {
    ASSERT_EQ(rays.size(), 24u) << id;
    for (const auto& r : rays) hits += r[5].get<int>();
  }
  EXPECT_GT(hits, 0) << "no robot's ray hits anything";
  client.Send(R"({"cmd":"inspect","id":"mb7"})");
  const json inspected = json::parse(Next(client, "inspect")->payload);
  EXPECT_EQ(inspected["sensors"][0]["rays"], reply["robots"]["mb7"]);
  client.Close();
  served.Stop();

  auto crowd = LoadDiffusion(301);
  Served crowded(*crowd);
  WebSocketClient other;
  Connect(other, crowded.ws());
  Next(other, "frame");
  other.Send(R"({"cmd":"rays"})");
  EXPECT_NE(json::parse(Next(other, "error")->payload)["message"].get<std::string>().find(
                "up to 300 robots; this run has 301"),
            std::string::npos);
  other.Close();
}

TEST(Viewer, MoveWhilePausedPutsTheRobotThereAndTheRunGoesOn) {
  auto sim = LoadProbes();
  Served served(*sim);
  WebSocketClient client;
  Connect(client, served.ws());
  const json scene = json::parse(Next(client, "scene")->payload);
  EXPECT_EQ(json::parse(Next(client, "status")->payload)["moved"], false);
  Next(client, "frame");
  size_t a = 0, crate = 0;
  for (size_t i = 0; i < scene["movers"].size(); ++i) {
    if (scene["movers"][i]["id"] == "a") a = i;
    if (scene["movers"][i]["id"] == "crate") crate = i;
  }
  const std::pair<const char*, const char*> refused[] = {
      {R"({"cmd":"move","id":"zz","x":0,"y":0})", "there is no entity 'zz'"},
      {R"({"cmd":"move","id":"a","x":5,"y":0})", "outside the arena"},
      {R"({"cmd":"move","id":"a","x":1.95,"y":0})", "outside the arena"},  // half out
      {R"({"cmd":"move","id":"a","x":0.9,"y":1})", "overlaps 'fixed'"},
      {R"({"cmd":"move","id":"a","x":-1,"y":1.1})", "overlaps 'c'"},
      {R"({"cmd":"move","id":"fixed","x":0,"y":-1})", "it is fixed"},
      {R"({"cmd":"move","id":"a","x":"left","y":0})", "move x \"left\" is not accepted"},
      {R"({"cmd":"move","id":"a","x":1})", "move y null is not accepted"},
      {R"({"cmd":"move","id":"a","x":1,"y":1e999})", "not JSON"},
      {R"({"cmd":"move","id":"a","x":1,"y":0,"z":3})", "command 'move' takes no \"z\""},
  };
  for (const auto& [message, expected] : refused) {
    client.Send(message);
    const auto reply = Next(client, "error");
    ASSERT_TRUE(reply) << message;
    EXPECT_NE(json::parse(reply->payload)["message"].get<std::string>().find(expected),
              std::string::npos)
        << message << " -> " << reply->payload;
  }
  // Nothing moved.
  client.Send(R"({"cmd":"inspect","id":"a"})");
  EXPECT_EQ(json::parse(Next(client, "inspect")->payload)["position"], json({0.0, 0.0, 0.0}));

  client.Send(R"({"cmd":"move","id":"a","x":1.2,"y":-1.3,"yaw":1.5})");
  Frame moved = Decode(Next(client, "frame")->payload);
  EXPECT_EQ(moved.tick, 0u);
  EXPECT_FLOAT_EQ(moved.records[a].x, 1.2f);
  EXPECT_FLOAT_EQ(moved.records[a].y, -1.3f);
  EXPECT_FLOAT_EQ(moved.records[a].yaw, 1.5f);
  EXPECT_EQ(json::parse(Next(client, "status")->payload)["moved"], true);
  client.Send(R"({"cmd":"move","id":"crate","x":0,"y":-1.5})");
  moved = Decode(Next(client, "frame")->payload);
  EXPECT_FLOAT_EQ(moved.records[crate].x, 0.0f);
  EXPECT_FLOAT_EQ(moved.records[crate].y, -1.5f);
  // Stepping goes on from the new place: a turns on the spot there.
  for (uint64_t k = 1; k <= 3; ++k) {
    client.Send(R"({"cmd":"step"})");
    const Frame f = Decode(Next(client, "frame")->payload);
    EXPECT_EQ(f.tick, k);
    EXPECT_NEAR(f.records[a].x, 1.2, 1e-3);
    EXPECT_NEAR(f.records[a].y, -1.3, 1e-3);
  }
  // Not while playing.
  client.Send(R"({"cmd":"play"})");
  client.Send(R"({"cmd":"move","id":"a","x":0,"y":0})");
  EXPECT_NE(Next(client, "error")->payload.find("pause the run first"), std::string::npos);
  client.Send(R"({"cmd":"pause"})");
  // A reset forgets the move.
  client.Send(R"({"cmd":"reset"})");
  json status;
  do {
    status = json::parse(Next(client, "status")->payload);
  } while (status["tick"] != 0);
  EXPECT_EQ(status["moved"], false);
  client.Close();
  served.Stop();
  EXPECT_EQ(sim->tick(), 0u);
}

TEST(Viewer, QuitEndsTheServedRun) {
  auto sim = LoadDiffusion();
  Served served(*sim);
  WebSocketClient client;
  Connect(client, served.ws());
  client.Send(R"({"cmd":"quit"})");
  for (int k = 0; k < 100 && !client.closed(); ++k) std::this_thread::sleep_for(20ms);
  EXPECT_TRUE(client.closed());
  EXPECT_EQ(served.Stop(), 0);
}

TEST(Viewer, ServedRunWithNobodyConnectedEqualsAPlainRun) {
  auto plain = LoadDiffusion(kRobots, 5);
  while (!plain->Done()) plain->Step();
  auto served_sim = LoadDiffusion(kRobots, 5);
  std::atomic<bool> stop{false};
  ServeOptions options;
  options.start_playing = true;
  options.speed = 0;
  options.stop = &stop;
  options.on_listening = [](const std::string&) {};
  options.after_tick = [&stop](Simulation& s) { stop = stop || s.Done(); };
  EXPECT_EQ(ServeRun(*served_sim, options), 0);
  EXPECT_EQ(served_sim->tick(), plain->tick());
  EXPECT_EQ(served_sim->StateHash(), plain->StateHash());
}

// The eye-bot guidance example's loop functions draw its target's regions
// (core/drawing.h); every frame carries them, in the simulation's numbers,
// and a served run that draws for a connected page steps as a plain run.
TEST(Viewer, FramesCarryWhatTheLoopFunctionsDraw) {
  ExperimentOptions options;
  options.file = COLONY_SOURCE_DIR "/experiments/eyebot_guidance.xml";
  options.threads = 1;
  auto sim = Simulation::Load(options);
  auto plain = Simulation::Load(options);
  const Vec3 target = sim->space().pose(sim->space().Find("target").index).position;
  Served served(*sim);
  WebSocketClient client;
  Connect(client, served.ws());
  Frame first = Decode(Next(client, "frame")->payload);
  ASSERT_TRUE(first.drawn) << "no drawing section in the first frame";
  // The reach disc (0.6 m, green, translucent) and the mark ring (0.2 m,
  // yellow until marked), centred on the target.
  ASSERT_EQ(first.circles.size(), 2u);
  EXPECT_NEAR(first.circles[0].points[0][0], target.x(), 1e-5);
  EXPECT_NEAR(first.circles[0].points[0][1], target.y(), 1e-5);
  EXPECT_FLOAT_EQ(first.circles[0].size, 0.6f);
  EXPECT_TRUE(first.circles[0].flag);
  EXPECT_EQ(first.circles[0].rgba, (std::array<uint8_t, 4>{40, 200, 60, 90}));
  EXPECT_FLOAT_EQ(first.circles[1].size, 0.2f);
  EXPECT_FALSE(first.circles[1].flag);
  EXPECT_EQ(first.circles[1].rgba, (std::array<uint8_t, 4>{255, 220, 0, 255}));
  // No foot-bot starts within reach: no lines; the count above the target.
  EXPECT_TRUE(first.lines.empty());
  ASSERT_EQ(first.texts.size(), 1u);
  EXPECT_EQ(first.texts[0].text, "reached 0/5");
  EXPECT_NEAR(first.texts[0].points[0][2], target.z() + 0.3, 1e-5);
  for (int k = 0; k < 5; ++k) {
    client.Send(R"({"cmd":"step"})");
    EXPECT_TRUE(Decode(Next(client, "frame")->payload).drawn);
    Next(client, "status");
  }
  client.Close();
  served.Stop();
  for (int k = 0; k < 5; ++k) plain->Step();
  ASSERT_EQ(sim->tick(), 5u);
  EXPECT_EQ(sim->StateHash(), plain->StateHash()) << "drawing for the page changed the run";
}

// A run whose loop functions draw nothing sends frames without a drawing
// section: the records and nothing after them.
TEST(Viewer, FramesOfARunThatDrawsNothingEndAfterTheRecords) {
  auto sim = LoadDiffusion();
  Served served(*sim);
  WebSocketClient client;
  Connect(client, served.ws());
  const std::string payload = Next(client, "frame")->payload;
  EXPECT_EQ(payload.size(), 16u + 20u * kRobots);
  EXPECT_FALSE(Decode(payload).drawn);
}

// GET `path` from 127.0.0.1:`port` (with more header lines `headers`, each
// ending in \r\n): the whole response.
std::string HttpResponse(int port, const std::string& path, const std::string& headers = "") {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    close(fd);
    return "connect failed";
  }
  const std::string request =
      "GET " + path + " HTTP/1.1\r\nHost: x\r\nConnection: close\r\n" + headers + "\r\n";
  (void)!write(fd, request.data(), request.size());
  std::string response;
  char buffer[65536];
  for (ssize_t n; (n = read(fd, buffer, sizeof buffer)) > 0;) response.append(buffer, n);
  close(fd);
  return response;
}

// GET `path`: the status line and the body.
std::pair<std::string, std::string> HttpGet(int port, const std::string& path,
                                            const std::string& headers = "") {
  const std::string response = HttpResponse(port, path, headers);
  const size_t body = response.find("\r\n\r\n");
  return {response.substr(0, response.find("\r\n")),
          body == std::string::npos ? "" : response.substr(body + 4)};
}

TEST(Viewer, ServesThePageAndThreeJsAndNothingElse) {
  auto sim = LoadDiffusion();
  Served served(*sim);
  auto [status, body] = HttpGet(served.port(), "/");
  EXPECT_EQ(status, "HTTP/1.1 200 OK");
  EXPECT_NE(body.find("<html"), std::string::npos);
  std::tie(status, body) = HttpGet(served.port(), "/three/build/three.module.js");
  EXPECT_EQ(status, "HTTP/1.1 200 OK");
  EXPECT_NE(body.find("InstancedMesh"), std::string::npos);
  std::tie(status, body) = HttpGet(served.port(), "/three/examples/jsm/controls/OrbitControls.js");
  EXPECT_EQ(status, "HTTP/1.1 200 OK");
  for (const char* path : {"/../../etc/passwd", "/three/../../../etc/passwd", "/nothing.js"}) {
    EXPECT_EQ(HttpGet(served.port(), path).first, "HTTP/1.1 404 Not Found") << path;
  }
}

// Bound to every interface, the run asks for the random token of the URL it
// printed: the page, its files and the WebSocket are refused without it.
TEST(Viewer, AnAddressOtherThanLoopbackNeedsTheUrlsToken) {
  auto sim = LoadDiffusion();
  ServeOptions options;
  options.host = "0.0.0.0";
  Served served(*sim, options);
  std::smatch match;
  const std::string url = served.url();
  ASSERT_TRUE(std::regex_search(
      url, match, std::regex("^http://0\\.0\\.0\\.0:[0-9]+/\\?token=([0-9a-f]{32})$")))
      << url;
  const std::string token = match[1];
  const int port = served.port();
  // Without it, or with another: 403, for the page, its files and three.js.
  for (const char* path : {"/", "/?token=", "/?token=0123456789abcdef0123456789abcdef",
                           "/viewer.js", "/three/build/three.module.js"}) {
    EXPECT_EQ(HttpGet(port, path).first, "HTTP/1.1 403 Forbidden") << path;
  }
  // With it: the page, and a cookie that lets the page's own requests in.
  const std::string page = HttpResponse(port, "/?token=" + token);
  EXPECT_EQ(page.substr(0, page.find("\r\n")), "HTTP/1.1 200 OK");
  ASSERT_TRUE(std::regex_search(page, match, std::regex("Set-Cookie: ([^=]+)=([0-9a-f]+);")));
  EXPECT_EQ(match[2], token);
  const std::string cookie = "Cookie: " + match[1].str() + "=" + token + "\r\n";
  EXPECT_EQ(HttpGet(port, "/viewer.js", cookie).first, "HTTP/1.1 200 OK");
  EXPECT_EQ(HttpGet(port, "/viewer.js", "Cookie: " + match[1].str() + "=x\r\n").first,
            "HTTP/1.1 403 Forbidden");
  // The WebSocket upgrade: refused (403) without the token, accepted with it.
  const std::string upgrade =
      "Upgrade: websocket\r\nConnection: Upgrade\r\nSec-WebSocket-Version: 13\r\n"
      "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n";
  EXPECT_EQ(HttpGet(port, "/", upgrade).first, "HTTP/1.1 403 Forbidden");
  WebSocketClient refused;
  std::string error;
  EXPECT_FALSE(refused.Connect("ws://127.0.0.1:" + std::to_string(port) + "/", 5s, error));
  WebSocketClient wrong;
  EXPECT_FALSE(wrong.Connect(
      "ws://127.0.0.1:" + std::to_string(port) + "/?token=" + std::string(32, 'a'), 5s, error));
  WebSocketClient client;
  Connect(client, "ws://127.0.0.1:" + std::to_string(port) + "/?token=" + token);
  ASSERT_TRUE(Next(client, "scene"));
  client.Send(R"({"cmd":"step"})");
  EXPECT_EQ(Decode(Next(client, "frame")->payload).tick, 0u);
  EXPECT_EQ(Decode(Next(client, "frame")->payload).tick, 1u);
  client.Close();
  served.Stop();
  EXPECT_EQ(sim->tick(), 1u);  // the refused connections changed nothing
}

// On loopback no token is asked for, unless one is given.
TEST(Viewer, LoopbackNeedsNoTokenUnlessGivenOne) {
  auto sim = LoadDiffusion();
  {
    Served served(*sim);
    EXPECT_EQ(served.url().find('?'), std::string::npos) << served.url();
    EXPECT_EQ(HttpGet(served.port(), "/").first, "HTTP/1.1 200 OK");
  }
  ServeOptions options;
  options.token = "secret-1";
  Served served(*sim, options);
  EXPECT_NE(served.url().find("/?token=secret-1"), std::string::npos) << served.url();
  const int port = served.port();
  EXPECT_EQ(HttpGet(port, "/").first, "HTTP/1.1 403 Forbidden");
  EXPECT_EQ(HttpGet(port, "/?token=secret-1").first, "HTTP/1.1 200 OK");
}

TEST(Viewer, AddressesAreCheckedAndABusyPortIsNamed) {
  ServeOptions options;
  ParseServeAddress("8080", options);
  EXPECT_EQ(options.host, "127.0.0.1");
  EXPECT_EQ(options.port, 8080);
  ParseServeAddress("0.0.0.0:9000", options);
  EXPECT_EQ(options.host, "0.0.0.0");
  EXPECT_EQ(options.port, 9000);
  ParseServeAddress("[::1]:7", options);
  EXPECT_EQ(options.host, "::1");
  for (const char* bad : {"", "http", "70000", ":80", "host:", "[::1]80", "-1", "123456"}) {
    try {
      ParseServeAddress(bad, options);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("expected [HOST:]PORT"), std::string::npos) << e.what();
    }
  }
  auto sim = LoadDiffusion();
  Served served(*sim);
  ServeOptions same;
  same.port = served.port();
  same.on_listening = [](const std::string&) {};
  try {
    ServeRun(*sim, same);
    ADD_FAILURE() << "served twice on port " << same.port;
  } catch (const RuntimeFailure& e) {
    EXPECT_NE(std::string(e.what()).find("cannot listen on 127.0.0.1:" + std::to_string(same.port)),
              std::string::npos)
        << e.what();
  }
}

// The page in a real browser: headless Chromium loads it from the server,
// draws the scene with WebGL (software) and writes what it drew into the
// DOM; screenshots are kept for docs/viewer.md. Chromium is driven through
// its DevTools protocol, so a screenshot is taken once the page says it has
// drawn (Chromium's --screenshot flag races with the page's WebSocket).

// Standard base64 (what DevTools sends screenshots in) to bytes.
std::string DecodeBase64(const std::string& text) {
  const std::string alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  uint32_t bits = 0;
  int count = 0;
  for (char c : text) {
    const size_t value = alphabet.find(c);
    if (value == std::string::npos) continue;  // '=' padding
    bits = (bits << 6) | static_cast<uint32_t>(value);
    count += 6;
    if (count >= 8) {
      count -= 8;
      out.push_back(static_cast<char>((bits >> count) & 0xFF));
    }
  }
  return out;
}

// Headless Chromium driven through its DevTools protocol (over our own
// WebSocket client): opens a page, evaluates expressions in it and sends it
// real mouse events. Ends the browser it started when it goes.
class DevToolsBrowser {
 public:
  // Starts `chromium` with a DevTools endpoint and a profile in `profile`;
  // why not ("" when started).
  std::string Start(const std::string& chromium, const std::string& profile) {
    std::filesystem::remove_all(profile);
    std::filesystem::create_directories(profile);
    const std::vector<std::string> args = {chromium,
                                           "--headless=new",
                                           "--no-sandbox",
                                           "--disable-gpu",
                                           "--use-angle=swiftshader",
                                           "--enable-unsafe-swiftshader",
                                           "--hide-scrollbars",
                                           "--window-size=1024,768",
                                           "--remote-debugging-port=0",
                                           "--remote-allow-origins=*",
                                           "--user-data-dir=" + profile,
                                           "about:blank"};
    pid_ = fork();
    if (pid_ == 0) {
      std::vector<char*> argv;
      for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
      argv.push_back(nullptr);
      const std::string log = profile + "/../chromium_drag.log";
      (void)!freopen(log.c_str(), "a", stderr);
      (void)!freopen("/dev/null", "w", stdout);
      execv(argv[0], argv.data());
      _exit(127);
    }
    // Chromium writes its port and the browser's path once it listens.
    const std::string active = profile + "/DevToolsActivePort";
    for (int k = 0; k < 300; ++k) {
      std::ifstream in(active);
      std::string port, path;
      if (std::getline(in, port) && std::getline(in, path) && !path.empty()) {
        std::string error;
        if (!client_.Connect("ws://127.0.0.1:" + port + path, 10s, error)) return error;
        return "";
      }
      std::this_thread::sleep_for(100ms);
    }
    return "no " + active + " after 30 s";
  }
  ~DevToolsBrowser() {
    client_.Close();
    if (pid_ > 0) {
      kill(pid_, SIGTERM);
      waitpid(pid_, nullptr, 0);
    }
  }

  // Calls `method`, in the page's session when there is one; its result.
  json Call(const std::string& method, json params = json::object()) {
    json message = {{"id", ++id_}, {"method", method}, {"params", std::move(params)}};
    if (!session_.empty()) message["sessionId"] = session_;
    client_.Send(message.dump());
    const auto deadline = std::chrono::steady_clock::now() + 30s;
    while (std::chrono::steady_clock::now() < deadline) {
      const auto m = client_.Receive(200ms);
      if (!m) continue;
      const json reply = json::parse(m->payload, nullptr, false);
      if (!reply.is_object() || reply.value("id", -1) != id_) continue;  // events
      EXPECT_FALSE(reply.contains("error")) << method << ": " << reply.dump();
      return reply.value("result", json::object());
    }
    ADD_FAILURE() << "no reply to " << method;
    return json::object();
  }
  // Opens `url` in a new tab and talks to it from now on.
  void Open(const std::string& url) {
    const json target = Call("Target.createTarget", {{"url", url}});
    session_ = Call("Target.attachToTarget",
                    {{"targetId", target.value("targetId", "")}, {"flatten", true}})
                   .value("sessionId", "");
  }
  // The value of a JavaScript expression in the page (JSON-able).
  json Evaluate(const std::string& expression) {
    return Call("Runtime.evaluate", {{"expression", expression}, {"returnByValue", true}})
        .value("result", json::object())
        .value("value", json());
  }
  // A mouse event at (x, y) CSS pixels, the left button, with shift held.
  void ShiftMouse(const std::string& type, double x, double y) {
    Call("Input.dispatchMouseEvent", {{"type", type},
                                      {"x", x},
                                      {"y", y},
                                      {"button", "left"},
                                      {"buttons", type == "mouseReleased" ? 0 : 1},
                                      {"clickCount", 1},
                                      {"modifiers", 8}});
  }

 private:
  pid_t pid_ = -1;
  WebSocketClient client_;
  int id_ = 0;
  std::string session_;
};

// Evaluates `expression` in the page every 100 ms, for up to 30 s, until it
// gives `expected`; the last value.
json WaitFor(DevToolsBrowser& browser, const std::string& expression, const json& expected) {
  json value;
  for (int k = 0; k < 300 && value != expected; ++k) {
    std::this_thread::sleep_for(100ms);
    value = browser.Evaluate(expression);
  }
  return value;
}

// Writes what the page shows now to the PNG file `path`.
void SaveScreenshot(DevToolsBrowser& browser, const std::string& path) {
  const std::string png =
      DecodeBase64(browser.Call("Page.captureScreenshot", {{"format", "png"}}).value("data", ""));
  ASSERT_GT(png.size(), 1000u) << path;
  std::ofstream(path, std::ios::binary) << png;
}

TEST(Viewer, ChromiumDrawsTheRobots) {
  const char* chromium = "/usr/bin/chromium";
  if (!std::filesystem::exists(chromium))
    GTEST_SKIP() << "chromium is not installed (apt-get install chromium)";
  auto sim = LoadDiffusion();
  Served served(*sim);
  const std::string dir = COLONY_BINARY_DIR "/tests/viewer";
  std::filesystem::create_directories(dir);
  DevToolsBrowser browser;
  ASSERT_EQ(browser.Start(chromium, dir + "/profile"), "");
  browser.Open(served.url());
  EXPECT_EQ(WaitFor(browser, "document.body.dataset.robotsDrawn || ''", std::to_string(kRobots)),
            std::to_string(kRobots))
      << "the page did not say it drew the robots";
  SaveScreenshot(browser, dir + "/viewer.png");
}

// A robot selected on the page (here by the address's ?select=) shows its
// proximity readings in the side panel, as the inspect reply gave them.
TEST(Viewer, ChromiumShowsTheSelectedRobotsReadings) {
  const char* chromium = "/usr/bin/chromium";
  if (!std::filesystem::exists(chromium))
    GTEST_SKIP() << "chromium is not installed (apt-get install chromium)";
  auto sim = LoadProbes();
  sim->Step();
  Served served(*sim);
  const std::string dir = COLONY_BINARY_DIR "/tests/viewer";
  std::filesystem::create_directories(dir);
  DevToolsBrowser browser;
  ASSERT_EQ(browser.Start(chromium, dir + "/profile_inspect"), "");
  browser.Open(served.url() + "?select=a");
  WaitFor(browser,
          "document.body.dataset.inspected === 'a' && "
          "document.getElementById('inspect').textContent.includes('proximity: 24 readings')",
          true);
  const json html = browser.Evaluate("document.documentElement.outerHTML");
  const std::string text = html.is_string() ? html.get<std::string>() : "";
  const std::string dom = dir + "/dom_inspect.html";
  std::ofstream(dom) << text;
  EXPECT_NE(text.find("data-inspected=\"a\""), std::string::npos) << "DOM in " << dom;
  // The panel: the controller, the ring's 24 readings, the wheels and the values.
  const size_t panel = text.find("id=\"inspect\"");
  ASSERT_NE(panel, std::string::npos) << dom;
  const std::string shown = text.substr(panel, text.find("</div>", panel) - panel);
  for (const char* expected : {"controller viewer_probe", "proximity: 24 readings",
                               "differential_steering", "left 0.010", "steps 1", "state odd"}) {
    EXPECT_NE(shown.find(expected), std::string::npos) << expected << " not in: " << shown;
  }
  SaveScreenshot(browser, dir + "/viewer_inspect.png");
}

// Shift + drag on the page, with the mouse of a real browser, moves robot c
// in the simulation: the server then has it where it was dropped.
TEST(Viewer, ChromiumShiftDragMovesTheRobotInTheSimulation) {
  const char* chromium = "/usr/bin/chromium";
  if (!std::filesystem::exists(chromium))
    GTEST_SKIP() << "chromium is not installed (apt-get install chromium)";
  auto sim = LoadProbes();
  Served served(*sim);
  const std::string dir = COLONY_BINARY_DIR "/tests/viewer";
  std::filesystem::create_directories(dir);
  DevToolsBrowser browser;
  const std::string started = browser.Start(chromium, dir + "/profile_drag");
  ASSERT_EQ(started, "");
  browser.Open(served.url());
  json drawn;
  for (int k = 0; k < 300 && drawn != "3"; ++k) {
    std::this_thread::sleep_for(100ms);
    drawn = browser.Evaluate("document.body.dataset.robotsDrawn || ''");
  }
  ASSERT_EQ(drawn, "3") << "the page did not draw the 3 robots";
  const json from = browser.Evaluate("window.colonyViewer.screenOf('c')");
  const json to = browser.Evaluate("window.colonyViewer.screenOfPoint(-1.5, 0.3, 0)");
  ASSERT_TRUE(from.is_array() && to.is_array()) << from << " " << to;
  browser.ShiftMouse("mousePressed", from[0], from[1]);
  for (int k = 1; k <= 5; ++k) {
    const double f = k / 5.0;
    browser.ShiftMouse("mouseMoved",
                       from[0].get<double>() + f * (to[0].get<double>() - from[0].get<double>()),
                       from[1].get<double>() + f * (to[1].get<double>() - from[1].get<double>()));
  }
  browser.ShiftMouse("mouseReleased", to[0], to[1]);
  // The server's own answer: c where it was dropped, the run marked moved.
  WebSocketClient client;
  Connect(client, served.ws());
  json c;
  for (int k = 0; k < 50; ++k) {
    client.Send(R"({"cmd":"inspect","id":"c"})");
    c = json::parse(Next(client, "inspect")->payload);
    if (std::abs(c["position"][0].get<double>() - -1.5) < 0.05) break;
    std::this_thread::sleep_for(100ms);
  }
  EXPECT_NEAR(c["position"][0].get<double>(), -1.5, 0.03) << c["position"];
  EXPECT_NEAR(c["position"][1].get<double>(), 0.3, 0.03) << c["position"];
  client.Send(R"({"cmd":"pause"})");
  EXPECT_EQ(json::parse(Next(client, "status")->payload)["moved"], true);
  client.Close();
  served.Stop();
  EXPECT_NEAR(testing::PositionOf(*sim, "c").x(), -1.5, 0.03);
  EXPECT_NEAR(testing::PositionOf(*sim, "c").y(), 0.3, 0.03);
  EXPECT_EQ(sim->tick(), 0u);
}

// What the loop functions draw shows on the page (the eye-bot guidance
// example's target regions and its text, as HTML labels), and so do the
// overlays asked for in the address (robot ids, the selected robot's
// proximity rays). The screenshot is
// docs/viewer_drawing.png.
TEST(Viewer, ChromiumShowsWhatTheLoopFunctionsDrawAndTheIdOverlay) {
  const char* chromium = "/usr/bin/chromium";
  if (!std::filesystem::exists(chromium))
    GTEST_SKIP() << "chromium is not installed (apt-get install chromium)";
  ExperimentOptions options;
  options.file = COLONY_SOURCE_DIR "/experiments/eyebot_guidance.xml";
  options.threads = 1;
  auto sim = Simulation::Load(options);
  while (sim->tick() < 600) sim->Step();  // foot-bots gather at the marked target
  Served served(*sim);
  const std::string dir = COLONY_BINARY_DIR "/tests/viewer";
  std::filesystem::create_directories(dir);
  DevToolsBrowser browser;
  ASSERT_EQ(browser.Start(chromium, dir + "/profile_drawing"), "");
  browser.Open(served.url() + "?overlays=ids,rays,fov&select=fb2");
  // Drawn, with fb2's inspection in: its 24 rays and its camera's range (48 segments).
  WaitFor(browser, "document.body.dataset.overlayLines === '72'", true);
  // The id labels may come a frame after the rays (seen on a busy machine).
  WaitFor(browser,
          "['>fb0<', '>fb9<', '>eye0<'].every(s => "
          "document.documentElement.outerHTML.includes(s))",
          true);
  const json html = browser.Evaluate("document.documentElement.outerHTML");
  const std::string text = html.is_string() ? html.get<std::string>() : "";
  const std::string dom = dir + "/dom_drawing.html";
  std::ofstream(dom) << text;
  std::smatch match;
  ASSERT_TRUE(
      std::regex_search(text, match, std::regex("data-drawn=\"(\\d+) (\\d+) (\\d+) (\\d+)\"")))
      << "DOM in " << dom;
  EXPECT_EQ(match[3], "2") << "the reach and mark circles";
  EXPECT_EQ(match[4], "1") << "the text";
  EXPECT_GE(std::stoi(match[2]), 1) << "lines to the foot-bots within reach";
  EXPECT_TRUE(std::regex_search(text, std::regex("class=\"drawn-text\"[^>]*>reached \\d/5<")))
      << "DOM in " << dom;
  // fb2 selected: its 24 proximity rays and its omnidirectional camera's range.
  EXPECT_NE(text.find("data-overlay-lines=\"72\""), std::string::npos) << "DOM in " << dom;
  for (const char* id : {">fb0<", ">fb9<", ">eye0<"}) {
    EXPECT_NE(text.find(id), std::string::npos) << id << " not labelled; DOM in " << dom;
  }
  SaveScreenshot(browser, dir + "/viewer_drawing.png");
}

// The trails overlay, on while the run plays, keeps each robot's positions
// from the frames: a segment per robot per frame after the first.
TEST(Viewer, ChromiumTrailsGrowAsTheRunPlays) {
  const char* chromium = "/usr/bin/chromium";
  if (!std::filesystem::exists(chromium))
    GTEST_SKIP() << "chromium is not installed (apt-get install chromium)";
  auto sim = LoadDiffusion();
  ServeOptions options;
  options.start_playing = true;
  Served served(*sim, options);
  const std::string dir = COLONY_BINARY_DIR "/tests/viewer";
  std::filesystem::create_directories(dir);
  DevToolsBrowser browser;
  ASSERT_EQ(browser.Start(chromium, dir + "/profile_trails"), "");
  browser.Open(served.url() + "?overlays=trails");
  json lines;
  for (int k = 0; k < 300; ++k) {
    std::this_thread::sleep_for(100ms);
    lines = browser.Evaluate("Number(document.body.dataset.overlayLines || 0)");
    if (lines.is_number() && lines.get<int>() >= 5 * kRobots) break;
  }
  ASSERT_TRUE(lines.is_number());
  EXPECT_GE(lines.get<int>(), 5 * kRobots) << "not 6 frames' trails after 30 s";
  EXPECT_EQ(lines.get<int>() % kRobots, 0) << "every robot's trail grows by one a frame";
}

// The served program's first line that holds its URL (log lines may come
// first); "" after `limit` lines or at the end of its output.
std::string UrlLine(FILE* out, int limit = 20) {
  char line[512] = {};
  for (int k = 0; k < limit && std::fgets(line, sizeof line, out); ++k) {
    if (std::strstr(line, "http://")) return line;
  }
  return "";
}

// The command a user types: `colony run FILE --serve 0` prints the URL,
// serves the run paused, steps when asked and ends with the page's quit.
TEST(Viewer, ColonyRunServeServesTheRunUntilThePageEndsIt) {
  // `timeout`: a failed check leaves no server behind holding ctest's output.
  const std::string command = std::string("timeout 120 " COLONY_BINARY_DIR "/bin/colony run ") +
                              COLONY_SOURCE_DIR
                              "/experiments/diffusion.xml --set "
                              "arena.distribute.entity.quantity=7 --threads 1 --serve 0 2>&1";
  FILE* out = popen(command.c_str(), "r");
  ASSERT_NE(out, nullptr);
  char line[512] = {};
  std::smatch url;
  const std::string first = UrlLine(out);
  ASSERT_TRUE(std::regex_search(first, url, std::regex("http://127\\.0\\.0\\.1:([0-9]+)/")))
      << first;
  EXPECT_NE(first.find("7 robots, paused at tick 0"), std::string::npos) << first;
  WebSocketClient client;
  Connect(client, "ws://127.0.0.1:" + url[1].str() + "/");
  const auto scene = Next(client, "scene");
  ASSERT_TRUE(scene);
  EXPECT_EQ(json::parse(scene->payload)["movers"].size(), 7u);
  Next(client, "frame");  // tick 0
  client.Send(R"({"cmd":"step"})");
  client.Send(R"({"cmd":"step"})");
  for (int frames = 0; frames < 2;) {
    if (!Next(client, "frame")) break;
    ++frames;
  }
  client.Send(R"({"cmd":"quit"})");
  std::string rest;
  while (std::fgets(line, sizeof line, out)) rest += line;
  const int status = pclose(out);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << rest;
  EXPECT_NE(rest.find("served 2 ticks of 7 robots"), std::string::npos) << rest;
}

// What cannot be served is refused before loading, with the reason.
TEST(Viewer, ColonyRunServeRefusesABadAddressAndARunFolder) {
  const std::string colony =
      COLONY_BINARY_DIR "/bin/colony run " COLONY_SOURCE_DIR "/experiments/diffusion.xml ";
  auto r = testing::RunCommand(colony + "--serve 70000 2>&1");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("--serve '70000'"), std::string::npos) << r.output;
  r = testing::RunCommand(colony + "--serve 0 --out /tmp/colony_serve_out 2>&1");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("--serve and --out do not go together"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists("/tmp/colony_serve_out"));
}

// --- Replays (colony view) -------------------------------------------------

namespace fs = std::filesystem;

// Folders removed when the test process ends.
struct TempFolders {
  std::map<std::string, fs::path> folders;
  ~TempFolders() {
    for (const auto& [name, dir] : folders) fs::remove_all(dir);
  }
};
TempFolders recorded, bad_folders;

// A run of 7 diffusing robots for 3 s (30 ticks) recorded with `colony run`
// every 5 ticks, as CSV or HDF5; recorded once per format and process.
fs::path RecordedRun(const std::string& format) {
  if (recorded.folders.count(format)) return recorded.folders[format];
  const fs::path dir = testing::FreshTempDir("colony_view", format);
  const auto r = testing::RunCommand(
      std::string(COLONY_BINARY_DIR "/bin/colony run ") + COLONY_SOURCE_DIR +
      "/experiments/diffusion.xml --quiet --threads 1 --out " + dir.string() +
      " --set arena.distribute.entity.quantity=7 --set framework.experiment.length=3"
      " --set output.trajectories_every=5 --set output.format=" +
      format);
  EXPECT_EQ(r.status, 0) << r.output;
  recorded.folders[format] = dir;
  return dir;
}

// A replay served on a free port in a thread, for as long as the object lives.
class Replayed {
 public:
  explicit Replayed(const fs::path& folder) {
    std::promise<std::string> url;
    auto listening = url.get_future();
    ServeOptions options;
    options.stop = &stop_;
    options.on_listening = [&url](const std::string& u) { url.set_value(u); };
    thread_ = std::thread([this, folder, options] {
      try {
        ServeReplay(folder.string(), options);
      } catch (const std::exception& e) {
        ADD_FAILURE() << e.what();
      }
    });
    if (listening.wait_for(20s) == std::future_status::ready)
      ws_ = "ws" + listening.get().substr(4);
  }
  ~Replayed() {
    stop_ = true;
    thread_.join();
  }
  const std::string& ws() const { return ws_; }

 private:
  std::atomic<bool> stop_{false};
  std::thread thread_;
  std::string ws_;
};

// The trajectories.csv rows of `tick`: id -> (x, y, z, yaw).
std::map<std::string, std::array<double, 4>> CsvPoses(const fs::path& dir, uint64_t tick) {
  const auto csv = sweep::ReadCsvFile((dir / "trajectories.csv").string());
  const auto& header = csv.records.at(0);
  auto at = [&](const char* name) {
    return std::find(header.begin(), header.end(), name) - header.begin();
  };
  std::map<std::string, std::array<double, 4>> poses;
  for (size_t r = 1; r < csv.records.size(); ++r) {
    const auto& row = csv.records[r];
    if (std::stoull(row[at("tick")]) != tick) continue;
    poses[row[at("id")]] = {std::stod(row[at("x")]), std::stod(row[at("y")]),
                            std::stod(row[at("z")]), std::stod(row[at("yaw")])};
  }
  return poses;
}

// Connects to a replay, steps to recorded tick 15 (three steps of 5 ticks)
// and checks the frame against the CSV rows of tick 15 and the live run.
void CheckReplayAtTick15(const fs::path& dir) {
  Replayed replay(dir);
  ASSERT_FALSE(replay.ws().empty());
  WebSocketClient client;
  Connect(client, replay.ws());
  const auto scene = Next(client, "scene");
  ASSERT_TRUE(scene);
  const json s = json::parse(scene->payload);
  EXPECT_TRUE(s["replay"].get<bool>());
  ASSERT_EQ(s["movers"].size(), 7u);
  const auto status = Next(client, "status");
  ASSERT_TRUE(status);
  EXPECT_EQ(json::parse(status->payload)["tick"], 0);
  ASSERT_TRUE(Next(client, "frame"));
  for (int i = 0; i < 3; ++i) client.Send(R"({"cmd":"step"})");
  std::optional<Frame> frame;
  while (auto m = Next(client, "frame")) {
    frame = Decode(m->payload);
    if (frame->tick >= 15) break;
  }
  ASSERT_TRUE(frame);
  ASSERT_EQ(frame->tick, 15u);
  ASSERT_EQ(frame->records.size(), 7u);

  // The recorded rows of tick 15, and the live run stepped to tick 15.
  const auto rows = CsvPoses(RecordedRun("csv"), 15);
  ASSERT_EQ(rows.size(), 7u);
  ExperimentOptions options;
  options.file = (dir / "experiment.xml").string();
  auto live = Simulation::Load(options);
  for (int t = 0; t < 15; ++t) live->Step();
  for (size_t i = 0; i < 7; ++i) {
    const std::string id = s["movers"][i]["id"];
    const auto& r = frame->records[i];
    ASSERT_TRUE(rows.count(id)) << id;
    const auto& row = rows.at(id);
    EXPECT_EQ(r.x, static_cast<float>(row[0])) << id;
    EXPECT_EQ(r.y, static_cast<float>(row[1])) << id;
    EXPECT_EQ(r.z, static_cast<float>(row[2])) << id;
    EXPECT_NEAR(r.yaw, row[3], 1e-6) << id;
    const Vec3 p = testing::PositionOf(*live, id);
    EXPECT_EQ(r.x, static_cast<float>(p.x())) << id;
    EXPECT_EQ(r.y, static_cast<float>(p.y())) << id;
  }

  // Inspect, move and rays are refused, saying why; the replay stays at tick 15.
  client.Send(R"({"cmd":"inspect","id":")" + s["movers"][0]["id"].get<std::string>() + R"("})");
  auto error = Next(client, "error");
  ASSERT_TRUE(error);
  EXPECT_NE(json::parse(error->payload)["message"].get<std::string>().find("replay"),
            std::string::npos)
      << error->payload;
  client.Send(R"({"cmd":"move","id":")" + s["movers"][0]["id"].get<std::string>() +
              R"(","x":0,"y":0})");
  error = Next(client, "error");
  ASSERT_TRUE(error);
  EXPECT_NE(json::parse(error->payload)["message"].get<std::string>().find("move"),
            std::string::npos);
  client.Send(R"({"cmd":"rays"})");
  error = Next(client, "error");
  ASSERT_TRUE(error);
  EXPECT_NE(
      json::parse(error->payload)["message"].get<std::string>().find("rays: this is a replay"),
      std::string::npos)
      << error->payload;

  // Reset goes back to tick 0; play runs to the last recorded tick (30).
  client.Send(R"({"cmd":"reset"})");
  client.Send(R"({"cmd":"speed","value":"max"})");
  client.Send(R"({"cmd":"play"})");
  bool done = false;
  while (auto m = Next(client, "status")) {
    const json st = json::parse(m->payload);
    if (st["done"].get<bool>()) {
      EXPECT_EQ(st["tick"], 30);
      done = true;
      break;
    }
  }
  EXPECT_TRUE(done);
}

TEST(Viewer, ReplayOfACsvRecordShowsTheRunsPositionsAtATick) {
  CheckReplayAtTick15(RecordedRun("csv"));
}

TEST(Viewer, ReplayOfAnHdf5RecordShowsTheRunsPositionsAtATick) {
  CheckReplayAtTick15(RecordedRun("hdf5"));
}

// The error ServeReplay gives for `folder` ("" if none); it must fail
// before serving (a replay that starts is stopped at once).
std::string ReplayError(const fs::path& folder) {
  const std::atomic<bool> stop{true};
  ServeOptions options;
  options.stop = &stop;
  options.on_listening = [](const std::string&) {};
  try {
    ServeReplay(folder.string(), options);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

// A run recorded with <output leds="true"> replays with the LED colours it
// had: the aggregation example's robots turn from green (walking) to red
// (staying in a spot). At a recorded tick where some are red and some
// green, the replay's frame gives each robot the colour of its row, which
// is the live run's at that tick; from CSV and from HDF5 alike.
TEST(Viewer, ReplayOfARunRecordedWithLedsShowsTheirColours) {
  std::map<std::string, fs::path> dirs;
  for (const std::string format : {"csv", "hdf5"}) {
    dirs[format] = testing::FreshTempDir("colony_view_leds", format);
    const auto r = testing::RunCommand(
        std::string(COLONY_BINARY_DIR "/bin/colony run ") + COLONY_SOURCE_DIR +
        "/experiments/aggregation.xml --quiet --threads 1 --out " + dirs[format].string() +
        " --set framework.experiment.length=60 --set output.trajectories_every=100"
        " --set output.leds=true --set output.format=" +
        format);
    ASSERT_EQ(r.status, 0) << r.output;
  }
  // The CSV's colours per recorded tick: id -> (r, g, b).
  const auto csv = sweep::ReadCsvFile((dirs["csv"] / "trajectories.csv").string());
  const auto& header = csv.records.at(0);
  auto at = [&](const char* name) {
    return std::find(header.begin(), header.end(), name) - header.begin();
  };
  ASSERT_LT(at("led_b"), static_cast<long>(header.size()));
  std::map<uint64_t, std::map<std::string, std::array<int, 3>>> colors;
  for (size_t r = 1; r < csv.records.size(); ++r) {
    const auto& row = csv.records[r];
    colors[std::stoull(row[at("tick")])][row[at("id")]] = {
        std::stoi(row[at("led_r")]), std::stoi(row[at("led_g")]), std::stoi(row[at("led_b")])};
  }
  // The first recorded tick where red and green robots are both there.
  const std::array<int, 3> red = {255, 0, 0}, green = {0, 255, 0};
  uint64_t shown = 0;
  size_t steps = 0;
  for (const auto& [tick, of] : colors) {
    int reds = 0, greens = 0;
    for (const auto& [id, c] : of) {
      reds += c == red;
      greens += c == green;
    }
    if (reds > 0 && greens > 0) {
      shown = tick;
      break;
    }
    ++steps;
  }
  ASSERT_GT(shown, 0u) << "no recorded tick with both staying (red) and walking robots";
  ExperimentOptions options;
  options.file = (dirs["csv"] / "experiment.xml").string();
  auto live = Simulation::Load(options);
  while (live->tick() < shown) live->Step();
  for (const auto& [format, dir] : dirs) {
    Replayed replay(dir);
    ASSERT_FALSE(replay.ws().empty());
    WebSocketClient client;
    Connect(client, replay.ws());
    const json scene = json::parse(Next(client, "scene")->payload);
    ASSERT_TRUE(Next(client, "frame"));
    for (size_t k = 0; k < steps; ++k) client.Send(R"({"cmd":"step"})");
    std::optional<Frame> frame;
    while (auto m = Next(client, "frame")) {
      frame = Decode(m->payload);
      if (frame->tick >= shown) break;
    }
    ASSERT_TRUE(frame);
    ASSERT_EQ(frame->tick, shown) << format;
    ASSERT_EQ(frame->records.size(), colors[shown].size());
    for (size_t i = 0; i < frame->records.size(); ++i) {
      const std::string id = scene["movers"][i]["id"];
      const auto& r = frame->records[i];
      EXPECT_EQ((std::array<int, 3>{r.r, r.g, r.b}), colors[shown][id]) << format << " " << id;
      const Color c = live->space().leds(live->space().Find(id).index)[0];
      EXPECT_EQ((std::array<int, 3>{c.r, c.g, c.b}), colors[shown][id]) << "live " << id;
    }
    client.Close();
  }
}

// A copy of the CSV run folder with trajectories.csv replaced by `text`
// (or none when `name` is empty), as file `name`.
fs::path BadFolder(const std::string& tag, const std::string& name, const std::string& text) {
  const fs::path dir = testing::FreshTempDir("colony_view_bad", tag);
  fs::create_directories(dir);
  bad_folders.folders[tag] = dir;
  fs::copy_file(RecordedRun("csv") / "experiment.xml", dir / "experiment.xml");
  if (!name.empty()) std::ofstream(dir / name, std::ios::binary) << text;
  return dir;
}

TEST(Viewer, ReplayRefusesWhatIsNotAWholeRecordOfTheRun) {
  const fs::path csv = RecordedRun("csv");
  const std::string rows = testing::ReadFile(csv / "trajectories.csv");
  ASSERT_GT(rows.size(), 100u);
  EXPECT_TRUE(testing::Mentions(ReplayError("/nonexistent/run"), {"is not a folder"}));
  EXPECT_TRUE(testing::Mentions(ReplayError(COLONY_SOURCE_DIR "/docs"), {"not a run folder"}));
  EXPECT_TRUE(testing::Mentions(ReplayError(BadFolder("none", "", "")),
                                {"no trajectories", "trajectories_every"}));
  // Cut in the middle of a row.
  EXPECT_TRUE(testing::Mentions(
      ReplayError(BadFolder("cut", "trajectories.csv", rows.substr(0, rows.size() - 7))),
      {"cut short"}));
  // A header only; a number that is not one; a robot the experiment lacks.
  EXPECT_TRUE(testing::Mentions(
      ReplayError(BadFolder("empty", "trajectories.csv", rows.substr(0, rows.find('\n') + 1))),
      {"no rows"}));
  std::string garbled = rows;
  garbled.replace(garbled.rfind('\n', garbled.size() - 2) + 1, 2, "30,3,x,y,zz");
  EXPECT_TRUE(
      testing::Mentions(ReplayError(BadFolder("garbled", "trajectories.csv", garbled)), {"line"}));
  std::string ghost = rows;
  const size_t last = ghost.rfind('\n', ghost.size() - 2) + 1;
  std::string row = ghost.substr(last);
  const size_t id = row.find(',', row.find(',') + 1) + 1;
  row.replace(id, row.find(',', id) - id, "ghost");
  ghost += row;
  EXPECT_TRUE(testing::Mentions(ReplayError(BadFolder("ghost", "trajectories.csv", ghost)),
                                {"robot 'ghost'", "not in the run's experiment.xml"}));
  // LED columns: some but not all three; a channel that is not 0 to 255.
  auto with_columns = [&](const std::string& header, const std::string& cells) {
    std::string out;
    std::istringstream in(rows);
    for (std::string line; std::getline(in, line);)
      out += line + (out.empty() ? header : cells) + "\n";
    return out;
  };
  EXPECT_TRUE(testing::Mentions(
      ReplayError(BadFolder("led_r", "trajectories.csv", with_columns(",led_r", ",0"))),
      {"led_r, led_g, led_b but not all three"}));
  EXPECT_TRUE(
      testing::Mentions(ReplayError(BadFolder("led300", "trajectories.csv",
                                              with_columns(",led_r,led_g,led_b", ",0,300,0"))),
                        {"led_g 300", "not a colour channel"}));
  // Damaged gzip and HDF5 files.
  EXPECT_TRUE(testing::Mentions(
      ReplayError(BadFolder("gz", "trajectories.csv.gz", std::string("\x1f\x8b\x08\0", 4))),
      {"trajectories.csv.gz"}));
  const std::string h5 = testing::ReadFile(RecordedRun("hdf5") / "trajectories.h5");
  ASSERT_GT(h5.size(), 1000u);
  EXPECT_TRUE(testing::Mentions(
      ReplayError(BadFolder("h5", "trajectories.h5", h5.substr(0, h5.size() / 2))),
      {"trajectories.h5"}));
  EXPECT_TRUE(testing::Mentions(ReplayError(BadFolder("noth5", "trajectories.h5", rows)),
                                {"not a readable HDF5 file"}));
  // The command: exit status 2 for each, 2 for a bad command line.
  EXPECT_EQ(ViewCommand({BadFolder("none2", "", "").string(), "--serve", "0"}), 2);
  EXPECT_EQ(ViewCommand({csv.string(), "--serve", "70000"}), 2);
  EXPECT_EQ(ViewCommand({}), 2);
  EXPECT_EQ(ViewCommand({csv.string(), "--bogus"}), 2);
}

// The command a user types: `colony view RUN_FOLDER --serve 0` serves the
// recorded run as a replay until the page ends it.
TEST(Viewer, ColonyViewServesAReplayOfARecordedRun) {
  const std::string folder = COLONY_BINARY_DIR "/tests/viewer/colony_view_run";
  std::filesystem::remove_all(folder);
  const std::string colony = COLONY_BINARY_DIR "/bin/colony ";
  const auto recorded = testing::RunCommand(
      colony +
      "run " COLONY_SOURCE_DIR
      "/experiments/diffusion.xml --set "
      "arena.distribute.entity.quantity=5 --set framework.experiment.length=2 --set "
      "output.trajectories_every=5 --quiet --out " +
      folder);
  ASSERT_EQ(recorded.status, 0) << recorded.output;
  // `timeout`: a failed check leaves no server behind holding ctest's output.
  FILE* out = popen(("timeout 120 " + colony + "view " + folder + " --serve 0 2>&1").c_str(), "r");
  ASSERT_NE(out, nullptr);
  char line[512] = {};
  const std::string first = UrlLine(out);
  std::smatch url;
  ASSERT_TRUE(std::regex_search(first, url, std::regex("http://127\\.0\\.0\\.1:([0-9]+)/")))
      << first;
  WebSocketClient client;
  Connect(client, "ws://127.0.0.1:" + url[1].str() + "/");
  const auto scene = Next(client, "scene");
  ASSERT_TRUE(scene);
  const json j = json::parse(scene->payload);
  EXPECT_EQ(j["replay"], true);
  EXPECT_EQ(j["movers"].size(), 5u);
  client.Send(R"({"cmd":"quit"})");
  std::string rest;
  while (std::fgets(line, sizeof line, out)) rest += line;
  const int status = pclose(out);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << rest;
  std::filesystem::remove_all(folder);
}

}  // namespace
}  // namespace colony
