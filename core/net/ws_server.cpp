// Built as C++17 (websocketpp 0.8 does not compile as C++20): see ws_server.h.
#include "core/net/ws_server.h"

#include <map>
#include <mutex>
#include <stdexcept>
#include <thread>

#include <websocketpp/config/asio_no_tls.hpp>
#include <websocketpp/server.hpp>

namespace enact::net {

using Server = websocketpp::server<websocketpp::config::asio>;
using Handle = websocketpp::connection_hdl;

struct WsServer::Impl {
  Server server;
  std::string subprotocol;
  WsHandlers handlers;
  std::size_t max_backlog_bytes = 0;
  std::mutex mutex;  // guards the two maps: sends come from other threads
  std::map<ClientId, Handle> handles;
  std::map<Handle, ClientId, std::owner_less<Handle>> ids;
  ClientId next_id = 1;
  std::thread thread;
  bool stopped = false;

  // the connection's id, 0 when unknown
  ClientId id_of(const Handle& h) {
    std::lock_guard lock(mutex);
    const auto it = ids.find(h);
    return it == ids.end() ? 0 : it->second;
  }

  // accepts the handshake only when the client offers our subprotocol, and selects it (no
  // subprotocol asked for: every handshake is accepted)
  bool validate(const Handle& h) {
    if (subprotocol.empty()) return true;
    const auto con = server.get_con_from_hdl(h);
    for (const std::string& p : con->get_requested_subprotocols()) {
      if (p == subprotocol) {
        con->select_subprotocol(p);
        return true;
      }
    }
    return false;
  }

  void opened(const Handle& h) {
    ClientId id = 0;
    {
      std::lock_guard lock(mutex);
      id = next_id++;
      handles[id] = h;
      ids[h] = id;
    }
    if (handlers.on_open) handlers.on_open(id);
  }

  void closed(const Handle& h) {
    ClientId id = 0;
    {
      std::lock_guard lock(mutex);
      const auto it = ids.find(h);
      if (it == ids.end()) return;
      id = it->second;
      handles.erase(id);
      ids.erase(it);
    }
    if (handlers.on_close) handlers.on_close(id);
  }

  void received(const Handle& h, const Server::message_ptr& msg) {
    const ClientId id = id_of(h);
    if (id == 0) return;
    const bool text = msg->get_opcode() == websocketpp::frame::opcode::text;
    const auto& handler = text ? handlers.on_text : handlers.on_binary;
    if (handler) handler(id, msg->get_payload());
  }
};

WsServer::WsServer(const std::string& host, int port, std::string subprotocol, WsHandlers handlers, std::size_t max_backlog_bytes)
    : impl_(std::make_unique<Impl>()) {
  Impl& i = *impl_;
  i.subprotocol = std::move(subprotocol);
  i.handlers = std::move(handlers);
  i.max_backlog_bytes = max_backlog_bytes;
  // websocketpp's own logging off: we report what matters ourselves
  i.server.clear_access_channels(websocketpp::log::alevel::all);
  i.server.clear_error_channels(websocketpp::log::elevel::all);
  i.server.init_asio();
  i.server.set_reuse_addr(true);
  i.server.set_validate_handler([&i](Handle h) { return i.validate(h); });
  i.server.set_open_handler([&i](Handle h) { i.opened(h); });
  i.server.set_close_handler([&i](Handle h) { i.closed(h); });
  i.server.set_fail_handler([&i](Handle h) { i.closed(h); });
  i.server.set_message_handler([&i](Handle h, Server::message_ptr m) { i.received(h, m); });
  asio::error_code ec;
  const auto address = asio::ip::make_address(host, ec);
  if (ec) throw std::runtime_error("not an IP address: " + host);
  i.server.listen(asio::ip::tcp::endpoint(address, static_cast<unsigned short>(port)), ec);
  if (ec) throw std::runtime_error("cannot listen on " + host + ":" + std::to_string(port) + ": " + ec.message());
  i.server.start_accept();
  i.thread = std::thread([&i] { i.server.run(); });
}

WsServer::~WsServer() { stop(); }

int WsServer::port() const {
  asio::error_code ec;
  return impl_->server.get_local_endpoint(ec).port();
}

bool WsServer::send(ClientId client, const std::string& data, bool binary) {
  Handle h;
  {
    std::lock_guard lock(impl_->mutex);
    const auto it = impl_->handles.find(client);
    if (it == impl_->handles.end()) return false;
    h = it->second;
  }
  websocketpp::lib::error_code ec;
  const auto con = impl_->server.get_con_from_hdl(h, ec);
  if (ec || !con || con->get_buffered_amount() > impl_->max_backlog_bytes) return false;
  ec = con->send(data, binary ? websocketpp::frame::opcode::binary : websocketpp::frame::opcode::text);
  return !ec;
}

void WsServer::close(ClientId client) {
  Handle h;
  {
    std::lock_guard lock(impl_->mutex);
    const auto it = impl_->handles.find(client);
    if (it == impl_->handles.end()) return;
    h = it->second;
  }
  websocketpp::lib::error_code ec;
  impl_->server.close(h, websocketpp::close::status::going_away, "", ec);
}

void WsServer::stop() {
  Impl& i = *impl_;
  if (i.stopped) return;
  i.stopped = true;
  i.server.stop();
  if (i.thread.joinable()) i.thread.join();
}

}  // namespace enact::net
