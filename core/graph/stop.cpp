#include "core/graph/stop.h"

#include <signal.h>
#include <unistd.h>

#include <atomic>

namespace enact::graph {
namespace {

std::atomic<bool> g_stop{false};
void on_stop(int) {
  // the first request arms the grace period: SIGALRM's default action ends the process
  if (!g_stop.exchange(true)) alarm(kStopGrace_s);
}

}  // namespace

void install_stop_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_stop;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

bool stop_requested() { return g_stop.load(std::memory_order_relaxed); }

}  // namespace enact::graph
