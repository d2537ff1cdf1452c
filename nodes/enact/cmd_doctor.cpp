// enact doctor: is this machine ready for real-time haptics? One line per check, ok or the
// fix; then the machine probe's figures and, for each mode, the rates this machine holds and
// what to change for more; exit 1 when something blocks the 5 kHz loop (memory locking).
#include <algorithm>
#include <cstdio>
#include <string>

#include "core/config/share.h"
#include "core/rt/clock.h"
#include "core/rt/histogram.h"
#include "core/rt/probe.h"
#include "core/rt/readiness.h"
#include "core/sim/simulator.h"
#include "nodes/enact/args.h"
#include "nodes/enact/commands.h"

namespace enact::cli {
namespace {

constexpr const char* kDoctorHelp = R"(usage: enact doctor [--fresh]

Is this machine ready for real-time haptics (the loop of enact-rt and of the distributed
graph, real devices, the viewer, the tests)? One line per check: ok, warn (works, with more
jitter or a missing extra) or FAIL (blocks the real-time loop), each with what was found and
the fix. Checks: memory locking, SCHED_FIFO, CPU frequency governor, CPU idle states, the CPU
latency request (/dev/cpu_dma_latency), isolated CPUs, timer slack, real-time throttling, udev
rules for the supported USB devices, BRLTTY (it grabs Metec displays), a display or offscreen
OpenGL for the viewer, Node.js for the interop tests.

Then the machine probe (the figures every loop chooses its wait from: how late a sleeping
thread wakes, the pipe round trip on one CPU and across two, measured about a second and
cached per boot), the co-located tick's cost on the bridge scene, and for each mode the rate
this machine holds and what to change for more. Exit 1 when something FAILs.

options:
  --fresh   measure the machine again (after changing a kernel option, a CPU's governor...)
)";

// the co-located tick's cost: p99 of 4000 simulator steps on the bridge scene, ns (0: the
// scene is not found)
std::int64_t tick_cost_ns() {
  std::string scene;
  try {
    scene = find_file("launch/scenes/bridge.yaml");
  } catch (const std::exception&) {
    return 0;
  }
  sim::SimParams params;
  params.scene = scene;
  sim::Simulator simulator;
  simulator.configure(params);
  simulator.activate(0);
  rt::LatencyHistogram cost;
  const math::Vec3 start{-0.0074246, -0.0222739, 0.0119};
  for (int i = 0; i < 4000; ++i) {
    const math::Vec3 at{start.x + 1e-6 * (i % 200), start.y, start.z - 1e-6 * (i % 100)};
    const std::int64_t t0 = rt::now_ns();
    simulator.step(static_cast<std::int64_t>(i) * 200'000, at);
    cost.record(rt::now_ns() - t0);
  }
  return cost.percentile(99.0);
}

double khz(double hz) { return hz * 1e-3; }

// the probe's figures, the rate each mode holds here, and what to change for more
void machine_section(bool fresh) {
  const rt::MachineProbe p = rt::cached_probe(fresh);
  std::printf("\n%s", rt::describe(p).c_str());
  const std::int64_t work_ns = tick_cost_ns();
  std::printf("  the co-located tick (bridge scene, CM1): %.2f us p99\n", rt::to_us(work_ns));
  const std::int64_t late_p99 = p.sleep_late.p99_ns;
  const auto [sleeping_hz, spinning_hz, distributed_hz] = rt::held_rates(p, work_ns);
  std::printf("\nrates this machine holds (from the figures above):\n");
  std::printf("  co-located (enact-rt), sleeping each tick: up to %.1f kHz\n", khz(sleeping_hz));
  if (spinning_hz > 0.0) {
    std::printf("  co-located, spinning on a CPU of its own (what enact-rt does when the period is under twice the lateness): %.1f kHz", khz(spinning_hz));
    if (p.spin_missed_44k > 0.001) std::printf(", missing at least %.2f %% of 44 kHz deadlines (the spinning floor)", 100.0 * p.spin_missed_44k);
    std::printf("\n");
  } else {
    std::printf("  co-located, spinning: not here (one CPU: the loop would starve everything else)\n");
  }
  std::printf("  distributed on one host (the local link): up to %.1f kHz; over ZeroMQ (loop_transport=zeromq) less: enact bench loop measures both\n",
              khz(distributed_hz));
  std::printf("\nto hold more:\n");
  int tips = 0;
  if (late_p99 > 50'000) {
    ++tips;
    std::printf("  - a sleeping thread wakes %.0f us late (p99): deep CPU idle states or a virtual CPU that sleeps; fix: let enact hold the CPU latency "
                "request (/dev/cpu_dma_latency, see cpu_latency above), the kernel option idle=poll or processor.max_cstate=1, or a VM with "
                "dedicated vCPUs\n",
                rt::to_us(late_p99));
  }
  if (p.fifo_permitted && p.sleep_late_fifo.p99_ns * 10 >= late_p99 * 9) {
    ++tips;
    std::printf("  - SCHED_FIFO wakes no sooner here (%.1f against %.1f us p99, the machine quiet); it still keeps other threads off the "
                "loop's CPU: /usr/bin/python3 %s compares the shipped fifo_priority 80 with -- --arg fifo_priority=0 on this machine\n",
                rt::to_us(p.sleep_late_fifo.p99_ns), rt::to_us(late_p99), config::shipped("scripts/graph_deadlines.py").c_str());
  }
  if (p.cpus < 2) {
    ++tips;
    std::printf("  - one CPU: give the machine a second one, so that the loop has a CPU of its own\n");
  }
  if (sleeping_hz < 5'000.0) {
    ++tips;
    std::printf("  - a sleeping loop cannot hold 5 kHz here: the co-located loop spins (realtime profile, a CPU of its own)\n");
  }
  if (p.spin_missed_44k > 0.001) {
    ++tips;
    std::printf("  - a thread spinning with no work misses %.2f %% of 44 kHz deadlines here (the latest %.0f us late): the virtual CPU is interrupted "
                "or taken away by the host, and no loop here misses fewer; fix: a machine whose CPUs are its own (dedicated vCPUs or bare metal)\n",
                100.0 * p.spin_missed_44k, rt::to_us(p.spin_longest_late_ns));
  }
  if (tips == 0) std::printf("  nothing to change for the shipped rates (5 kHz distributed, 44 kHz co-located)\n");
}

}  // namespace

int doctor(int argc, char** argv) {
  const Args a = parse(argc, argv, 2, {}, {"fresh"});
  if (a.flag("help")) {
    std::fputs(kDoctorHelp, stdout);
    return 0;
  }
  if (!a.positional.empty()) throw UsageError("enact doctor takes no argument");
  bool blocked = false;
  for (const rt::Check& c : rt::machine_checks()) {
    const char* tag = c.level == rt::Level::ok ? "ok  " : c.level == rt::Level::warn ? "warn" : "FAIL";
    std::printf("%s  %-14s %s\n", tag, c.name, c.found.c_str());
    blocked = blocked || c.level == rt::Level::fail;
  }
  machine_section(a.flag("fresh"));
  if (blocked) std::printf("\nthe real-time loop cannot run as it should here: fix the FAIL lines\n");
  return blocked ? 1 : 0;
}

}  // namespace enact::cli
