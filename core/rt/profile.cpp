#include "core/rt/profile.h"

#include <fcntl.h>
#include <pthread.h>
#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <sstream>

#include "core/config/env.h"
#include "core/config/share.h"
#include "core/config/yaml.h"

namespace enact::rt {
namespace {

constexpr const char* kLatencyDevice = "/dev/cpu_dma_latency";

// (the loop goes on without it)
std::string refused_going_on(const std::string& what, int err, const std::string& fix) {
  return what + " refused (" + std::strerror(err) + "); fix: " + fix + "; running without it";
}

std::string joined(const std::vector<std::string>& lines, const char* sep) {
  std::string out;
  for (const std::string& l : lines) out += (out.empty() ? "" : sep) + l;
  return out;
}

std::vector<int> parse_cpus(const std::string& text) {
  std::vector<int> out;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    std::size_t used = 0;
    const int cpu = std::stoi(item, &used);
    if (used != item.size() || cpu < 0 || cpu >= CPU_SETSIZE) throw std::invalid_argument(item);
    out.push_back(cpu);
  }
  return out;
}

int parse_priority(const std::string& text) {
  std::size_t used = 0;
  const int p = std::stoi(text, &used);
  if (used != text.size() || p < 0 || p > 99) throw std::invalid_argument(text);
  return p;
}

// the real system calls
std::vector<int> real_allowed_cpus() {
  cpu_set_t set;
  CPU_ZERO(&set);
  std::vector<int> out;
  if (sched_getaffinity(0, sizeof set, &set) != 0) return out;
  for (int c = 0; c < CPU_SETSIZE; ++c) {
    if (CPU_ISSET(c, &set)) out.push_back(c);
  }
  return out;
}

int real_pin_thread(const std::vector<int>& cpus) {
  cpu_set_t set;
  CPU_ZERO(&set);
  for (const int c : cpus) CPU_SET(static_cast<std::size_t>(c), &set);
  return pthread_setaffinity_np(pthread_self(), sizeof set, &set);
}

int real_set_fifo(int priority) {
  sched_param sp{};
  sp.sched_priority = priority;
  return pthread_setschedparam(pthread_self(), priority > 0 ? SCHED_FIFO : SCHED_OTHER, &sp);
}

int real_hold_cpu_latency(int& fd) {
  // the PM QoS interface: the request holds while the file stays open (kernel
  // Documentation/power/pm_qos_interface.rst); the value is a 32-bit latency in us
  fd = open(kLatencyDevice, O_WRONLY | O_CLOEXEC);
  if (fd < 0) return errno;
  const std::int32_t zero_us = 0;
  if (write(fd, &zero_us, sizeof zero_us) != static_cast<ssize_t>(sizeof zero_us)) {
    const int err = errno;
    close(fd);
    fd = -1;
    return err;
  }
  return 0;
}

void real_release_cpu_latency(int fd) { close(fd); }

}  // namespace

void GraphProfile::validate() const {
  const int lowest = fifo_priority - static_cast<int>(loop.size());
  if (fifo_priority < 0 || fifo_priority > 99 || (fifo_priority > 0 && lowest < 1)) {
    throw config::Error("realtime: fifo_priority " + std::to_string(fifo_priority) + " cannot order the loop's " + std::to_string(loop.size()) +
                        " processes below their I/O threads\n  fix: use 0 (normal scheduling) or a priority from " +
                        std::to_string(loop.size() + 1) + " to 99 (the I/O threads get it, the processes one less each)");
  }
}

std::string NodeProfile::to_env() const {
  return "cpus=" + cpu_list(cpus) + " io_cpus=" + cpu_list(io_cpus) + " fifo=" + std::to_string(fifo_priority) + " io_fifo=" + std::to_string(io_fifo_priority) + " sharing=" + std::to_string(sharing);
}

