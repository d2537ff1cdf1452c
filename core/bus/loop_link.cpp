#include "core/bus/loop_link.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <utility>

#include "core/config/yaml.h"
#include "core/rt/clock.h"

namespace enact::bus {
namespace {

// a Unix address for `path`; false when it does not fit sun_path
bool unix_address(const std::string& path, sockaddr_un& out) {
  out = {};
  out.sun_family = AF_UNIX;
  if (path.empty() || path.size() >= sizeof out.sun_path) return false;
  std::memcpy(out.sun_path, path.c_str(), path.size() + 1);
  return true;
}

int seqpacket_socket() { return socket(AF_UNIX, SOCK_SEQPACKET | SOCK_NONBLOCK | SOCK_CLOEXEC, 0); }

// waits for `events` on fd until deadline_ns, or until stop_fd (>= 0) is readable: true when
// fd is ready (or hung up)
bool wait_fd(int fd, short events, std::int64_t deadline_ns, int stop_fd = -1) noexcept {
  const std::int64_t left = deadline_ns - rt::now_ns();
  if (left <= 0) return false;
  pollfd p[2] = {{fd, events, 0}, {stop_fd, POLLIN, 0}};
  const timespec ts{static_cast<time_t>(left / 1'000'000'000), static_cast<long>(left % 1'000'000'000)};
  return ppoll(p, stop_fd >= 0 ? 2 : 1, &ts, nullptr) > 0 && p[0].revents != 0;
}

void close_fd(int& fd) noexcept {
  if (fd >= 0) close(fd);
  fd = -1;
}

}  // namespace

LoopLink::~LoopLink() {
  close_fd(peer_);
  close_fd(listen_);
}

LoopLink::LoopLink(LoopLink&& other) noexcept { *this = std::move(other); }

LoopLink& LoopLink::operator=(LoopLink&& other) noexcept {
  if (this == &other) return *this;
  close_fd(peer_);
  close_fd(listen_);
  listen_ = std::exchange(other.listen_, -1);
  peer_ = std::exchange(other.peer_, -1);
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
  do {
    int fd = seqpacket_socket();
    if (fd >= 0 && ::connect(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) == 0) {
      link.peer_ = fd;
      ++link.counters_.peers;
      return link;
    }
    close_fd(fd);
    if (rt::now_ns() >= deadline_ns) break;
    rt::sleep_until_ns(std::min(rt::now_ns() + 2'000'000, deadline_ns));
  } while (true);
  return link;
}

bool LoopLink::accept_peer() noexcept {
  if (listen_ < 0) return false;
  const int fd = accept4(listen_, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
  if (fd < 0) return false;
  close_fd(peer_);
  peer_ = fd;
  ++counters_.peers;
  return true;
}

bool LoopLink::wait_for_peer(std::int64_t deadline_ns) noexcept {
  while (!connected() && !accept_peer() && wait_fd(listen_, POLLIN, deadline_ns)) {
  }
  return connected();
}

bool LoopLink::send(const void* data, std::size_t size) noexcept {
  if (peer_ < 0 || ::send(peer_, data, size, MSG_DONTWAIT | MSG_NOSIGNAL) != static_cast<ssize_t>(size)) {
    if (peer_ >= 0 && (errno == EPIPE || errno == ECONNRESET)) drop_peer();
    ++counters_.dropped;
    return false;
  }
  ++counters_.sent;
  return true;
}

long LoopLink::receive(void* buffer, std::size_t capacity, std::int64_t deadline_ns, int stop_fd) noexcept {
  while (peer_ >= 0) {
    const ssize_t n = recv(peer_, buffer, capacity, MSG_DONTWAIT);
    if (n > 0) {
      ++counters_.received;
      return n;
    }
    // 0 is the peer's orderly close (a seqpacket link carries no empty messages)
    if (n == 0 || (errno != EAGAIN && errno != EINTR)) {
      drop_peer();
      return -1;
    }
    if (!wait_fd(peer_, POLLIN, deadline_ns, stop_fd)) return 0;
  }
  return -1;
}

void LoopLink::drop_peer() noexcept { close_fd(peer_); }

std::string loop_link_path(const std::string& dir, const std::string& master) {
  const std::string path = dir + "/loop." + master + ".sock";
  sockaddr_un addr;
  if (!unix_address(path, addr)) {
    throw config::Error("loop link '" + path + "': the path is too long for a Unix socket (at most 107 bytes)\n  fix: use a shorter ENACT_GRAPH_DIR");
  }
  return path;
}

}  // namespace enact::bus
