// colony_viewer_probe: a stand-in browser for measuring what serving costs.
// Connects to a served run, sends play at "max" speed, and reads frames until
// the server closes or the time is up; prints frames and bytes per second.
//   colony_viewer_probe ws://127.0.0.1:8080/ [SECONDS]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "apps/colony/viewer/ws_client.h"

int main(int argc, char** argv) {
  if (argc < 2 || argc > 3) {
    std::fprintf(stderr, "usage: colony_viewer_probe ws://HOST:PORT/ [SECONDS]\n");
    return 2;
  }
  const double limit = argc == 3 ? std::atof(argv[2]) : 3600;
  colony::viewer::WebSocketClient client;
  std::string error;
  if (!client.Connect(argv[1], std::chrono::seconds(5), error)) {
    std::fprintf(stderr, "colony_viewer_probe: cannot connect to %s: %s\n", argv[1], error.c_str());
    return 1;
  }
  client.Send(R"({"cmd":"speed","value":"max"})");
  client.Send(R"({"cmd":"play"})");
  const auto start = std::chrono::steady_clock::now();
  double frames = 0, bytes = 0, seconds = 0;
  while (!client.closed() && seconds < limit) {
    if (auto m = client.Receive(std::chrono::milliseconds(100)); m && m->binary) {
      ++frames;
      bytes += static_cast<double>(m->payload.size());
    }
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  std::printf("%.0f frames, %.3g bytes in %.2f s: %.1f frames/s, %.3g bytes/s\n", frames, bytes,
              seconds, frames / seconds, bytes / seconds);
  return 0;
}
