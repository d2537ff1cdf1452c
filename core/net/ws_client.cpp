// Built as C++17 (websocketpp 0.8 does not compile as C++20): see ws_client.h.
#include "core/net/ws_client.h"

#include <chrono>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <stdexcept>
#include <thread>

#include <websocketpp/client.hpp>
#include <websocketpp/config/asio_no_tls_client.hpp>

namespace enact::net {

using Client = websocketpp::client<websocketpp::config::asio_client>;
using Handle = websocketpp::connection_hdl;

struct WsClient::Impl {
  Client client;
  Handle handle;
  std::thread thread;
  mutable std::mutex mutex;
  std::condition_variable changed;
  std::deque<std::string> inbox;
  bool open = false;
  bool gone = false;  // closed or failed
  std::string why;    // why it failed
  bool stopped = false;
};

WsClient::WsClient(const std::string& host, int port, double timeout_s) : impl_(std::make_unique<Impl>()) {
  Impl& i = *impl_;
  i.client.clear_access_channels(websocketpp::log::alevel::all);
  i.client.clear_error_channels(websocketpp::log::elevel::all);
  i.client.init_asio();
  i.client.set_open_handler([&i](Handle) {
    std::lock_guard lock(i.mutex);
    i.open = true;
    i.changed.notify_all();
  });
  const auto ended = [&i](Handle h) {
    std::lock_guard lock(i.mutex);
    if (!i.open) {
      websocketpp::lib::error_code ec;
      const auto con = i.client.get_con_from_hdl(h, ec);
      i.why = con ? con->get_ec().message() : "connection failed";
    }
    i.gone = true;
    i.changed.notify_all();
  };
  i.client.set_fail_handler(ended);
  i.client.set_close_handler(ended);
  i.client.set_message_handler([&i](Handle, Client::message_ptr m) {
    std::lock_guard lock(i.mutex);
    i.inbox.push_back(m->get_payload());
    i.changed.notify_all();
  });
  const std::string uri = "ws://" + host + ":" + std::to_string(port) + "/";
  websocketpp::lib::error_code ec;
  const auto con = i.client.get_connection(uri, ec);
  if (ec) throw std::runtime_error("not a WebSocket address: " + uri + " (" + ec.message() + ")");
  i.handle = con->get_handle();
  i.client.connect(con);
  i.thread = std::thread([&i] { i.client.run(); });
  std::unique_lock lock(i.mutex);
  const bool done = i.changed.wait_for(lock, std::chrono::duration<double>(timeout_s), [&i] { return i.open || i.gone; });
  if (!done || !i.open) {
    const std::string why = done ? i.why : "no answer within " + std::to_string(timeout_s) + " s";
    lock.unlock();
    close();
    throw std::runtime_error("cannot connect to " + uri + ": " + why);
  }
}

WsClient::~WsClient() { close(); }

bool WsClient::send(const std::string& text) {
  Impl& i = *impl_;
  {
    std::lock_guard lock(i.mutex);
    if (i.gone || !i.open) return false;
  }
  websocketpp::lib::error_code ec;
  i.client.send(i.handle, text, websocketpp::frame::opcode::text, ec);
  return !ec;
}

std::optional<std::string> WsClient::receive(std::int64_t timeout_ns) {
  Impl& i = *impl_;
  std::unique_lock lock(i.mutex);
  i.changed.wait_for(lock, std::chrono::nanoseconds(timeout_ns), [&i] { return !i.inbox.empty() || i.gone; });
  if (i.inbox.empty()) return std::nullopt;
  std::string out = std::move(i.inbox.front());
  i.inbox.pop_front();
  return out;
}

bool WsClient::closed() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->gone;
}

void WsClient::close() {
  Impl& i = *impl_;
  if (i.stopped) return;
  i.stopped = true;
  websocketpp::lib::error_code ec;
  bool open = false;
  {
    std::lock_guard lock(i.mutex);
    open = i.open && !i.gone;
  }
  if (open) i.client.close(i.handle, websocketpp::close::status::going_away, "", ec);
  // give the close handshake a moment, then stop the loop whatever happened
  {
    std::unique_lock lock(i.mutex);
    i.changed.wait_for(lock, std::chrono::milliseconds(open ? 200 : 0), [&i] { return i.gone; });
  }
  i.client.stop();
  if (i.thread.joinable()) i.thread.join();
  std::lock_guard lock(i.mutex);
  i.gone = true;
}

}  // namespace enact::net
