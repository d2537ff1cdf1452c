// enact doctor: is this machine ready for real-time haptics? One line per check, ok or the
// fix; then the machine probe's figures and, for each mode, the rates this machine holds and
// what to change for more; exit 1 when something blocks the 5 kHz loop (memory locking).
#include <dirent.h>
#include <fcntl.h>
#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "core/rt/clock.h"
#include "core/rt/histogram.h"
#include "core/rt/probe.h"
#include "core/sim/simulator.h"
#include "nodes/enact/args.h"
#include "nodes/enact/commands.h"

namespace enact::cli {
namespace {

constexpr const char* kHelp = R"(usage: enact doctor [--fresh]

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

enum class Level { ok, warn, fail };

struct Check {
  const char* name;
  Level level;
  std::string found;  // what is there, and the fix when not ok
};

// the first line of a file, "" when unreadable
std::string first_line(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  return line;
}

bool on_path(const std::string& program) { return std::system(("command -v " + program + " >/dev/null 2>&1").c_str()) == 0; }

Check memlock() {
  rlimit lim{};
  getrlimit(RLIMIT_MEMLOCK, &lim);
  const bool locked = mlockall(MCL_CURRENT) == 0;
  munlockall();
  const bool enough = lim.rlim_cur == RLIM_INFINITY || lim.rlim_cur >= (64u << 20) || geteuid() == 0;
  const std::string limit = lim.rlim_cur == RLIM_INFINITY ? "unlimited" : std::to_string(lim.rlim_cur >> 10) + " KiB";
  if (locked && enough) return {"memlock", Level::ok, "memory can be locked (limit " + limit + ")"};
  return {"memlock", Level::fail,
          "limit " + limit + ": the loop's memory cannot be locked (page faults stall it); fix: a line '@realtime - memlock unlimited' in "
          "/etc/security/limits.d/enact.conf, your user in group realtime, log in again"};
}

Check sched_fifo() {
  // try it on a thread of our own
  int result = 0;
  std::thread t([&result] {
    sched_param p{};
    p.sched_priority = 1;
    result = pthread_setschedparam(pthread_self(), SCHED_FIFO, &p);
  });
  t.join();
  rlimit lim{};
  getrlimit(RLIMIT_RTPRIO, &lim);
  if (result == 0) return {"sched_fifo", Level::ok, "SCHED_FIFO allowed (rtprio limit " + (lim.rlim_cur == RLIM_INFINITY ? std::string("unlimited") : std::to_string(lim.rlim_cur)) + ")"};
  return {"sched_fifo", Level::fail,
          "SCHED_FIFO refused (rtprio limit " + std::to_string(lim.rlim_cur) + "): the loop competes with every process; fix: '@realtime - rtprio 90' in "
          "/etc/security/limits.d/enact.conf, your user in group realtime, log in again"};
}

Check governor() {
  std::vector<std::string> slow;
  int cpus = 0;
  for (int cpu = 0;; ++cpu) {
    const std::string base = "/sys/devices/system/cpu/cpu" + std::to_string(cpu);
    if (!std::filesystem::exists(base)) break;
    const std::string g = first_line(base + "/cpufreq/scaling_governor");
    if (g.empty()) continue;
    ++cpus;
    if (g != "performance") slow.push_back("cpu" + std::to_string(cpu) + " " + g);
  }
  if (cpus == 0) return {"cpu_governor", Level::ok, "no frequency scaling exposed (fixed clock, or a virtual machine)"};
  if (slow.empty()) return {"cpu_governor", Level::ok, "performance on every CPU"};
  return {"cpu_governor", Level::warn, slow.front() + (slow.size() > 1 ? " and " + std::to_string(slow.size() - 1) + " more" : "") +
                                           ": clock changes add latency; fix: sudo cpupower frequency-set -g performance"};
}

Check idle_states() {
  const std::string dir = "/sys/devices/system/cpu/cpu0/cpuidle";
  long worst_us = 0;
  std::string worst;
  for (int s = 0; std::filesystem::exists(dir + "/state" + std::to_string(s)); ++s) {
    const std::string base = dir + "/state" + std::to_string(s);
    const long latency = std::atol(first_line(base + "/latency").c_str());
    if (first_line(base + "/disable") != "1" && latency > worst_us) {
      worst_us = latency;
      worst = first_line(base + "/name");
    }
  }
  if (worst_us <= 20) return {"cpu_idle", Level::ok, worst.empty() ? "no idle states exposed" : "deepest enabled idle state exits in " + std::to_string(worst_us) + " us"};
  return {"cpu_idle", Level::warn, "idle state " + worst + " takes " + std::to_string(worst_us) + " us to wake (a 5 kHz period is 200 us); "
                                   "fix: the CPU latency request below (enact-rt holds it), or the kernel option processor.max_cstate=1"};
}

Check latency_request() {
  const int fd = open("/dev/cpu_dma_latency", O_RDWR);
  if (fd >= 0) {
    close(fd);
    return {"cpu_latency", Level::ok, "/dev/cpu_dma_latency can be held (enact-rt keeps idle states shallow while it runs)"};
  }
  if (!std::filesystem::exists("/dev/cpu_dma_latency")) return {"cpu_latency", Level::warn, "no /dev/cpu_dma_latency: idle states cannot be held shallow"};
  return {"cpu_latency", Level::warn, "/dev/cpu_dma_latency not writable: deep idle states add wake-up latency; "
                                      "fix: a udev rule KERNEL==\"cpu_dma_latency\", GROUP=\"realtime\", MODE=\"0660\""};
}

Check isolated_cpus() {
  const std::string isolated = first_line("/sys/devices/system/cpu/isolated");
  if (!isolated.empty()) return {"isolated_cpus", Level::ok, "isolated: " + isolated + " (pin the loop there: enact-rt cpu parameter)"};
  return {"isolated_cpus", Level::warn, "none: other processes share the loop's CPU; fix: kernel options isolcpus=N nohz_full=N rcu_nocbs=N for one CPU"};
}

Check timer_slack() {
  const long slack_ns = std::atol(first_line("/proc/self/timerslack_ns").c_str());
  if (slack_ns <= 1000) return {"timer_slack", Level::ok, std::to_string(slack_ns) + " ns"};
  return {"timer_slack", Level::ok, std::to_string(slack_ns) + " ns by default; a SCHED_FIFO thread (enact-rt) has none: the kernel ignores slack for real-time threads"};
}

Check rt_throttling() {
  const std::string runtime = first_line("/proc/sys/kernel/sched_rt_runtime_us");
  const std::string period = first_line("/proc/sys/kernel/sched_rt_period_us");
  if (runtime.empty()) return {"rt_throttling", Level::ok, "not exposed"};
  if (runtime == "-1") return {"rt_throttling", Level::ok, "off"};
  return {"rt_throttling", Level::warn, "real-time threads get at most " + runtime + " us of every " + period +
                                            " us (the loop sleeps each period, so only a runaway loop meets it); to turn it off: echo -1 | sudo tee /proc/sys/kernel/sched_rt_runtime_us"};
}

Check udev_rules() {
  for (const char* dir : {"/etc/udev/rules.d", "/lib/udev/rules.d", "/usr/lib/udev/rules.d"}) {
    if (std::filesystem::exists(std::string(dir) + "/99-enact.rules")) return {"usb_udev", Level::ok, std::string(dir) + "/99-enact.rules installed (Novint Falcon, Metec cells)"};
  }
  return {"usb_udev", Level::warn, "no udev rules for the Novint Falcon and Metec cells: only root can open them; "
                                   "fix: sudo cp scripts/udev/99-enact.rules /etc/udev/rules.d/ && sudo udevadm control --reload, then replug"};
}

Check brltty() {
  if (DIR* proc = opendir("/proc")) {
    for (dirent* e; (e = readdir(proc));) {
      if (first_line(std::string("/proc/") + e->d_name + "/comm") == "brltty") {
        closedir(proc);
        return {"brltty", Level::warn, "BRLTTY is running and may claim a Metec display's USB interface; fix: sudo systemctl disable --now brltty (or remove the package)"};
      }
    }
    closedir(proc);
  }
  return {"brltty", Level::ok, "not running"};
}

Check display() {
  if (std::getenv("DISPLAY") || std::getenv("WAYLAND_DISPLAY")) return {"display", Level::ok, "a display for enact-viewer"};
  if (on_path("Xvfb") || on_path("xvfb-run")) return {"display", Level::ok, "no display; Xvfb present: xvfb-run enact-viewer, or enact-viewer --snapshot (offscreen OpenGL)"};
  return {"display", Level::warn, "no display and no Xvfb: enact-viewer can only take --snapshot pictures offscreen; fix: run it on a desktop, or sudo apt install xvfb"};
}

Check node_js() {
  if (on_path("node")) return {"nodejs", Level::ok, "Node.js present: the MCAP and Foxglove interop tests run (scripts/setup.sh installs their packages)"};
  return {"nodejs", Level::warn, "no Node.js: the interop tests are skipped; fix: sudo apt install nodejs npm, then scripts/setup.sh"};
}

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
  // a loop that sleeps every tick: its spin window covers the lateness, twice over
  const double sleeping_hz = rt::sleeping_rate_limit_hz(p, false, work_ns);
  // spinning on a CPU of its own: the tick's cost and a margin
  const double spinning_hz = p.cpus >= 2 ? std::min(44'000.0, 1e9 / (1.5 * static_cast<double>(work_ns) + 2'000.0)) : 0.0;
  // distributed on one host: the window, then the hop (one pipe round trip) and the step
  const double window_ns = static_cast<double>(late_p99 + late_p99 / 4 + 5'000);
  const double distributed_hz = std::min(44'000.0, 1e9 / (window_ns + static_cast<double>(p.pipe_same_cpu.p99_ns + work_ns)));
  std::printf("\nrates this machine holds (from the figures above):\n");
  std::printf("  co-located (enact-rt), sleeping each tick: up to %.1f kHz\n", khz(sleeping_hz));
  if (spinning_hz > 0.0) {
    std::printf("  co-located, spinning on a CPU of its own (what enact-rt does when the period is under twice the lateness): %.1f kHz\n", khz(spinning_hz));
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
                "loop's CPU: scripts/graph_deadlines.py compares the shipped fifo_priority 80 with -- --arg fifo_priority=0 on this machine\n",
                rt::to_us(p.sleep_late_fifo.p99_ns), rt::to_us(late_p99));
  }
  if (p.cpus < 2) {
    ++tips;
    std::printf("  - one CPU: give the machine a second one, so that the loop has a CPU of its own\n");
  }
  if (sleeping_hz < 5'000.0) {
    ++tips;
    std::printf("  - a sleeping loop cannot hold 5 kHz here: the co-located loop spins (realtime profile, a CPU of its own)\n");
  }
  if (tips == 0) std::printf("  nothing to change for the shipped rates (5 kHz distributed, 44 kHz co-located)\n");
}

}  // namespace

int doctor(int argc, char** argv) {
  const Args a = parse(argc, argv, 2, {}, {"fresh"});
  if (a.flag("help")) {
    std::fputs(kHelp, stdout);
    return 0;
  }
  if (!a.positional.empty()) throw UsageError("enact doctor takes no argument");
  const Check checks[] = {memlock(),      sched_fifo(),  governor(),   idle_states(), latency_request(), isolated_cpus(),
                          timer_slack(), rt_throttling(), udev_rules(), brltty(),      display(),         node_js()};
  bool blocked = false;
  for (const Check& c : checks) {
    const char* tag = c.level == Level::ok ? "ok  " : c.level == Level::warn ? "warn" : "FAIL";
    std::printf("%s  %-14s %s\n", tag, c.name, c.found.c_str());
    blocked = blocked || c.level == Level::fail;
  }
  machine_section(a.flag("fresh"));
  if (blocked) std::printf("\nthe real-time loop cannot run as it should here: fix the FAIL lines\n");
  return blocked ? 1 : 0;
}

}  // namespace enact::cli
