#pragma once
// Last words to the hardware when the driver process dies: the process that owns a device
// must zero it on its own way out. A backend registers an emergency stop (a function and a
// context) while it holds a device; a handler of the fatal signals (SIGSEGV, SIGBUS, SIGILL,
// SIGFPE, SIGABRT, SIGALRM: a crash, an uncaught exception, an abort, a stop past its grace period) runs every registered stop,
// then lets the signal take its course (the previous handler, or the default action: the
// process still dies with that signal). An exit() that skips the backends' destructors runs
// them too (atexit). Stops must be async-signal-safe: atomics and the transports'
// emergency_* transfers (usbfs ioctls), nothing else. SIGINT and SIGTERM are the nodes'
// clean stop (deactivate), not handled here; SIGKILL cannot be handled at all.
#include <cstddef>

namespace enact::devices::usb {

using StopFn = void (*)(void* context) noexcept;

// one registration, held by the backend while it owns the device (move-only)
class EmergencyStop {
 public:
  EmergencyStop() = default;
  // register fn(context); installs the signal handlers on first use; throws
  // std::runtime_error when every slot is taken (kSlots devices in one process)
  EmergencyStop(StopFn fn, void* context);
  ~EmergencyStop();
  EmergencyStop(EmergencyStop&& o) noexcept;
  EmergencyStop& operator=(EmergencyStop&& o) noexcept;
  EmergencyStop(const EmergencyStop&) = delete;
  EmergencyStop& operator=(const EmergencyStop&) = delete;

  // unregister (safe twice)
  void reset() noexcept;
  bool armed() const { return slot_ >= 0; }

  static constexpr std::size_t kSlots = 16;

 private:
  int slot_ = -1;
};

// run every registered stop now (what the signal handler does); each stop runs once per call
void run_emergency_stops() noexcept;

}  // namespace enact::devices::usb
