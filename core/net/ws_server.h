#pragma once
// A WebSocket server on its own thread (websocketpp over standalone asio, Debian's
// libwebsocketpp-dev and libasio-dev): connections that ask for one subprotocol, text and
// binary messages both ways, and sends from any thread that drop instead of queueing
// without bound. Kept free of websocketpp types: websocketpp 0.8 only compiles as C++17,
// so ws_server.cpp is built as C++17 and the rest of enact sees this plain interface.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

namespace enact::net {

// a connection, unique over the server's life
using ClientId = std::uint64_t;

struct WsHandlers {
  std::function<void(ClientId)> on_open;                            // handshake done
  std::function<void(ClientId)> on_close;                           // gone (closed or failed)
  std::function<void(ClientId, const std::string&)> on_text;        // a text message
  std::function<void(ClientId, const std::string&)> on_binary;      // a binary message
};

class WsServer {
 public:
  // binds `host`:`port` (0: any free port) and accepts connections offering `subprotocol`
  // (others are refused at the handshake; an empty subprotocol accepts every connection). The handlers run on the server's thread.
  // Throws std::runtime_error when the address cannot be bound.
  WsServer(const std::string& host, int port, std::string subprotocol, WsHandlers handlers, std::size_t max_backlog_bytes);
  // stop()
  ~WsServer();
  WsServer(const WsServer&) = delete;
  WsServer& operator=(const WsServer&) = delete;

  // the port bound
  int port() const;

  // queues a message to `client` from any thread, without blocking. False (dropped) when the
  // client is gone or more than max_backlog_bytes are already waiting to go out to it: a
  // slow client loses messages, nobody else waits for it.
  bool send(ClientId client, const std::string& data, bool binary);

  // closes one connection (from any thread; a client already gone is ignored)
  void close(ClientId client);

  // closes every connection and joins the thread; safe twice
  void stop();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace enact::net
