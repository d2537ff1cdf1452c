#include "core/rt/wakeup.h"

#include <poll.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <system_error>

#include "core/rt/clock.h"

namespace enact::rt {

Wakeup::Wakeup() : fd_(eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC)) {
  if (fd_ < 0) throw std::system_error(errno, std::generic_category(), "eventfd");
}

Wakeup::~Wakeup() { close(fd_); }

void Wakeup::notify() noexcept {
  const std::uint64_t one = 1;
  [[maybe_unused]] const ssize_t n = write(fd_, &one, sizeof one);  // a full counter is a wake-up already
}

bool Wakeup::wait(std::int64_t deadline_ns) noexcept {
  const std::int64_t left_ns = deadline_ns - now_ns();
  pollfd p{fd_, POLLIN, 0};
  // poll's timeout is in ms: a remainder below one rounds up, so the wait ends at or after the deadline
  const int timeout_ms = left_ns <= 0 ? 0 : static_cast<int>((left_ns + 999'999) / 1'000'000);
  if (poll(&p, 1, timeout_ms) <= 0) return false;
  std::uint64_t count = 0;
  return read(fd_, &count, sizeof count) == sizeof count;
}

}  // namespace enact::rt
