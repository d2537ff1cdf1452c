#include "core/bus/loop_link.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/mman.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <new>
#include <utility>

#include "core/config/yaml.h"
#include "core/rt/clock.h"

namespace enact::bus {

// one direction: records of [size (4 bytes, 4 more unused)][payload, padded to 8 bytes], in a
// ring of bytes written by one side and read by the other. `head` and `tail` count bytes
// since the start; a record that would not fit before the ring's end leaves a wrap mark there
// and starts again at 0
struct LinkRing {
  static constexpr std::size_t kBytes = LoopLink::kRingBytes;
  alignas(64) std::atomic<std::uint64_t> head{0};           // the reader's
  alignas(64) std::atomic<std::uint64_t> tail{0};           // the writer's
  alignas(64) std::atomic<std::uint32_t> reader_waiting{0}; // the reader sleeps on its doorbell
  alignas(64) unsigned char bytes[kBytes];
};

struct LinkShared {
  static constexpr std::uint64_t kMagic = 0x316b6e696c746e65;  // "entlink1": this layout
  std::uint64_t magic = kMagic;
  LinkRing to_master, to_follower;
};

namespace {

static_assert(std::atomic<std::uint64_t>::is_always_lock_free && std::atomic<std::uint32_t>::is_always_lock_free,
              "the rings' counters are shared between processes: they must be lock-free");

constexpr std::uint32_t kWrap = 0xffffffffu;        // the rest of the ring is empty: go on at 0
constexpr std::size_t kRecordHeader = 8;
constexpr char kHello[] = "enact loop link 1";       // the follower's one message on the socket
constexpr int kHelloFds = 3;                          // the memory, the follower's bell, the master's

std::uint64_t record_bytes(std::size_t size) { return kRecordHeader + ((size + 7) & ~std::size_t{7}); }

// a Unix address for `path`; false when it does not fit sun_path
bool unix_address(const std::string& path, sockaddr_un& out) {
  out = {};
  out.sun_family = AF_UNIX;
  if (path.empty() || path.size() >= sizeof out.sun_path) return false;
  std::memcpy(out.sun_path, path.c_str(), path.size() + 1);
  return true;
}

int seqpacket_socket() { return socket(AF_UNIX, SOCK_SEQPACKET | SOCK_NONBLOCK | SOCK_CLOEXEC, 0); }

void close_fd(int& fd) noexcept {
  if (fd >= 0) close(fd);
  fd = -1;
}

// the shared memory of `fd`, mapped with its pages in place (the loop's first message takes
// no page fault); nullptr when it is not a link's
LinkShared* map_shared(int fd) noexcept {
  struct stat st {};
  if (fstat(fd, &st) != 0 || static_cast<std::size_t>(st.st_size) != sizeof(LinkShared)) return nullptr;
  void* m = mmap(nullptr, sizeof(LinkShared), PROT_READ | PROT_WRITE, MAP_SHARED | MAP_POPULATE, fd, 0);
  return m == MAP_FAILED ? nullptr : static_cast<LinkShared*>(m);
}

void unmap(LinkShared*& shared) noexcept {
  if (shared) munmap(shared, sizeof(LinkShared));
  shared = nullptr;
}

// the next record's payload and size in `ring`; size -1: none, -2: not a record (a peer that
// wrote past its records, or a counter that is not one this side wrote)
const unsigned char* peek(const LinkRing& ring, std::uint64_t& head, long& size) noexcept {
  head = ring.head.load(std::memory_order_relaxed);
  if (head == ring.tail.load(std::memory_order_acquire)) {
    size = -1;
    return nullptr;
  }
  std::size_t at = head % LinkRing::kBytes;
  std::uint32_t n = 0;
  if (at % 8 != 0) {  // the counters live in shared memory: never read past the ring on them
    size = -2;
    return nullptr;
  }
  std::memcpy(&n, ring.bytes + at, sizeof n);
  if (n == kWrap) {  // the writer published the mark and the record after it together
    head += LinkRing::kBytes - at;
    at = 0;
    std::memcpy(&n, ring.bytes, sizeof n);
  }
  if (n == 0 || n > LoopLink::kMaxMessage || at + record_bytes(n) > LinkRing::kBytes) {
    size = -2;
    return nullptr;
  }
  size = n;
  return ring.bytes + at + kRecordHeader;
}

// waits until one of `fds` is readable or deadline_ns: the index of the first readable, -1
// at the deadline (or a signal)
int wait_readable(const int (&fds)[3], std::int64_t deadline_ns) noexcept {
  const std::int64_t left = deadline_ns - rt::now_ns();
  if (left <= 0) return -1;
  pollfd p[3] = {{fds[0], POLLIN, 0}, {fds[1], POLLIN, 0}, {fds[2], POLLIN, 0}};
  const timespec ts{static_cast<time_t>(left / 1'000'000'000), static_cast<long>(left % 1'000'000'000)};
  if (ppoll(p, fds[2] >= 0 ? 3 : 2, deadline_ns == LoopLink::kNoDeadline ? nullptr : &ts, nullptr) <= 0) return -1;
  for (int i = 0; i < 3; ++i) {
    if (p[i].revents != 0) return i;
  }
  return -1;
}

}  // namespace

LoopLink::~LoopLink() { close_all(); }

LoopLink::LoopLink(LoopLink&& other) noexcept { *this = std::move(other); }

LoopLink& LoopLink::operator=(LoopLink&& other) noexcept {
  if (this == &other) return *this;
  close_all();
  listen_ = std::exchange(other.listen_, -1);
  pending_ = std::exchange(other.pending_, -1);
  peer_ = std::exchange(other.peer_, -1);
  bell_in_ = std::exchange(other.bell_in_, -1);
  bell_out_ = std::exchange(other.bell_out_, -1);
  shared_ = std::exchange(other.shared_, nullptr);
  in_ = std::exchange(other.in_, nullptr);
  out_ = std::exchange(other.out_, nullptr);
  path_ = std::move(other.path_);
  counters_ = other.counters_;
  return *this;
}

LoopLink LoopLink::listen(const std::string& path) {
  sockaddr_un addr;
  if (!unix_address(path, addr)) {
    throw config::Error("loop link '" + path + "': the path is too long for a Unix socket (at most 107 bytes)\n  fix: use a shorter ENACT_GRAPH_DIR");
  }
  LoopLink link;
  link.path_ = path;
  link.listen_ = seqpacket_socket();
  unlink(path.c_str());  // a dead graph's socket file
  if (link.listen_ < 0 || bind(link.listen_, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0 || ::listen(link.listen_, 4) != 0) {
    throw config::Error("loop link '" + path + "': cannot listen (" + std::strerror(errno) +
                        ")\n  fix: check the graph folder is writable, or use loop_transport=zeromq");
  }
  return link;
}

LoopLink LoopLink::connect(const std::string& path, std::int64_t deadline_ns) {
  LoopLink link;
  link.path_ = path;
  sockaddr_un addr;
  if (!unix_address(path, addr)) return link;
  int fd = -1;
  for (;;) {
    fd = seqpacket_socket();
    if (fd >= 0 && ::connect(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) == 0) break;
    close_fd(fd);
    if (rt::now_ns() >= deadline_ns) return link;
    rt::sleep_until_ns(std::min(rt::now_ns() + 2'000'000, deadline_ns));
  }
  // the follower makes the shared memory and both doorbells, and hands them over at once (a
  // connected Unix socket queues them even before the master accepts)
  int memory = memfd_create("enact-loop-link", MFD_CLOEXEC);
  int bells[2] = {eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC), eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC)};  // the follower's, the master's
  LinkShared* shared = nullptr;
  if (memory >= 0 && bells[0] >= 0 && bells[1] >= 0 && ftruncate(memory, sizeof(LinkShared)) == 0 && (shared = map_shared(memory))) {
    new (shared) LinkShared();
    const int fds[kHelloFds] = {memory, bells[0], bells[1]};
    alignas(cmsghdr) char control[CMSG_SPACE(sizeof fds)] = {};
    iovec iov{const_cast<char*>(kHello), sizeof kHello};
    msghdr msg{};
    msg.msg_iov = &iov;
    msg.msg_iovlen = 1;
    msg.msg_control = control;
    msg.msg_controllen = sizeof control;
    cmsghdr* c = CMSG_FIRSTHDR(&msg);
    c->cmsg_level = SOL_SOCKET;
    c->cmsg_type = SCM_RIGHTS;
    c->cmsg_len = CMSG_LEN(sizeof fds);
    std::memcpy(CMSG_DATA(c), fds, sizeof fds);
    if (sendmsg(fd, &msg, MSG_NOSIGNAL) == static_cast<ssize_t>(sizeof kHello)) {
      link.peer_ = std::exchange(fd, -1);
      link.bell_in_ = std::exchange(bells[0], -1);
      link.bell_out_ = std::exchange(bells[1], -1);
      link.shared_ = std::exchange(shared, nullptr);
      link.in_ = &link.shared_->to_follower;
      link.out_ = &link.shared_->to_master;
      ++link.counters_.peers;
    }
  }
  unmap(shared);
  for (int* f : {&memory, &bells[0], &bells[1], &fd}) close_fd(*f);
  return link;
}

