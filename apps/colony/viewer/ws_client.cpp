#include "apps/colony/viewer/ws_client.h"

#include <condition_variable>
#include <deque>
#include <mutex>
#include <thread>
#include <websocketpp/client.hpp>
#include <websocketpp/config/asio_no_tls_client.hpp>

namespace colony::viewer {

using Client = websocketpp::client<websocketpp::config::asio_client>;

struct WebSocketClient::Impl {
  Client client;
  std::thread thread;
  websocketpp::connection_hdl handle;
  std::mutex mutex;
  std::condition_variable changed;
  std::deque<Message> inbox;
  bool open = false, closed = false;
  int close_code = 0;
  std::string failure;
};

WebSocketClient::WebSocketClient() : impl_(std::make_unique<Impl>()) {
  Impl& d = *impl_;
  d.client.clear_access_channels(websocketpp::log::alevel::all);
  d.client.clear_error_channels(websocketpp::log::elevel::all);
  d.client.init_asio();
  d.client.set_max_message_size(256 << 20);
  d.client.set_open_handler([&d](websocketpp::connection_hdl) {
    std::lock_guard lock(d.mutex);
    d.open = true;
    d.changed.notify_all();
  });
  d.client.set_fail_handler([&d](websocketpp::connection_hdl h) {
    std::lock_guard lock(d.mutex);
    d.closed = true;
    d.failure = d.client.get_con_from_hdl(h)->get_ec().message();
    d.changed.notify_all();
  });
  d.client.set_close_handler([&d](websocketpp::connection_hdl h) {
    std::lock_guard lock(d.mutex);
    d.closed = true;
    d.close_code = d.client.get_con_from_hdl(h)->get_remote_close_code();
    d.changed.notify_all();
  });
  d.client.set_message_handler([&d](websocketpp::connection_hdl, Client::message_ptr msg) {
    std::lock_guard lock(d.mutex);
    d.inbox.push_back(
        {msg->get_payload(), msg->get_opcode() == websocketpp::frame::opcode::binary});
    d.changed.notify_all();
  });
}

WebSocketClient::~WebSocketClient() {
  Close();
  impl_->client.stop();
  if (impl_->thread.joinable()) impl_->thread.join();
}

bool WebSocketClient::Connect(const std::string& uri, std::chrono::milliseconds timeout,
                              std::string& error) {
  Impl& d = *impl_;
  websocketpp::lib::error_code ec;
  Client::connection_ptr con = d.client.get_connection(uri, ec);
  if (ec) {
    error = ec.message();
    return false;
  }
  d.handle = con->get_handle();
  d.client.connect(con);
  d.thread = std::thread([&d] { d.client.run(); });
  std::unique_lock lock(d.mutex);
  if (!d.changed.wait_for(lock, timeout, [&d] { return d.open || d.closed; })) {
    error = "timed out";
    return false;
  }
  if (!d.open) error = d.failure.empty() ? "connection failed" : d.failure;
  return d.open;
}

void WebSocketClient::Send(const std::string& data, bool binary) {
  websocketpp::lib::error_code ec;
  impl_->client.send(impl_->handle, data,
                     binary ? websocketpp::frame::opcode::binary : websocketpp::frame::opcode::text,
                     ec);
}

std::optional<WebSocketClient::Message> WebSocketClient::Receive(
    std::chrono::milliseconds timeout) {
  Impl& d = *impl_;
  std::unique_lock lock(d.mutex);
  if (!d.changed.wait_for(lock, timeout, [&d] { return !d.inbox.empty(); })) return std::nullopt;
  Message m = std::move(d.inbox.front());
  d.inbox.pop_front();
  return m;
}

bool WebSocketClient::closed() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->closed;
}

int WebSocketClient::close_code() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->close_code;
}

void WebSocketClient::Close() {
  Impl& d = *impl_;
  {
    std::lock_guard lock(d.mutex);
    if (!d.open || d.closed) return;
  }
  websocketpp::lib::error_code ec;
  d.client.close(d.handle, websocketpp::close::status::normal, "", ec);
  std::unique_lock lock(d.mutex);
  d.changed.wait_for(lock, std::chrono::seconds(1), [&d] { return d.closed; });
}

}  // namespace colony::viewer
