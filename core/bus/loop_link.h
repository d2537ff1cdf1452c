#pragma once
// The loop's own hop on one host (DESIGN.md, "transport by locality"): one Unix
// SOCK_SEQPACKET connection between the clock master (the FFD driver: it listens) and the
// simulator (it connects), written and read by the loop threads themselves. A message costs
// one wake-up of the reader, no I/O thread in between: the round trip is the machine's pipe
// floor, where ZeroMQ adds its I/O threads' wake-ups on both sides. The payloads are the same
// serialised Protobuf messages the bus carries; the bus still carries them to observers.
//
// Threads: a LoopLink is used by one thread at a time. Nothing blocks past the deadline given;
// send, receive and accept_peer allocate nothing and never throw.
#include <cstddef>
#include <cstdint>
#include <string>

namespace enact::bus {

// what the link did, cumulative
struct LinkCounters {
  std::uint64_t sent = 0;      // messages the socket took
  std::uint64_t dropped = 0;   // messages not sent: no peer, or the peer's queue full
  std::uint64_t received = 0;  // messages read
  std::uint64_t peers = 0;     // peers accepted (master) or connections made (follower)
};

class LoopLink {
 public:
  // the largest message a link carries (a DeviceState or ForceCommand is ~100 bytes)
  static constexpr std::size_t kMaxMessage = 4096;

  LoopLink() = default;
  ~LoopLink();
  LoopLink(LoopLink&& other) noexcept;
  LoopLink& operator=(LoopLink&& other) noexcept;
  LoopLink(const LoopLink&) = delete;
  LoopLink& operator=(const LoopLink&) = delete;

  // the clock master's end: listens at `path` (a stale file from a dead graph is replaced);
  // throws config::Error naming the path and the fix when it cannot
  static LoopLink listen(const std::string& path);
  // the follower's end: connects to `path`, retrying every 2 ms until deadline_ns (the master
  // may not be listening yet; a deadline already past: one try); an unconnected link when it
  // could not (connected() false)
  static LoopLink connect(const std::string& path, std::int64_t deadline_ns);

  // whether a peer is connected
  bool connected() const { return peer_ >= 0; }
  // master: takes a peer waiting to connect, replacing the one before (a respawned follower);
  // true when a new peer came. Never blocks.
  bool accept_peer() noexcept;
  // master: waits until a peer connects or deadline_ns; true when one is connected
  bool wait_for_peer(std::int64_t deadline_ns) noexcept;

  // sends one message without blocking; false (counted dropped) with no peer, or when the
  // peer's queue is full (a stopped follower: its old messages wait, new ones are dropped)
  bool send(const void* data, std::size_t size) noexcept;
  // waits until a message comes or the monotonic clock reaches deadline_ns, and reads it into
  // buffer (at most capacity bytes). Returns its size; 0 on timeout (or a signal); -1 when
  // there is no peer or the peer left (the link is then unconnected).
  // With stop_fd (>= 0) it also returns 0 once stop_fd is readable: a loop whose scheduler's
  // timer ends the wait (rt::PeriodicScheduler::reply_wait) gives a far deadline as a backstop,
  // and its wait then arms no timer of its own (on a VM a timer due before any other costs the
  // round trip some 10 us: enact bench loop's link arm).
  long receive(void* buffer, std::size_t capacity, std::int64_t deadline_ns, int stop_fd = -1) noexcept;

  // the connected socket, to wait on it with poll() beside other sockets (-1: no peer)
  int fd() const { return peer_; }
  // the path listened at or connected to
  const std::string& path() const { return path_; }
  const LinkCounters& counters() const { return counters_; }

 private:
  void drop_peer() noexcept;

  int listen_ = -1;  // master only
  int peer_ = -1;
  std::string path_;
  LinkCounters counters_;
};

// where the loop hop of the graph whose sockets live in `dir` listens: DIR/loop.<master>.sock;
// throws config::Error if the path is too long for a Unix socket
std::string loop_link_path(const std::string& dir, const std::string& master);

}  // namespace enact::bus
