#include "core/bus/disconnect.h"

#include <cstdint>
#include <cstring>

#include "core/bus/context.h"

namespace enact::bus {
DisconnectWatch::DisconnectWatch(zmq::socket_t& socket) : socket_(socket), reports_(make_socket(zmq::socket_type::pair)) {
  const std::string endpoint = monitor_endpoint();
  if (zmq_socket_monitor(socket_.handle(), endpoint.c_str(), ZMQ_EVENT_DISCONNECTED) != 0) throw zmq::error_t();
  reports_.connect(endpoint);
}

DisconnectWatch::~DisconnectWatch() { zmq_socket_monitor(socket_.handle(), nullptr, 0); }

bool DisconnectWatch::disconnected() {
  // each report: a frame with the event (16 bits) and its value (32 bits), then the endpoint
  zmq::message_t frame;
  for (Received got; (got = recv_frame(reports_, frame, zmq::recv_flags::dontwait)) != Received::none;) {
    if (got == Received::interrupted) continue;
    std::uint16_t event = 0;
    if (frame.size() >= sizeof event) std::memcpy(&event, frame.data(), sizeof event);
    while (frame.more()) recv_more(reports_, frame);
    disconnected_ = disconnected_ || event == ZMQ_EVENT_DISCONNECTED;
  }
  return disconnected_;
}

}  // namespace enact::bus