NodeProfile NodeProfile::from_env(const std::string& text) {
  NodeProfile out;
  std::stringstream in(text);
  for (std::string word; in >> word;) {
    const std::size_t eq = word.find('=');
    const std::string key = word.substr(0, eq), value = eq == std::string::npos ? "" : word.substr(eq + 1);
    try {
      if (key == "cpus") out.cpus = value.empty() ? std::vector<int>{} : parse_cpus(value);
      else if (key == "io_cpus") out.io_cpus = value.empty() ? std::vector<int>{} : parse_cpus(value);
      else if (key == "fifo") out.fifo_priority = parse_priority(value);
      else if (key == "io_fifo") out.io_fifo_priority = parse_priority(value);
      else if (key == "sharing") out.sharing = std::max(1, std::stoi(value));
      else throw std::invalid_argument(key);
    } catch (const std::exception&) {
      throw config::Error(std::string(env::kRtProfile) + ": cannot read '" + word +
                          "'\n  fix: unset it, or write e.g. \"cpus=1 fifo=0 io_fifo=0\" (enact launch sets it from the launch file's realtime: entry)");
    }
  }
  return out;
}

ProfileSystem system_calls() {
  return {real_allowed_cpus, real_pin_thread, real_set_fifo, real_hold_cpu_latency, real_release_cpu_latency};
}

LauncherProfile::LauncherProfile(const GraphProfile& profile, ProfileSystem system) : profile_(profile), system_(std::move(system)) {
  profile_.validate();
  if (!profile_.enabled) {
    notes_.push_back("off");
    return;
  }
  // the loop on the last CPU no other graph's loop holds, the rest on the CPUs no loop holds
  const std::vector<int> allowed = system_.allowed_cpus();
  allowed_ = allowed;
  if (allowed.size() >= 2 && !profile_.loop.empty()) {
    const auto held = [&](int cpu) { return profile_.other_loops.count(cpu) > 0; };
    const auto free_cpu = std::find_if(allowed.rbegin(), allowed.rend(), [&](int cpu) { return !held(cpu); });
    loop_cpus_ = {free_cpu != allowed.rend() ? *free_cpu : allowed.back()};
    for (const int cpu : allowed) {
      if (cpu != loop_cpus_[0] && !held(cpu)) other_cpus_.push_back(cpu);
    }
    if (other_cpus_.empty()) {
      for (const int cpu : allowed) {
        if (cpu != loop_cpus_[0]) other_cpus_.push_back(cpu);
      }
    }
    if (held(loop_cpus_[0])) {
      notes_.push_back("every CPU holds a loop already: this loop shares CPU " + std::to_string(loop_cpus_[0]) + " with graph '" +
                       profile_.other_loops.at(loop_cpus_[0]) + "'s loop, and both will miss deadlines (their watchdogs cut the force); "
                       "fix: stop the other graph (enact graph list), or give this machine another CPU");
    } else {
      for (const auto& [cpu, name] : profile_.other_loops) {
        if (std::find(allowed.begin(), allowed.end(), cpu) == allowed.end()) continue;
        notes_.push_back("graph '" + name + "'s loop holds CPU " + std::to_string(cpu) + (cpu == other_cpus_[0] && other_cpus_.size() == 1 ? ", where this graph's other processes run beside it" : "") +
                         ": this loop goes on CPU " + std::to_string(loop_cpus_[0]));
      }
    }
    const int err = system_.pin_thread(other_cpus_);
    pinned_ = err == 0;
    if (pinned_) {
      notes_.push_back("loop (" + joined(profile_.loop, ", ") + ") on CPU " + cpu_list(loop_cpus_) + ", the launcher, the other nodes" +
                       (profile_.io_with_loop ? "" : " and the loop's ZeroMQ I/O threads") + " on CPU " + cpu_list(other_cpus_));
    } else {
      notes_.push_back(refused_going_on("pinning to CPU " + cpu_list(other_cpus_), err, "allow this process every CPU of its cpuset (taskset -p, container cpuset)"));
      loop_cpus_.clear();
      other_cpus_.clear();
    }
  } else if (!profile_.loop.empty()) {
    notes_.push_back("one CPU (" + cpu_list(allowed) + "): the loop shares it with everything else, nothing to pin");
  }
  // the CPU latency request
  if (profile_.cpu_latency) {
    const int err = system_.hold_cpu_latency(latency_fd_);
    if (err == 0) notes_.push_back("CPU latency request 0 us held (" + std::string(kLatencyDevice) + ")");
    else {
      latency_fd_ = -1;
      notes_.push_back(refused_going_on("CPU latency request (" + std::string(kLatencyDevice) + ")", err,
                               "run as root, or let your user write it (" + config::shipped("scripts/udev/99-enact-cpu-latency.rules") + ")"));
    }
  }
  // SCHED_FIFO: try it here and go back, so that a refusal is said once, not once per node
  if (profile_.fifo_priority > 0) {
    const int err = system_.set_fifo(profile_.fifo_priority);
    fifo_ok_ = err == 0;
    if (fifo_ok_) {
      system_.set_fifo(0);
      const std::string io = profile_.io_with_loop ? "I/O threads " + std::to_string(profile_.fifo_priority) + ", " : "";
      notes_.push_back("SCHED_FIFO: " + io + joined(profile_.loop, " then ") + " from " + std::to_string(profile_.fifo_priority - 1) + " down");
    } else {
      notes_.push_back(refused_going_on("SCHED_FIFO " + std::to_string(profile_.fifo_priority), err,
                               "run as root or grant CAP_SYS_NICE / rtprio in /etc/security/limits.conf"));
    }
  } else {
    notes_.push_back("normal scheduling (fifo_priority 0)");
  }
}

