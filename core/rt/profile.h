#pragma once
// The real-time profile of a graph: where its processes run and how they are scheduled.
// The processes of the zero-delay loop (e.g. ffd and sim) and their ZeroMQ I/O threads share
// one CPU, so a message between them never waits for a wake-up on another, idle CPU (50-100
// us on a 2-vCPU VM); the launcher and the observers (logger, viewer, tactile driver) run on
// the other CPUs. The CPU latency request (/dev/cpu_dma_latency at 0) keeps the CPUs out of
// deep idle states while the graph runs. SCHED_FIFO is optional and ordered: the loop's I/O
// threads first, then the loop's processes in the order listed.
//
// The launcher applies its part (apply_launcher_profile) and hands each loop process its
// NodeProfile in the environment (ENACT_RT_PROFILE); the process applies it first thing
// (apply_node_profile), before its first socket. A refusal by the system is never an error:
// it is reported once, by the launcher, and the graph runs without that part.
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace enact::rt {

// what a launch file asks for (launch file entry `realtime:`)
struct GraphProfile {
  bool enabled = false;
  std::vector<std::string> loop;  // the loop's processes, by node name, highest priority first
  int fifo_priority = 0;          // 0: normal scheduling; P: I/O threads P, loop[i] at P-1-i
  bool cpu_latency = true;        // hold /dev/cpu_dma_latency at 0 while the graph runs
  // the loop's hop goes through ZeroMQ (loop_transport=zeromq): its I/O threads carry the
  // loop, so they share the loop's CPU and priority. Otherwise (the same-host link) they carry
  // only the observers' copies and run on the other CPUs, at normal priority.
  bool io_with_loop = false;
  // the loops of the graphs already running on this machine (the registry): CPU -> graph name.
  // This loop goes on a CPU none of them holds; where every CPU is held, it shares one and says
  // what that costs.
  std::map<int, std::string> other_loops;

  // throws config::Error for a priority outside 0..99, or too low to order the loop
  // (P - loop.size() must be >= 1)
  void validate() const;
};

// what one loop process applies to itself (and to the ZeroMQ context it is about to make)
struct NodeProfile {
  std::vector<int> cpus;     // pin the process (its main thread, and every thread it starts)
  std::vector<int> io_cpus;  // the ZeroMQ I/O threads' CPUs (empty: the process's)
  int fifo_priority = 0;     // SCHED_FIFO for the main thread (0: normal)
  int io_fifo_priority = 0;  // SCHED_FIFO for the ZeroMQ I/O threads (0: normal)
  int sharing = 1;           // the loop's processes pinned to these CPUs, this one included

  // "cpus=1 io_cpus=0 fifo=79 io_fifo=80 sharing=2" (the environment form); from_env reads it back
  std::string to_env() const;
  // throws config::Error naming ENACT_RT_PROFILE and the fix on a malformed text
  static NodeProfile from_env(const std::string& text);
};

// the system calls a profile makes, replaceable in tests. Each returns 0 or an errno value.
struct ProfileSystem {
  std::function<std::vector<int>()> allowed_cpus;                 // CPUs this process may use
  std::function<int(const std::vector<int>&)> pin_thread;         // the calling thread (and what it starts)
  std::function<int(int priority)> set_fifo;                      // the calling thread; 0: back to normal
  std::function<int(int& fd)> hold_cpu_latency;                   // open and write 0; fd stays open
  std::function<void(int fd)> release_cpu_latency;
};

// the real calls: sched_getaffinity, pthread_setaffinity_np, pthread_setschedparam,
// /dev/cpu_dma_latency
ProfileSystem system_calls();

// the launcher's part, held for the life of the object (the CPU latency request)
class LauncherProfile {
 public:
  // plans the CPUs (the loop on the last CPU this process may use, everything else on the
  // others; with a single CPU, everything shares it), pins the calling thread to the
  // others (call it before the launcher starts threads or processes: they inherit it), holds
  // the CPU latency request, and checks SCHED_FIFO is permitted. Refusals go to notes().
  LauncherProfile(const GraphProfile& profile, ProfileSystem system = system_calls());
  ~LauncherProfile();
  LauncherProfile(const LauncherProfile&) = delete;
  LauncherProfile& operator=(const LauncherProfile&) = delete;

  // whether `name` is one of the loop's processes (false when the profile is off)
  bool in_loop(const std::string& name) const;
  // the profile of loop process `name`: no CPUs and no FIFO when it is not in the loop
  // (then it keeps the launcher's CPUs) or when that part was refused
  NodeProfile node(const std::string& name) const;

  const std::vector<int>& loop_cpus() const { return loop_cpus_; }
  const std::vector<int>& other_cpus() const { return other_cpus_; }
  bool cpu_latency_held() const { return latency_fd_ >= 0; }
  bool fifo_permitted() const { return fifo_ok_; }

  // what was applied and what was refused (why, and the fix), one line each
  const std::vector<std::string>& notes() const { return notes_; }
  // the notes as one paragraph, starting "real-time profile: "
  std::string summary() const;

 private:
  GraphProfile profile_;
  ProfileSystem system_;
  std::vector<int> loop_cpus_, other_cpus_;
  std::vector<int> allowed_;  // the launcher's CPUs before the profile (given back at the end)
  bool pinned_ = false;
  bool fifo_ok_ = false;
  int latency_fd_ = -1;
  std::vector<std::string> notes_;
};

// what a loop process applied, and the settings for its ZeroMQ context's I/O threads
struct NodeProfileReport {
  bool pinned = false;
  bool fifo = false;
  std::vector<int> io_cpus;  // empty: do not pin the I/O threads
  int io_fifo_priority = 0;  // 0: do not change their scheduling (libzmq aborts on a refusal)
  std::vector<std::string> notes;

  // the notes as one line
  std::string summary() const;
};

// applies `profile` to the calling thread. The I/O thread settings are only those known to
// be permitted (the same CPUs once pinning worked, FIFO once FIFO worked).
NodeProfileReport apply_node_profile(const NodeProfile& profile, const ProfileSystem& system = system_calls());

// "1,3"
std::string cpu_list(const std::vector<int>& cpus);

}  // namespace enact::rt
