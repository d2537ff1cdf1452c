#pragma once
// Is this machine ready for real-time haptics? The checks `enact doctor` prints (memory
// locking, SCHED_FIFO, the CPU's governor and idle states, the CPU latency request, isolated
// CPUs, timer slack, real-time throttling, udev rules, BRLTTY, a display, Node.js), each with
// what was found and the fix, and the rate each mode of the loop holds given the machine
// probe's figures (probe.h).
#include <cstdint>
#include <string>
#include <vector>

#include "core/rt/probe.h"

namespace enact::rt {

enum class Level { ok, warn, fail };

struct Check {
  const char* name;
  Level level;
  std::string found;  // what is there, and the fix when not ok
};

// every check, in the order `enact doctor` prints them
std::vector<Check> machine_checks();

// the rates the loop holds here, Hz (0: not here), given the probe and the co-located tick's
// cost (p99, ns)
struct HeldRates {
  double sleeping_hz = 0.0;     // co-located, sleeping every tick: its spin window covers the lateness, twice over
  double spinning_hz = 0.0;     // co-located, spinning on a CPU of its own (two CPUs at least): the tick and a margin
  double distributed_hz = 0.0;  // distributed on one host: the window, then the hop (one pipe round trip) and the step
};
HeldRates held_rates(const MachineProbe& probe, std::int64_t tick_ns);

}  // namespace enact::rt
