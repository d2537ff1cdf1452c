#pragma once
// Real-time setup of the loop thread (the ros2_control recipe): lock memory, SCHED_FIFO,
// CPU affinity. A refusal by the system (no privilege, no such CPU) is never an error: the
// loop runs anyway, and the report says what was refused, why, and how to get it.
#include <cstddef>
#include <string>
#include <vector>

namespace enact::rt {

struct RtParams {
  bool lock_memory = false;  // mlockall(MCL_CURRENT | MCL_FUTURE): no page faults in the loop
  int fifo_priority = 0;     // 0: do not change the scheduling; 1..99: SCHED_FIFO at this priority
  std::vector<int> cpus;     // CPUs to pin the thread to; empty: do not pin
  // normal scheduling's weight for a thread that spins its whole period (never sleeps, so not
  // SCHED_FIFO, which the kernel throttles): -20 makes the other threads on its CPU take a
  // sliver of it instead of a share. 0: unchanged. Refused without the privilege: said.
  int nice = 0;

  // throws config::Error for a priority outside 0..99 or a CPU index out of 0..CPU_SETSIZE-1
  void validate() const;
};

struct RtReport {
  bool memory_locked = false;  // granted requests
  bool fifo = false;
  bool pinned = false;
  // one line per request: what was done, or what was refused, why (errno text) and the fix
  std::vector<std::string> notes;

  // the notes on one line, "; " between them ("no real-time setup requested" when there are none)
  std::string summary() const;
};

// validate (config::Error) and apply the requests to the calling thread (memory locking is
// process-wide). Refusals are reported, never thrown.
RtReport apply_rt_setup(const RtParams& params);  // also sets the thread's timer slack to 1 ns

// whether the calling thread runs under SCHED_FIFO (set here or by a graph's profile)
bool running_fifo();
// the calling thread's SCHED_FIFO priority, 0 when it is not under SCHED_FIFO: what a loop
// runs at, whatever asked for it (its parameter, a graph's profile) and whatever was refused
int fifo_priority_now();

// the calling thread back to normal scheduling (SCHED_OTHER): a loop process's helper thread,
// which the graph's profile made FIFO with the process, yields to the loop thread beside it
void leave_fifo() noexcept;

// touch `bytes` of stack below the caller so the loop never page-faults on it (call it from
// the loop thread, after locking memory, so the pages stay resident). Stops short of the end
// of the thread's stack; returns the bytes touched.
std::size_t prefault_stack(std::size_t bytes = 256 * 1024);

}  // namespace enact::rt
