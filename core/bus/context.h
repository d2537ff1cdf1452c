#pragma once
// The process-wide ZeroMQ context every bus socket is made from. inproc:// endpoints only
// join sockets of the same context, so there is exactly one per process.
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

#include <zmq.hpp>

namespace enact::bus {

// how long a closed publishing socket (PUB, XPUB) may still deliver the messages it queued, ms.
// Not 0: with linger 0, libzmq 4.3 aborts in its I/O thread (session_base.cpp, clean_pipes)
// when a peer drops while half a multipart message is on the wire (libzmq issue #3442).
inline constexpr int kPublisherLinger_ms = 100;

// where the context's I/O threads run (they carry every message of the process)
struct IoThreads {
  std::vector<int> cpus;  // ZMQ_THREAD_AFFINITY_CPU_ADD each; empty: inherit the creating thread's
  int fifo_priority = 0;  // ZMQ_THREAD_SCHED_POLICY SCHED_FIFO at ZMQ_THREAD_PRIORITY; 0: unchanged.
                          // Only a permitted setting: libzmq aborts its I/O thread on a refusal
};

// sets the I/O threads of the context to come; throws std::logic_error once the context exists
// (call it before the first socket)
void set_io_threads(const IoThreads& io);

// the context, created on first use (thread-safe). It is destroyed at exit, which waits
// until every socket made from it is closed and, for publishers, their linger has passed.
zmq::context_t& context();

// a socket of the context: linger kPublisherLinger_ms for PUB and XPUB, 0 for the others
// (closing never waits)
zmq::socket_t make_socket(zmq::socket_type type);

// one frame into `frame`; with dontwait `none` when nothing is waiting (a blocking receive
// with a timeout: `none` at the timeout). libzmq returns a signal's EINTR (Ctrl-C, a stop
// handler's SIGTERM, a child's SIGCHLD) from any receive while it checks its commands, even
// one that does not wait, even inside a multipart message: that is `interrupted`, never an
// error; the message is still there (a busy `enact record` died of it, "Interrupted system
// call", its file without its summary)
enum class Received { frame, none, interrupted };
Received recv_frame(zmq::socket_t& socket, zmq::message_t& frame, zmq::recv_flags flags);
// the next frame of a multipart message begun (it arrives whole, so it is there): retried
// through signals
void recv_more(zmq::socket_t& socket, zmq::message_t& frame);

// a fresh inproc endpoint for a socket monitor's reports (zmq_socket_monitor)
std::string monitor_endpoint();

// sends every frame of a message (blocking), the last without sndmore: for command and
// control sockets, not the data path
void send_frames(zmq::socket_t& socket, std::initializer_list<std::string_view> frames);

// every frame of the next message (blocking; those read before a timeout or an error)
std::vector<std::string> receive_frames(zmq::socket_t& socket);

}  // namespace enact::bus
