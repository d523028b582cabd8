#include "apps/colony/viewer/ws_hub.h"

#include <atomic>
#include <chrono>
#include <map>
#include <stdexcept>
#include <thread>
#include <websocketpp/config/asio_no_tls.hpp>
#include <websocketpp/server.hpp>

namespace colony::viewer {

using Server = websocketpp::server<websocketpp::config::asio>;
using Handle = websocketpp::connection_hdl;

struct WebSocketHub::Impl {
  Handlers handlers;
  size_t max_buffered_bytes = 0;
  Server server;
  std::thread thread;
  // Only touched on the network thread.
  std::map<Handle, ConnectionId, std::owner_less<Handle>> ids;
  std::map<ConnectionId, Handle> handles;
  ConnectionId next_id = 1;
  std::atomic<size_t> open_count{0};
  std::atomic<uint64_t> dropped{0};
  bool running = false;

  void SendNow(const Handle& h, const std::string& data, bool binary, bool droppable) {
    websocketpp::lib::error_code ec;
    Server::connection_ptr con = server.get_con_from_hdl(h, ec);
    if (ec || !con || con->get_state() != websocketpp::session::state::open) return;
    const size_t waiting = con->get_buffered_amount();
    if (droppable && waiting > max_buffered_bytes) {
      dropped.fetch_add(1, std::memory_order_relaxed);
      return;
    }
    // What cannot be dropped (statuses, scenes, replies) still has a bound: a
    // connection that reads nothing while it keeps asking is cut off (its
    // close frame waits behind the rest; websocketpp ends the connection when
    // the close handshake times out, 5 s later).
    if (waiting > 2 * max_buffered_bytes) {
      websocketpp::lib::error_code ignored;
      con->close(websocketpp::close::status::policy_violation,
                 "the client reads nothing of what it is sent", ignored);
      return;
    }
    // An error here is a connection closing under us: its close handler follows.
    (void)con->send(data,
                    binary ? websocketpp::frame::opcode::binary : websocketpp::frame::opcode::text);
  }
};

WebSocketHub::WebSocketHub(Handlers handlers, size_t max_message_bytes, size_t max_buffered_bytes)
    : impl_(std::make_unique<Impl>()) {
  Impl& d = *impl_;
  d.handlers = std::move(handlers);
  d.max_buffered_bytes = max_buffered_bytes;
  Server& s = d.server;
  // The viewer logs what matters itself; websocketpp's own lines would be noise.
  s.clear_access_channels(websocketpp::log::alevel::all);
  s.clear_error_channels(websocketpp::log::elevel::all);
  s.init_asio();
  s.set_reuse_addr(true);
  s.set_max_message_size(max_message_bytes);
  s.set_http_handler([&d](Handle h) {
    Server::connection_ptr con = d.server.get_con_from_hdl(h);
    const HttpReply reply =
        d.handlers.http({con->get_resource(), con->get_request_header("Cookie")});
    con->set_status(static_cast<websocketpp::http::status_code::value>(reply.status));
    con->replace_header("Content-Type", reply.content_type);
    con->replace_header("Cache-Control", "no-cache");
    if (!reply.set_cookie.empty()) con->replace_header("Set-Cookie", reply.set_cookie);
    con->set_body(reply.body);
  });
  s.set_validate_handler([&d](Handle h) {
    if (!d.handlers.accept) return true;
    Server::connection_ptr con = d.server.get_con_from_hdl(h);
    if (d.handlers.accept({con->get_resource(), con->get_request_header("Cookie")})) return true;
    con->set_status(websocketpp::http::status_code::forbidden);
    return false;
  });
  s.set_open_handler([&d](Handle h) {
    const ConnectionId id = d.next_id++;
    d.ids[h] = id;
    d.handles[id] = h;
    d.open_count.store(d.handles.size());
    if (d.handlers.open) d.handlers.open(id);
  });
  auto closed = [&d](Handle h) {
    auto it = d.ids.find(h);
    if (it == d.ids.end()) return;
    const ConnectionId id = it->second;
    d.handles.erase(id);
    d.ids.erase(it);
    d.open_count.store(d.handles.size());
    if (d.handlers.close) d.handlers.close(id);
  };
  s.set_close_handler(closed);
  s.set_fail_handler(closed);
  s.set_message_handler([&d](Handle h, Server::message_ptr msg) {
    auto it = d.ids.find(h);
    if (it == d.ids.end() || !d.handlers.message) return;
    d.handlers.message(it->second, msg->get_payload(),
                       msg->get_opcode() == websocketpp::frame::opcode::binary);
  });
}

WebSocketHub::~WebSocketHub() { Stop(); }

int WebSocketHub::Start(const std::string& host, int port) {
  Impl& d = *impl_;
  websocketpp::lib::error_code ec;
  d.server.listen(host, std::to_string(port), ec);
  if (ec) {
    throw std::runtime_error("cannot listen on " + host + ":" + std::to_string(port) + ": " +
                             ec.message());
  }
  const auto endpoint = d.server.get_local_endpoint(ec);
  if (ec) throw std::runtime_error("cannot read the listening port: " + ec.message());
  d.server.start_accept(ec);
  if (ec) throw std::runtime_error("cannot accept connections: " + ec.message());
  d.running = true;
  d.thread = std::thread([&d] { d.server.run(); });
  return endpoint.port();
}

void WebSocketHub::Stop() {
  Impl& d = *impl_;
  if (!d.running) return;
  d.running = false;
  // Politely first: stop listening and close every connection; a browser that
  // does not answer the close within a second is cut off.
  asio::post(d.server.get_io_service(), [&d] {
    websocketpp::lib::error_code ec;
    d.server.stop_listening(ec);
    for (const auto& [id, h] : d.handles) {
      d.server.close(h, websocketpp::close::status::going_away, "server stopped", ec);
    }
  });
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(1);
  while (!d.server.stopped() && d.open_count.load() > 0 &&
         std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  d.server.stop();
  if (d.thread.joinable()) d.thread.join();
}

void WebSocketHub::Send(ConnectionId to, std::shared_ptr<const std::string> data, bool binary) {
  Impl& d = *impl_;
  asio::post(d.server.get_io_service(), [&d, to, data = std::move(data), binary] {
    auto it = d.handles.find(to);
    if (it != d.handles.end()) d.SendNow(it->second, *data, binary, false);
  });
}

void WebSocketHub::Broadcast(std::shared_ptr<const std::string> data, bool binary, bool droppable) {
  Impl& d = *impl_;
  asio::post(d.server.get_io_service(), [&d, data = std::move(data), binary, droppable] {
    for (const auto& [id, h] : d.handles) d.SendNow(h, *data, binary, droppable);
  });
}

size_t WebSocketHub::connections() const { return impl_->open_count.load(); }

uint64_t WebSocketHub::dropped() const { return impl_->dropped.load(); }

}  // namespace colony::viewer
