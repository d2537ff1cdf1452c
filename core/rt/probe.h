#pragma once
// The machine probe (DESIGN.md, wave 3): what this machine gives a loop, measured in well
// under a second and cached per boot. Machines differ more than code does: one VM wakes a
// sleeping thread 41 us late at the median where another takes 3 us, so a loop chooses how
// to wait from these figures, never from a constant tuned elsewhere.
//
//   sleep lateness   a thread sleeping to absolute deadlines at the loop's period (timer slack
//                    1 ns, the loop's own setting): how late it wakes, normal and SCHED_FIFO
//   pipe round trip  two threads ping-ponging a byte through two pipes, on one CPU and on two:
//                    the floor of any hop between two processes that wake each other
//   the rest         the default timer slack, whether SCHED_FIFO is permitted, real-time
//                    throttling, the CPU latency request
//
// Each figure is measured in 5 rounds and the round with the lowest p99 is kept (its count is
// every sample's): a burst of load elsewhere during one round is not the machine. The probe
// holds the CPU latency request while it measures when it may (as the loop runs).
#include <cstdint>
#include <optional>
#include <string>

namespace enact::rt {

// nanoseconds as microseconds, for the figures people read
inline double to_us(std::int64_t ns) { return static_cast<double>(ns) * 1e-3; }

// percentiles of one measurement, ns (all 0: not measured)
struct Spread {
  std::int64_t p50_ns = 0, p99_ns = 0, max_ns = 0;
  std::int64_t count = 0;
};

struct MachineProbe {
  std::int64_t period_ns = 200'000;  // the period the sleeps were measured at
  int cpus = 0;                      // CPUs this process may use
  Spread sleep_late;                 // wake-up lateness, normal scheduling
  Spread sleep_late_fifo;            // the same under SCHED_FIFO (count 0: refused)
  bool fifo_permitted = false;
  std::int64_t default_timer_slack_ns = 0;  // a new thread's, before the loop sets 1 ns
  Spread pipe_same_cpu;              // round trip, both threads on one CPU
  Spread pipe_cross_cpu;             // round trip, one thread on each of two CPUs (count 0: one CPU)
  long rt_runtime_us = -1;           // real-time throttling: FIFO threads get at most this of
  long rt_period_us = 0;             // every period (-1: off)
  bool cpu_latency_held = false;     // the CPU latency request could be held
  std::string boot_id;               // the boot it was measured in (the cache's key)
  std::int64_t probed_at_ns = 0;     // CLOCK_REALTIME when measured
  double load_per_cpu = 0.0;         // the 1-minute load average over the CPUs, when measured
  // the floor of a loop that spins: a thread on the loop's CPU (the last one), normal
  // scheduling, spinning on the clock to 44 kHz deadlines (22.7 us
  // apart) with no work at all. What it misses (the scheduler's count: a wake-up a period or
  // more late, and the deadlines it skips) is the machine's, not the loop's: the hypervisor,
  // interrupts, the kernel's own threads. Fraction of deadlines, -1: not measured
  double spin_missed_44k = -1.0;
  std::int64_t spin_longest_late_ns = 0;  // its latest wake-up
  std::int64_t spin_deadlines = 0;        // deadlines counted (every round)
  int spin_cpu = -1;                      // the CPU it spun on
};

// measures this machine now (about 1 s): `sleeps` wake-ups at period_ns each way, the pipe
// round trips, then 0.5 s of spinning to 44 kHz deadlines. Runs on threads of its own: the caller's
// CPUs and scheduling are untouched. Never throws for a refusal (FIFO, a CPU): it is recorded.
MachineProbe probe_machine(std::int64_t period_ns = 200'000, int sleeps = 1000);

// the spinning floor alone (MachineProbe::spin_missed_44k and the two after it): 5 rounds of
// 0.1 s on `cpu`, the share of missed deadlines over all of them (a rate of rare events: the
// quietest round would understate it; not measured: -1, when the CPU cannot be pinned)
void measure_spin_floor(int cpu, MachineProbe& probe);

// the probe of this boot: read from the cache file (cache_path()), else measured and stored
// there (a cache that cannot be written is not an error). `fresh` measures again and stores.
// A probe measured on a busy machine (load over kBusyLoadPerCpu) says what that moment gave:
// it is measured again once older than kBusyProbeLife_ns, so a burst of load (a build beside)
// does not set how every later loop of the boot waits.
inline constexpr double kBusyLoadPerCpu = 1.0;
inline constexpr std::int64_t kBusyProbeLife_ns = 600'000'000'000;  // 10 minutes
MachineProbe cached_probe(bool fresh = false);
// $XDG_CACHE_HOME/enact/machine-probe, else $HOME/.cache/enact/machine-probe, else
// /tmp/enact-<uid>/machine-probe
std::string cache_path();

// key=value lines, one figure each; from_text is nullopt for a text it cannot read whole
std::string to_text(const MachineProbe& probe);
std::optional<MachineProbe> from_text(const std::string& text);

// how a loop with period_ns waits on this machine
struct WaitPlan {
  bool spin_whole_period = false;  // never sleeps: the period is shorter than the lateness
  std::int64_t spin_ns = 0;        // otherwise: sleeps to spin_ns before each deadline, then spins
  bool fifo = false;               // runs under SCHED_FIFO (asked for, permitted, and it sleeps)
  std::string why;                 // one line for people: how it waits, and the figure it comes from
  double spin_floor = -1.0;        // spinning whole: the probe's spin_missed_44k (-1: not measured)
};

// the wait for a loop at period_ns that asks for SCHED_FIFO (fifo) or not: a spin window of
// the sleep lateness p99 (FIFO's when it runs under FIFO) with a 25 % + 5 us margin. A FIFO
// loop, or one that must leave its CPU to another thread every tick (must_sleep), sleeps
// every tick: its window is at most half the period. A period shorter than twice the p99
// lateness is spun whole when the loop has a CPU of its own (own_cpu), under normal
// scheduling (a FIFO thread that never sleeps is throttled by the kernel).
WaitPlan plan_wait(const MachineProbe& probe, std::int64_t period_ns, bool fifo, bool must_sleep, bool own_cpu);

// the wait of a loop whose spin window parameter is spin_us: negative plans it from this
// boot's probe (cached_probe: measured the first time), 0 or more fixes the window
WaitPlan loop_wait(double spin_us, std::int64_t period_ns, bool fifo, bool must_sleep, bool own_cpu);

// the highest rate (Hz, at most 44 kHz) a sleeping loop holds here: its period twice the
// p99 lateness and the tick's work (work_ns)
double sleeping_rate_limit_hz(const MachineProbe& probe, bool fifo, std::int64_t work_ns);

// one line for people: the spinning floor (MachineProbe::spin_missed_44k) and where it was measured
std::string spin_floor_text(const MachineProbe& probe);

// a few lines for people: every figure with its unit
std::string describe(const MachineProbe& probe);

// the first line of a file (a /proc or /sys setting), "" when unreadable
std::string first_line(const std::string& path);

}  // namespace enact::rt
