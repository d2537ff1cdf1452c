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

void send_frames(zmq::socket_t& socket, std::initializer_list<std::string_view> frames) {
  std::size_t i = 0;
  for (const std::string_view f : frames) {
    const bool last = ++i == frames.size();
    (void)socket.send(zmq::const_buffer(f.data(), f.size()), last ? zmq::send_flags::none : zmq::send_flags::sndmore);
  }
}

std::vector<std::string> receive_frames(zmq::socket_t& socket) {
  std::vector<std::string> frames;
  zmq::message_t frame;
  do {
    if (!socket.recv(frame)) break;
    frames.push_back(frame.to_string());
  } while (frame.more());
  return frames;
}

}  // namespace enact::bus