LauncherProfile::~LauncherProfile() {
  if (latency_fd_ >= 0) system_.release_cpu_latency(latency_fd_);
  // the launcher's CPUs as they were (an experiment runs its next trial's profile from here)
  if (pinned_ && !allowed_.empty()) system_.pin_thread(allowed_);
}

bool LauncherProfile::in_loop(const std::string& name) const {
  if (!profile_.enabled) return false;
  for (const std::string& n : profile_.loop) {
    if (n == name) return true;
  }
  return false;
}

NodeProfile LauncherProfile::node(const std::string& name) const {
  NodeProfile out;
  if (!in_loop(name)) return out;
  for (std::size_t i = 0; i < profile_.loop.size(); ++i) {
    if (profile_.loop[i] != name) continue;
    out.cpus = loop_cpus_;
    out.sharing = static_cast<int>(profile_.loop.size());
    if (!profile_.io_with_loop) out.io_cpus = other_cpus_;
    if (fifo_ok_) {
      if (profile_.io_with_loop) out.io_fifo_priority = profile_.fifo_priority;
      out.fifo_priority = profile_.fifo_priority - 1 - static_cast<int>(i);
    }
  }
  return out;
}

std::string LauncherProfile::summary() const { return "real-time profile: " + joined(notes_, "; "); }

NodeProfileReport apply_node_profile(const NodeProfile& profile, const ProfileSystem& system) {
  NodeProfileReport r;
  if (!profile.cpus.empty()) {
    const int err = system.pin_thread(profile.cpus);
    r.pinned = err == 0;
    if (r.pinned) {
      r.io_cpus = profile.io_cpus.empty() ? profile.cpus : profile.io_cpus;
      r.notes.push_back("pinned to CPU " + cpu_list(profile.cpus) + ", its ZeroMQ I/O threads to CPU " + cpu_list(r.io_cpus));
    } else {
      r.notes.push_back(refused_going_on("pinning to CPU " + cpu_list(profile.cpus), err, "see the launcher's real-time profile"));
    }
  }
  if (profile.fifo_priority > 0) {
    const int err = system.set_fifo(profile.fifo_priority);
    r.fifo = err == 0;
    if (r.fifo) {
      r.io_fifo_priority = profile.io_fifo_priority;
      r.notes.push_back("SCHED_FIFO " + std::to_string(profile.fifo_priority) + ", I/O threads " +
                        (profile.io_fifo_priority > 0 ? std::to_string(profile.io_fifo_priority) : std::string("normal")));
    } else {
      r.notes.push_back(refused_going_on("SCHED_FIFO " + std::to_string(profile.fifo_priority), err, "see the launcher's real-time profile"));
    }
  }
  return r;
}

std::string NodeProfileReport::summary() const { return "real-time profile: " + (notes.empty() ? std::string("nothing to apply") : joined(notes, "; ")); }

std::string cpu_list(const std::vector<int>& cpus) {
  std::string out;
  for (const int c : cpus) out += (out.empty() ? "" : ",") + std::to_string(c);
  return out;
}

}  // namespace enact::rt
