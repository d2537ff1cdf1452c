#pragma once
// enact bench loop, shared by its arms (one file per family):
//   bench_loop_timer.cpp    the 5 kHz timer comparison and the co-located tick at 44 kHz
//   bench_loop_rtt.cpp      ffd -> sim -> ffd round trips, bus and raw ZeroMQ, ipc and tcp
//   bench_loop_peer.cpp     the second process answering those round trips
//   bench_loop_ddsperf.cpp  Cyclone DDS's ddsperf ping/pong, when installed
//   bench_loop_report.cpp   the machine's state, the printed report and the JSON file
//   bench_loop.cpp          the command: options, the real-time profile, the order of the arms
#include <algorithm>
#include <cstdint>
#include <string>
#include <thread>
#include <vector>

#include "core/rt/histogram.h"
#include "core/rt/loop_stats.h"
#include "core/rt/probe.h"
#include "core/rt/round_trip.h"
#include "core/rt/rt_setup.h"

namespace enact::cli::loop {

constexpr double kRate_hz = 5000.0;
constexpr std::int64_t kBlockTicks = 250;  // 50 ms at 5 kHz

// nanoseconds as microseconds
inline double us(std::int64_t ns) { return rt::to_us(ns); }

// a / b, b at least 1
inline double ratio(std::int64_t a, std::int64_t b) { return static_cast<double>(a) / static_cast<double>(std::max<std::int64_t>(1, b)); }

// the value at quantile q (0..1) of a sorted copy of v (0 when empty)
double quantile(std::vector<double> v, double q);

// which arm tick n belongs to: blocks of `block` ticks (1: tick by tick), the order of each
// pair flipped every other pair
inline int arm_of(std::int64_t n, std::int64_t block) {
  const std::int64_t b = n / block;
  return static_cast<int>((b + (b / 2)) % 2);
}

// ratios of p50s, over the run and per block
struct Ratios {
  double overall = 0.0;
  std::vector<double> blocks;
  // the ratio of this block's p50s (when both arms have one); empties both histograms
  void add_block(rt::LatencyHistogram& num, rt::LatencyHistogram& den);
};

// runs `body` in a thread set up like the loop's (timer slack 1 ns; the calling thread's
// CPUs and scheduling are inherited) and waits for it
template <class Body>
void loop_thread(Body body) {
  std::thread t([&] {
    rt::apply_rt_setup({});
    body();
  });
  t.join();
}

// ---- timer (bench_loop_timer.cpp) ----

struct TimerArm {
  rt::LatencyHistogram sleep_late, block, latency;
  std::uint64_t slept = 0, overshoot = 0;
};

struct TimerResult {
  TimerArm arm[2];  // 0: bare, 1: co-located
  Ratios p50;
  std::int64_t spin_ns = 0;
};

// a bare periodic thread and the co-located tick on `scene`, 5 kHz, `ticks` in all, in
// alternating blocks; `fifo`: sleep every tick (a FIFO thread must let others run)
TimerResult timer_5khz(const std::string& scene, std::int64_t ticks, bool fifo);

struct Rate44 {
  rt::LoopSummary loop;
  std::uint64_t deadlines = 0, missed = 0;
  std::string how;  // how the loop waited, and why (rt::WaitPlan)
};

// the co-located tick on `scene` at 44 kHz for `seconds`, waiting as enact-rt does on this
// machine (`own_cpu`: the loop has a CPU of its own), every missed deadline counted
Rate44 colocated_44khz(const std::string& scene, double seconds, bool fifo, bool own_cpu);

// ---- round trips (bench_loop_rtt.cpp, bench_loop_peer.cpp) ----

// the arms of a round-trip case, alternating tick by tick; the same-host arms (the local
// link and the pipe) run in the ipc case alone
enum Arm { kBus = 0, kRaw = 1, kLink = 2, kPipe = 3, kArms = 4 };

struct RttResult {
  rt::RoundTrip arm[kArms];  // bus over ZeroMQ, raw ZeroMQ, the loop's local link, a pipe
  Ratios p50;                // bus / raw ZeroMQ
  Ratios floor;              // local link / pipe (ipc case)
  std::uint64_t lost = 0;
};

struct RttResults {
  RttResult ipc, tcp;
};

// ffd -> sim -> ffd at 5 kHz, `seconds` over ipc then over tcp, the simulator in a second
// process (started with `peer_profile_env`, "" : none) whose sockets live in folder `dir`
RttResults round_trips(const std::string& dir, const std::string& scene, const std::string& peer_profile_env, double seconds, bool fifo);

// the peer endpoints, bound by the peer and printed on its stdout: bus ipc, raw ipc, bus tcp, raw tcp
struct PeerEndpoints {
  std::string bus[2], raw[2];
};

// what the peer is given: this side's 4 endpoints, comma-separated; the local link's path;
// the pipes' ends it reads requests from and writes replies to
struct PeerSetup {
  std::string parent_list, link_path;
  int pipe_in = -1, pipe_out = -1;
};

// the second process: `enact bench loop --peer DIR --peer-of ENDPOINTS --peer-link PATH
// --peer-pipes IN,OUT`, stopped by SIGTERM
class Peer {
 public:
  // starts it and reads its endpoints
  Peer(const std::string& dir, const std::string& scene, const PeerSetup& setup, const std::string& profile_env);
  ~Peer();
  Peer(const Peer&) = delete;
  Peer& operator=(const Peer&) = delete;
  const PeerEndpoints& endpoints() const { return ends_; }

 private:
  int pid_ = -1;
  PeerEndpoints ends_;
};

// the peer's body: a simulator answering DeviceStates on the bus (ipc in `dir`, and tcp) and
// over the local link, and a raw echo on ZeroMQ (ipc, tcp) and the pipes; until SIGTERM or
// its parent is gone
int run_peer(const std::string& dir, const std::string& scene, const PeerSetup& setup);

// ---- ddsperf (bench_loop_ddsperf.cpp) ----

struct DdsPerf {
  bool ran = false;
  double p50_us = 0.0, p99_us = 0.0;  // medians over its per-second reports
  std::uint64_t round_trips = 0, expected = 0;
};

// Cyclone DDS's ping/pong at 5 kHz, 100 bytes, for `seconds`; both processes inherit this
// thread's CPU and scheduling (ran false when ddsperf is not installed)
DdsPerf ddsperf(double seconds);

// ---- the machine and the report (bench_loop_report.cpp) ----

struct CpuTimes {
  std::uint64_t total = 0, steal = 0;
};

// /proc/stat's first line: all CPU time and stolen time, in ticks
CpuTimes cpu_times();
// /proc/loadavg: "1 5 15"
std::string load_average();

struct Machine {
  unsigned cores = std::thread::hardware_concurrency();
  CpuTimes start = cpu_times();
  std::string load_start = load_average();
  std::string profile;  // the launcher's and this thread's profile notes
  bool latency_held = false;
  std::vector<int> loop_cpus;
  bool fifo = false;
  rt::MachineProbe probe;  // this boot's probe (rt::cached_probe), printed beside the figures
  // the stolen share of CPU time since construction, percent
  double steal_pct() const;
};

// every figure of a run
struct LoopResults {
  double seconds = 0.0;
  std::int64_t jitter_ticks = 0;
  int fifo_priority = 0;
  TimerResult timer;
  Rate44 r44;
  RttResults rtt;
  DdsPerf dds;
  Machine machine;
  double steal_pct = 0.0;
};

// prints the report on stdout; with a `json_path`, writes every figure there too
void report(const LoopResults& r, const std::string& json_path);

}  // namespace enact::cli::loop
