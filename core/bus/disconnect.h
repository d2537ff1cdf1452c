#pragma once
// Noticing that a peer went away: a socket whose connection closes (the process at the other
// end ended, even by SIGKILL: its kernel closes the connection) reports it through a ZeroMQ
// socket monitor. A stopped peer (SIGSTOP) keeps its connection and is not reported.
#include <string>

#include <zmq.hpp>

namespace enact::bus {

class DisconnectWatch {
 public:
  // watches `socket` (which must outlive this object) from now on: create it before connect(),
  // or after bus::attach_connect (whose own monitor is stopped when it returns)
  explicit DisconnectWatch(zmq::socket_t& socket);
  // stops watching
  ~DisconnectWatch();
  DisconnectWatch(const DisconnectWatch&) = delete;
  DisconnectWatch& operator=(const DisconnectWatch&) = delete;

  // true once a connection of the socket was lost (reads the pending reports, never waits)
  bool disconnected();

 private:
  zmq::socket_t& socket_;
  zmq::socket_t reports_;
  bool disconnected_ = false;
};

}  // namespace enact::bus
