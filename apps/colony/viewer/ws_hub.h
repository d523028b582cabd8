// The viewer's transport: an HTTP + WebSocket server (websocketpp on
// standalone asio) running on its own network thread. It knows nothing of
// simulations: it serves files through a callback, hands every message a
// browser sends to a callback, and sends what it is given. Every public
// method may be called from any thread.
//
// This header is plain C++17: ws_hub.cpp is compiled as C++17, since
// websocketpp 0.8.2's headers do not compile as C++20 (template-ids on
// constructors and destructors, removed from the language).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

namespace colony::viewer {

// What the handlers see of an HTTP request (a GET, or a WebSocket upgrade).
struct HttpRequest {
  std::string resource;  // "/path?query"
  std::string cookie;    // the Cookie header, "" without one
};

// The answer to an HTTP GET.
struct HttpReply {
  int status = 200;
  std::string content_type = "text/plain";
  std::string body;
  std::string set_cookie;  // a Set-Cookie header's value, "" for none
};

class WebSocketHub {
 public:
  using ConnectionId = uint64_t;
  // Called on the network thread; they must not block for long.
  struct Handlers {
    std::function<HttpReply(const HttpRequest&)> http;
    // Whether a WebSocket upgrade may go ahead (unset: always); a refused
    // one is answered 403 Forbidden.
    std::function<bool(const HttpRequest&)> accept;
    std::function<void(ConnectionId)> open, close;
    std::function<void(ConnectionId, const std::string& payload, bool binary)> message;
  };
  // `max_message_bytes`: a longer message from a browser closes its
  // connection (status 1009, "message too big"). `max_buffered_bytes`: a
  // droppable message is not sent to a connection with more than this still
  // waiting to go out (a stalled browser), so it never grows without bound;
  // a connection with twice that waiting is closed (1008, policy violation).
  WebSocketHub(Handlers handlers, size_t max_message_bytes, size_t max_buffered_bytes);
  ~WebSocketHub();  // Stop()
  WebSocketHub(const WebSocketHub&) = delete;
  WebSocketHub& operator=(const WebSocketHub&) = delete;

  // Listens on `host`:`port` (0: any free port) and starts the network
  // thread. Returns the port listened on. Throws std::runtime_error naming
  // the address and the reason (address in use, unknown host...).
  int Start(const std::string& host, int port);
  // Closes every connection and stops the network thread.
  void Stop();

  // Queue a message to one connection, or to all; `binary` chooses the
  // WebSocket opcode. A connection that closed in between is skipped.
  void Send(ConnectionId to, std::shared_ptr<const std::string> data, bool binary);
  void Broadcast(std::shared_ptr<const std::string> data, bool binary, bool droppable);
  // Open WebSocket connections now.
  size_t connections() const;
  // Droppable messages not sent to stalled connections so far.
  uint64_t dropped() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace colony::viewer
