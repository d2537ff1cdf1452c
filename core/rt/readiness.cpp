#include "core/rt/readiness.h"

#include <dirent.h>
#include <fcntl.h>
#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <thread>

#include "core/config/share.h"

namespace enact::rt {
namespace {

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
  if (!std::filesystem::exists("/dev/cpu_dma_latency")) return {"cpu_latency", Level::warn, "no /dev/cpu_dma_latency: idle states cannot be held shallow; fix: the kernel option processor.max_cstate=1 (or idle=poll) keeps them shallow"};
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
                                            " us (the loop sleeps each period, so only a runaway loop meets it); fix, to turn it off: echo -1 | sudo tee /proc/sys/kernel/sched_rt_runtime_us"};
}

Check udev_rules() {
  for (const char* dir : {"/etc/udev/rules.d", "/lib/udev/rules.d", "/usr/lib/udev/rules.d"}) {
    if (std::filesystem::exists(std::string(dir) + "/99-enact.rules")) return {"usb_udev", Level::ok, std::string(dir) + "/99-enact.rules installed (Novint Falcon, Metec cells)"};
  }
  return {"usb_udev", Level::warn, "no udev rules for the Novint Falcon and Metec cells: only root can open them; "
                                   "fix: sudo cp " + config::shipped("scripts/udev/99-enact.rules") + " /etc/udev/rules.d/ && sudo udevadm control --reload, then replug"};
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

}  // namespace

std::vector<Check> machine_checks() {
  return {memlock(), sched_fifo(), governor(), idle_states(), latency_request(), isolated_cpus(), timer_slack(), rt_throttling(), udev_rules(), brltty(), display(), node_js()};
}

HeldRates held_rates(const MachineProbe& p, std::int64_t tick_ns) {
  HeldRates r;
  r.sleeping_hz = sleeping_rate_limit_hz(p, false, tick_ns);
  r.spinning_hz = p.cpus >= 2 ? std::min(44'000.0, 1e9 / (1.5 * static_cast<double>(tick_ns) + 2'000.0)) : 0.0;
  const std::int64_t late_p99 = p.sleep_late.p99_ns;
  const double window_ns = static_cast<double>(late_p99 + late_p99 / 4 + 5'000);
  r.distributed_hz = std::min(44'000.0, 1e9 / (window_ns + static_cast<double>(p.pipe_same_cpu.p99_ns + tick_ns)));
  return r;
}

}  // namespace enact::rt