bool LoopLink::take_pending() noexcept {
  char hello[sizeof kHello + 1] = {};
  alignas(cmsghdr) char control[CMSG_SPACE(sizeof(int) * kHelloFds)] = {};
  iovec iov{hello, sizeof hello};
  msghdr msg{};
  msg.msg_iov = &iov;
  msg.msg_iovlen = 1;
  msg.msg_control = control;
  msg.msg_controllen = sizeof control;
  const ssize_t n = recvmsg(pending_, &msg, MSG_DONTWAIT | MSG_CMSG_CLOEXEC);
  if (n < 0 && (errno == EAGAIN || errno == EINTR)) return false;  // not here yet
  int fds[kHelloFds] = {-1, -1, -1};
  const cmsghdr* c = n > 0 ? CMSG_FIRSTHDR(&msg) : nullptr;
  const bool has_fds = c && c->cmsg_level == SOL_SOCKET && c->cmsg_type == SCM_RIGHTS && c->cmsg_len == CMSG_LEN(sizeof fds);
  if (has_fds) std::memcpy(fds, CMSG_DATA(c), sizeof fds);
  LinkShared* shared = nullptr;
  const bool ok = has_fds && n == static_cast<ssize_t>(sizeof kHello) && std::memcmp(hello, kHello, sizeof kHello) == 0 &&
                  (shared = map_shared(fds[0])) && shared->magic == LinkShared::kMagic;
  close_fd(fds[0]);  // the mapping keeps the memory
  if (!ok) {  // not a loop link's follower (or an older one): refused
    unmap(shared);
    close_fd(fds[1]);
    close_fd(fds[2]);
    close_fd(pending_);
    return false;
  }
  drop_peer();
  peer_ = std::exchange(pending_, -1);
  bell_out_ = fds[1];
  bell_in_ = fds[2];
  shared_ = shared;
  in_ = &shared_->to_master;
  out_ = &shared_->to_follower;
  ++counters_.peers;
  return true;
}

