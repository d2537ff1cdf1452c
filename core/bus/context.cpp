#include "core/bus/context.h"

namespace enact::bus {

zmq::context_t& context() {
  // a function-local static: created once, on first use, by whichever thread gets here first
  static zmq::context_t instance;
  return instance;
}

zmq::socket_t make_socket(zmq::socket_type type) {
  zmq::socket_t socket(context(), type);
  const bool publishes = type == zmq::socket_type::pub || type == zmq::socket_type::xpub;
  socket.set(zmq::sockopt::linger, publishes ? kPublisherLinger_ms : 0);
  return socket;
}

}  // namespace enact::bus
