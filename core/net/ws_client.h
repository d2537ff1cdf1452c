#pragma once
// A WebSocket client on its own thread (websocketpp over standalone asio, as the Foxglove
// server: core/net/ws_server.h), text messages both ways, received messages queued for
// a consumer thread. Kept free of websocketpp types: websocketpp 0.8 only compiles as C++17,
// so ws_client.cpp is built as C++17 and the rest of enact sees this plain interface. Not
// for the real-time thread: receive() waits on a condition variable.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

namespace enact::net {

class WsClient {
 public:
  // connect to ws://host:port/ within timeout_s; throws std::runtime_error saying why not
  WsClient(const std::string& host, int port, double timeout_s);
  // close()
  ~WsClient();
  WsClient(const WsClient&) = delete;
  WsClient& operator=(const WsClient&) = delete;

  // queue a text message; false when the connection is gone
  bool send(const std::string& text);
  // the oldest message not yet taken, waiting at most timeout_ns; nullopt on timeout, or
  // when the connection closed and nothing is left
  std::optional<std::string> receive(std::int64_t timeout_ns);
  // whether the connection has closed (the peer closed it, or it failed)
  bool closed() const;
  // close the connection and join the thread; safe twice
  void close();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace enact::net
