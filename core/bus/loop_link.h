#pragma once
// The loop's own hop on one host (DESIGN.md, "transport by locality"): a connection between
// the clock master (the FFD driver: it listens) and the simulator (it connects), written and
// read by the loop threads themselves, no I/O thread in between.
//
// A message goes through memory the two processes share: one ring of records each way, and an
// eventfd as each reader's doorbell, rung only when the reader sleeps. A reader that finds its
// message already there (the simulator, above the driver on one CPU, has answered before the
// driver looks) makes no system call at all; one that waits sleeps on its doorbell. The
// transport alone is then at the machine's pipe floor, where a Unix socket cost some 4 us
// more a round trip on a VM (docs/performance.md, "The hop through shared memory"). The Unix SOCK_SEQPACKET
// socket the two connect over carries the shared memory and the doorbells once (SCM_RIGHTS),
// then tells each side that the other left (its end closes with its process, however it
// ends). The payloads are the same serialised Protobuf messages the bus carries; the bus
// still carries them to observers.
//
// Threads: a LoopLink is used by one thread at a time. Nothing blocks past the deadline given;
// send, receive and accept_peer allocate nothing and never throw.
#include <cstddef>
#include <cstdint>
#include <string>

namespace enact::bus {

// what the link did, cumulative
struct LinkCounters {
  std::uint64_t sent = 0;      // messages the ring took
  std::uint64_t dropped = 0;   // messages not sent: no peer, or the peer's ring full
  std::uint64_t received = 0;  // messages read
  std::uint64_t peers = 0;     // peers accepted (master) or connections made (follower)
  std::uint64_t doorbells = 0; // sends that woke a sleeping reader (the others cost no call)
};

struct LinkShared;  // the memory the two ends share (loop_link.cpp)
struct LinkRing;

class LoopLink {
 public:
  // the largest message a link carries (a DeviceState or ForceCommand is ~100 bytes)
  static constexpr std::size_t kMaxMessage = 4096;
  // each direction's ring in the shared memory: records of an 8-byte header and the message
  // padded to 8 bytes (~1100 states of 100 bytes, 31 of the largest)
  static constexpr std::size_t kRingBytes = 128 * 1024;
  // a receive's deadline that arms no timer at all: its stop_fd or the peer's end ends it
  static constexpr std::int64_t kNoDeadline = INT64_MAX;

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
  bool connected() const { return shared_ != nullptr; }
  // master: takes a peer waiting to connect, replacing the one before (a respawned follower);
  // true when a new peer came. Never blocks.
  bool accept_peer() noexcept;
  // master: waits until a peer connects or deadline_ns; true when one is connected
  bool wait_for_peer(std::int64_t deadline_ns) noexcept;

  // sends one message without blocking; false (counted dropped) with no peer, or when the
  // peer's ring is full (a stopped follower: its old messages wait, new ones are dropped)
  bool send(const void* data, std::size_t size) noexcept;
  // waits until a message comes or the monotonic clock reaches deadline_ns, and reads it into
  // buffer (at most capacity bytes). Returns its size; 0 on timeout (or a signal); -1 when
  // there is no peer or the peer left (the link is then unconnected).
  // With stop_fd (>= 0) it also returns 0 once stop_fd is readable: a loop whose scheduler's
  // timer ends the wait (rt::PeriodicScheduler::reply_wait) gives a far deadline as a backstop,
  // and its wait then arms no timer of its own (on a VM a timer due before any other costs the
  // round trip some 10 us: enact bench loop's link arm). With kNoDeadline it sets no timer at
  // all (a far one still costs about a microsecond a wait here): give a stop_fd.
  long receive(void* buffer, std::size_t capacity, std::int64_t deadline_ns, int stop_fd = -1) noexcept;

  // the path listened at or connected to
  const std::string& path() const { return path_; }
  const LinkCounters& counters() const { return counters_; }

 private:
  enum class Woke { message, deadline, stop, peer_left };
  // waits on this end's doorbell until a message may be there, the deadline, stop_fd or the
  // peer's end
  Woke sleep(std::int64_t deadline_ns, int stop_fd) noexcept;
  // master: the pending peer's shared memory and doorbells, when they have come
  bool take_pending() noexcept;
  void drop_peer() noexcept;
  void close_all() noexcept;

  int listen_ = -1;   // master only
  int pending_ = -1;  // master: a peer accepted whose shared memory has not come yet
  int peer_ = -1;     // the connection: its end closing says the peer left
  int bell_in_ = -1;  // rung by the peer when this end sleeps on its ring
  int bell_out_ = -1; // the peer's doorbell
  LinkShared* shared_ = nullptr;
  LinkRing* in_ = nullptr;
  LinkRing* out_ = nullptr;
  std::string path_;
  LinkCounters counters_;
};

// where the loop hop of the graph whose sockets live in `dir` listens: DIR/loop.<master>.sock;
// throws config::Error if the path is too long for a Unix socket
std::string loop_link_path(const std::string& dir, const std::string& master);

}  // namespace enact::bus