bool LoopLink::accept_peer() noexcept {
  if (listen_ < 0) return false;
  // the newest of those waiting (each replaces the one before)
  for (int fd; (fd = accept4(listen_, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC)) >= 0;) {
    close_fd(pending_);
    pending_ = fd;
  }
  return pending_ >= 0 && take_pending();
}

bool LoopLink::wait_for_peer(std::int64_t deadline_ns) noexcept {
  while (!connected() && !accept_peer()) {
    const int fds[3] = {listen_, pending_, -1};
    if (wait_readable(fds, deadline_ns) < 0) break;
  }
  return connected();
}

bool LoopLink::send(const void* data, std::size_t size) noexcept {
  if (!out_ || size == 0 || size > kMaxMessage) {
    ++counters_.dropped;
    return false;
  }
  LinkRing& ring = *out_;
  const std::uint64_t need = record_bytes(size);
  std::uint64_t tail = ring.tail.load(std::memory_order_relaxed);
  const std::size_t at = tail % LinkRing::kBytes;
  const std::uint64_t skip = LinkRing::kBytes - at < need ? LinkRing::kBytes - at : 0;
  if (tail - ring.head.load(std::memory_order_acquire) + skip + need > LinkRing::kBytes) {
    ++counters_.dropped;  // a reader that stopped reading: it keeps what it has
    return false;
  }
  if (skip != 0) {
    std::memcpy(ring.bytes + at, &kWrap, sizeof kWrap);
    tail += skip;
  }
  const std::uint32_t n = static_cast<std::uint32_t>(size);
  std::memcpy(ring.bytes + tail % LinkRing::kBytes, &n, sizeof n);
  std::memcpy(ring.bytes + tail % LinkRing::kBytes + kRecordHeader, data, size);
  ring.tail.store(tail + need, std::memory_order_release);
  // the reader says it sleeps, then looks at the ring once more; this side publishes, then
  // looks whether it sleeps: one of the two sees the other (both fences are sequentially
  // consistent)
  std::atomic_thread_fence(std::memory_order_seq_cst);
  if (ring.reader_waiting.load(std::memory_order_relaxed) != 0) {
    const std::uint64_t one = 1;
    if (write(bell_out_, &one, sizeof one) == static_cast<ssize_t>(sizeof one)) ++counters_.doorbells;
  }
  ++counters_.sent;
  return true;
}

