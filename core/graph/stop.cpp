#include "core/graph/stop.h"

#include <signal.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdint>

namespace enact::graph {
namespace {

std::atomic<bool> g_stop{false};
int g_stop_fd = -1;
void on_stop(int) {
  // the first request arms the grace period: SIGALRM's default action ends the process
  if (g_stop.exchange(true)) return;
  alarm(kStopGrace_s);
  const int saved = errno;  // a handler leaves errno as it found it
  if (g_stop_fd >= 0) {
    const std::uint64_t one = 1;
    [[maybe_unused]] const ssize_t written = write(g_stop_fd, &one, sizeof one);
  }
  errno = saved;
}

}  // namespace

void install_stop_handlers() {
  if (g_stop_fd < 0) g_stop_fd = eventfd(g_stop.load() ? 1 : 0, EFD_NONBLOCK | EFD_CLOEXEC);
  struct sigaction sa {};
  sa.sa_handler = on_stop;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

bool stop_requested() { return g_stop.load(std::memory_order_relaxed); }

int stop_fd() { return g_stop_fd; }

}  // namespace enact::graph
