#include "core/devices/usb/emergency.h"

#include <signal.h>

#include <array>
#include <atomic>
#include <cstdlib>
#include <mutex>
#include <stdexcept>

namespace enact::devices::usb {
namespace {

struct Slot {
  std::atomic<bool> used{false};
  std::atomic<StopFn> fn{nullptr};
  std::atomic<void*> context{nullptr};
};
std::array<Slot, EmergencyStop::kSlots> g_slots;

// SIGALRM: a node past its stop grace period (core/graph/stop.h)
constexpr std::array<int, 6> kFatal = {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT, SIGALRM};
std::array<struct sigaction, kFatal.size()> g_previous{};
std::once_flag g_installed;

// a fatal signal: the stops, then the previous disposition, and the signal again
void on_fatal(int sig) {
  run_emergency_stops();
  for (std::size_t i = 0; i < kFatal.size(); ++i) {
    if (kFatal[i] == sig) sigaction(sig, &g_previous[i], nullptr);
  }
  raise(sig);
}

void at_exit() { run_emergency_stops(); }

void install() {
  struct sigaction sa {};
  sa.sa_handler = on_fatal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_NODEFER;  // the re-raise inside the handler is delivered at once
  for (std::size_t i = 0; i < kFatal.size(); ++i) sigaction(kFatal[i], &sa, &g_previous[i]);
  std::atexit(at_exit);
}

}  // namespace

EmergencyStop::EmergencyStop(StopFn fn, void* context) {
  std::call_once(g_installed, install);
  for (std::size_t i = 0; i < g_slots.size(); ++i) {
    if (g_slots[i].used.exchange(true)) continue;
    // the context first: a handler that sees the function sees its context
    g_slots[i].context.store(context);
    g_slots[i].fn.store(fn);
    slot_ = static_cast<int>(i);
    return;
  }
  throw std::runtime_error("too many USB devices in one process for the emergency stops");
}

EmergencyStop::~EmergencyStop() { reset(); }

EmergencyStop::EmergencyStop(EmergencyStop&& o) noexcept : slot_(o.slot_) { o.slot_ = -1; }

EmergencyStop& EmergencyStop::operator=(EmergencyStop&& o) noexcept {
  if (this != &o) {
    reset();
    slot_ = o.slot_;
    o.slot_ = -1;
  }
  return *this;
}

void EmergencyStop::reset() noexcept {
  if (slot_ < 0) return;
  g_slots[static_cast<std::size_t>(slot_)].fn.store(nullptr);
  g_slots[static_cast<std::size_t>(slot_)].used.store(false);
  slot_ = -1;
}

void run_emergency_stops() noexcept {
  for (auto& s : g_slots) {
    const StopFn fn = s.fn.load();
    if (fn) fn(s.context.load());
  }
}

}  // namespace enact::devices::usb
