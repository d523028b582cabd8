// A WebSocket client for the viewer's tests and its cost measurement
// (websocketpp's client on asio; plain C++17, as ws_hub.h). It connects,
// sends text, and queues what it receives for the caller to take.
#pragma once

#include <chrono>
#include <memory>
#include <optional>
#include <string>

namespace colony::viewer {

class WebSocketClient {
 public:
  struct Message {
    std::string payload;
    bool binary = false;
  };
  WebSocketClient();
  ~WebSocketClient();
  // Connects to e.g. "ws://127.0.0.1:8080/"; false (with `error` set) when
  // it cannot within `timeout`.
  bool Connect(const std::string& uri, std::chrono::milliseconds timeout, std::string& error);
  void Send(const std::string& data, bool binary = false);
  // The next message received, or nothing after `timeout`.
  std::optional<Message> Receive(std::chrono::milliseconds timeout);
  // Whether the server closed the connection, and its close code (0 if open).
  bool closed() const;
  int close_code() const;
  void Close();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace colony::viewer