LoopLink::Woke LoopLink::sleep(std::int64_t deadline_ns, int stop_fd) noexcept {
  LinkRing& ring = *in_;
  // say this end sleeps, then look once more: the writer publishes, then looks whether this
  // end sleeps; one of the two sees the other (both fences are sequentially consistent)
  ring.reader_waiting.store(1, std::memory_order_relaxed);
  std::atomic_thread_fence(std::memory_order_seq_cst);
  if (ring.tail.load(std::memory_order_relaxed) != ring.head.load(std::memory_order_relaxed)) {
    ring.reader_waiting.store(0, std::memory_order_relaxed);
    return Woke::message;
  }
  const int fds[3] = {bell_in_, peer_, stop_fd};
  const int woke = wait_readable(fds, deadline_ns);
  ring.reader_waiting.store(0, std::memory_order_relaxed);
  if (woke == 0) {
    std::uint64_t rung = 0;  // the doorbell quiet again (the ring is read after)
    [[maybe_unused]] const ssize_t cleared = read(bell_in_, &rung, sizeof rung);
    return Woke::message;
  }
  if (woke == 1) {
    // the connection carries nothing after the handover: readable, it says the peer left
    char none[16];
    const ssize_t got = recv(peer_, none, sizeof none, MSG_DONTWAIT);
    return got == 0 || (got < 0 && errno != EAGAIN && errno != EINTR) ? Woke::peer_left : Woke::message;
  }
  return woke == 2 ? Woke::stop : Woke::deadline;
}

long LoopLink::receive(void* buffer, std::size_t capacity, std::int64_t deadline_ns, int stop_fd) noexcept {
  while (in_) {
    std::uint64_t head = 0;
    long size = 0;
    if (const unsigned char* payload = peek(*in_, head, size)) {
      const std::size_t n = std::min(static_cast<std::size_t>(size), capacity);
      std::memcpy(buffer, payload, n);
      in_->head.store(head + record_bytes(static_cast<std::size_t>(size)), std::memory_order_release);
      ++counters_.received;
      return static_cast<long>(n);
    }
    if (size == -2) break;  // a peer that wrote past its records: not a link to trust
    const Woke woke = sleep(deadline_ns, stop_fd);
    // what came before a stop or the peer's end is read first
    const bool waiting = in_->tail.load(std::memory_order_acquire) != in_->head.load(std::memory_order_relaxed);
    if (woke == Woke::deadline || (woke == Woke::stop && !waiting)) return 0;
    if (woke == Woke::peer_left && !waiting) break;
  }
  drop_peer();
  return -1;
}

void LoopLink::drop_peer() noexcept {
  unmap(shared_);
  in_ = out_ = nullptr;
  for (int* fd : {&peer_, &bell_in_, &bell_out_}) close_fd(*fd);
}

void LoopLink::close_all() noexcept {
  drop_peer();
  close_fd(pending_);
  close_fd(listen_);
}

std::string loop_link_path(const std::string& dir, const std::string& master) {
  const std::string path = dir + "/loop." + master + ".sock";
  sockaddr_un addr;
  if (!unix_address(path, addr)) {
    throw config::Error("loop link '" + path + "': the path is too long for a Unix socket (at most 107 bytes)\n  fix: use a shorter ENACT_GRAPH_DIR");
  }
  return path;
}

}  // namespace enact::bus
