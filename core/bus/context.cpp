#include "core/bus/context.h"

#include <cerrno>

#include <sched.h>

#include <atomic>
#include <stdexcept>

namespace enact::bus {
namespace {

IoThreads g_io;
std::atomic<bool> g_created{false};

zmq::context_t make_context() {
  zmq::context_t c;
  // options of the I/O threads apply to threads started after them: before the first socket
  for (const int cpu : g_io.cpus) zmq_ctx_set(c.handle(), ZMQ_THREAD_AFFINITY_CPU_ADD, cpu);
  if (g_io.fifo_priority > 0) {
    zmq_ctx_set(c.handle(), ZMQ_THREAD_SCHED_POLICY, SCHED_FIFO);
    zmq_ctx_set(c.handle(), ZMQ_THREAD_PRIORITY, g_io.fifo_priority);
  }
  g_created.store(true);
  return c;
}

}  // namespace

void set_io_threads(const IoThreads& io) {
  if (g_created.load()) throw std::logic_error("bus: set_io_threads after the context was made; call it before the first socket");
  g_io = io;
}

zmq::context_t& context() {
  // a function-local static: created once, on first use, by whichever thread gets here first
  static zmq::context_t instance = make_context();
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

std::string monitor_endpoint() {
  static std::atomic<unsigned> next = 0;
  return "inproc://enact.bus.monitor." + std::to_string(next++);
}

Received recv_frame(zmq::socket_t& socket, zmq::message_t& frame, zmq::recv_flags flags) {
  try {
    return socket.recv(frame, flags) ? Received::frame : Received::none;
  } catch (const zmq::error_t& e) {
    if (e.num() != EINTR) throw;
    return Received::interrupted;
  }
}

void recv_more(zmq::socket_t& socket, zmq::message_t& frame) {
  while (recv_frame(socket, frame, zmq::recv_flags::none) == Received::interrupted) {
  }
}

std::vector<std::string> receive_frames(zmq::socket_t& socket) {
  std::vector<std::string> frames;
  zmq::message_t frame;
  do {
    Received got = Received::interrupted;
    while ((got = recv_frame(socket, frame, zmq::recv_flags::none)) == Received::interrupted) {
    }
    if (got == Received::none) break;
    frames.push_back(frame.to_string());
  } while (frame.more());
  return frames;
}

}  // namespace enact::bus
