#include <sys/prctl.h>
#include "core/rt/rt_setup.h"

#include <alloca.h>
#include <pthread.h>
#include <sched.h>
#include <sys/resource.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>

#include "core/config/yaml.h"
#include "core/rt/profile.h"

namespace enact::rt {
namespace {

// stack kept free below the prefaulted region, for the calls the loop makes from there
constexpr std::size_t kStackMargin = 64 * 1024;

std::string refused(const std::string& what, int err, const std::string& fix) {
  return what + " refused (" + std::strerror(err) + "); fix: " + fix;
}

bool lock_memory(RtReport& report) {
  if (mlockall(MCL_CURRENT | MCL_FUTURE) == 0) {
    report.notes.push_back("memory locked (mlockall current and future pages)");
    return true;
  }
  const int err = errno;
  report.notes.push_back(refused("memory locking", err,
                                 "run as root or grant CAP_IPC_LOCK, or raise memlock (ulimit -l unlimited, "
                                 "memlock in /etc/security/limits.conf); running with pageable memory"));
  return false;
}

bool set_fifo(int priority, RtReport& report) {
  sched_param sp{};
  sp.sched_priority = priority;
  const int err = pthread_setschedparam(pthread_self(), SCHED_FIFO, &sp);
  if (err == 0) {
    report.notes.push_back("SCHED_FIFO priority " + std::to_string(priority));
    return true;
  }
  report.notes.push_back(refused("SCHED_FIFO", err,
                                 "run as root or grant CAP_SYS_NICE / rtprio in /etc/security/limits.conf "
                                 "(in a container: --cap-add SYS_NICE); running with normal scheduling"));
  return false;
}

void set_nice(int nice, RtReport& report) {
  // the calling thread alone (Linux: a thread id is a PRIO_PROCESS target of its own)
  if (setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), nice) == 0) {
    report.notes.push_back("nice " + std::to_string(nice));
    return;
  }
  report.notes.push_back(refused("nice " + std::to_string(nice), errno,
                                 "grant CAP_SYS_NICE or a nice limit in /etc/security/limits.conf ('@realtime - nice -20'); other threads "
                                 "on the loop's CPU take their share of it"));
}

bool pin(const std::vector<int>& cpus, RtReport& report) {
  cpu_set_t set;
  CPU_ZERO(&set);
  for (const int c : cpus) CPU_SET(static_cast<std::size_t>(c), &set);
  const int err = pthread_setaffinity_np(pthread_self(), sizeof set, &set);
  if (err == 0) {
    report.notes.push_back("pinned to CPU " + cpu_list(cpus));
    return true;
  }
  report.notes.push_back(refused("pinning to CPU " + cpu_list(cpus), err,
                                 "use CPUs this process may run on (0.." + std::to_string(sysconf(_SC_NPROCESSORS_ONLN) - 1) +
                                     " here; see taskset -p and the cpuset of the container); running unpinned"));
  return false;
}

}  // namespace

void RtParams::validate() const {
  if (fifo_priority < 0 || fifo_priority > 99) {
    throw config::Error("rt: fifo_priority " + std::to_string(fifo_priority) +
                        " is out of range\n  fix: use 0 (normal scheduling) or a SCHED_FIFO priority from 1 to 99");
  }
  for (const int c : cpus) {
    if (c < 0 || c >= CPU_SETSIZE) {
      throw config::Error("rt: cpus entry " + std::to_string(c) + " is not a CPU index\n  fix: use CPU indices from 0 (see nproc), or an empty list to not pin");
    }
  }
}

std::string RtReport::summary() const {
  if (notes.empty()) return "no real-time setup requested";
  std::string out;
  for (const std::string& n : notes) {
    if (!out.empty()) out += "; ";
    out += n;
  }
  return out;
}

RtReport apply_rt_setup(const RtParams& params) {
  params.validate();
  RtReport report;
  // the kernel may wake a normal thread up to 50 us late to batch timers: no slack for the loop
  prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
  if (params.lock_memory) report.memory_locked = lock_memory(report);
  if (params.fifo_priority > 0) report.fifo = set_fifo(params.fifo_priority, report);
  else if (params.nice != 0) set_nice(params.nice, report);
  if (!params.cpus.empty()) report.pinned = pin(params.cpus, report);
  return report;
}

__attribute__((noinline)) void leave_fifo() noexcept {
  if (!running_fifo()) return;
  sched_param none{};
  pthread_setschedparam(pthread_self(), SCHED_OTHER, &none);
}

std::size_t prefault_stack(std::size_t bytes) {
  // room left on this thread's stack, below this frame
  pthread_attr_t attr;
  if (pthread_getattr_np(pthread_self(), &attr) == 0) {
    void* low = nullptr;
    std::size_t size = 0;
    pthread_attr_getstack(&attr, &low, &size);
    pthread_attr_destroy(&attr);
    // this frame's address, not a local's: under AddressSanitizer locals may live elsewhere
    const auto here = reinterpret_cast<std::uintptr_t>(__builtin_frame_address(0));
    const auto room = here - reinterpret_cast<std::uintptr_t>(low);
    bytes = std::min(bytes, room > kStackMargin ? room - kStackMargin : 0);
  }
  if (bytes == 0) return 0;
  // write one byte per page; volatile so the writes are kept
  auto* region = static_cast<volatile unsigned char*>(alloca(bytes));
  const auto page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
  for (std::size_t i = 0; i < bytes; i += page) region[i] = 0;
  region[bytes - 1] = 0;
  return bytes;
}

bool running_fifo() { return fifo_priority_now() > 0; }

int fifo_priority_now() {
  int policy = 0;
  sched_param sp{};
  return pthread_getschedparam(pthread_self(), &policy, &sp) == 0 && policy == SCHED_FIFO ? sp.sched_priority : 0;
}

}  // namespace enact::rt
