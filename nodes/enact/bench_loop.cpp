// enact bench loop: the real-time loop measured against the machine's floor, each pair of
// arms in the same run, alternating, so that noise hits both arms alike:
//  - timer: a bare periodic thread and the co-located tick (bridge, simulated devices) at
//    5 kHz, in short blocks with the order flipped; jitter = how late the sleep ends, before
//    any spin; then the co-located tick at 44 kHz, every missed deadline counted;
//  - round trip: ffd -> sim -> ffd over the bus (DeviceState out, a simulator steps in a
//    second process, ForceCommand back) and a raw ZeroMQ ping-pong of the same sizes and
//    layout, alternating tick by tick, over ipc and tcp; replies matched by sequence number.
// The machine's state (cores, steal, load, CPU latency request, pinning, FIFO) is recorded.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <thread>

#include "core/bus/context.h"
#include "core/bus/typed.h"
#include "core/devices/safety.h"
#include "core/devices/simulated_force.h"
#include "core/devices/simulated_tactile.h"
#include "core/graph/colocated.h"
#include "core/graph/messages.h"
#include "core/graph/node.h"
#include "core/graph/temp_folder.h"
#include "core/launch/launch_file.h"
#include "core/rt/clock.h"
#include "core/rt/profile.h"
#include "core/rt/round_trip.h"
#include "core/rt/rt_setup.h"
#include "core/rt/scheduler.h"
#include "nodes/enact/commands.h"
#include "nodes/enact/json.h"

namespace enact::cli {
namespace {

constexpr const char* kHelp = R"(usage: enact bench loop [--json FILE] [--seconds S] [--jitter-ticks N] [--scene PATH]
                        [--fifo PRIORITY] [--no-profile]

The real-time loop against the machine's floor; the arms of each comparison alternate in
the same run (noise hits both alike):
  timer     a bare periodic thread and the co-located tick (bridge scene, simulated ERGOS
            and cells) at 5 kHz, in blocks of 250 ticks with the order flipped; jitter = how
            late the sleep ends, before the spin (and the fraction of ticks it overshoots the
            spin window); then the co-located tick at 44 kHz, every missed deadline counted
  rtt       ffd -> sim -> ffd at 5 kHz with the simulator in a second process, like the
            graph: the bus (DeviceState, a simulator step, ForceCommand) and a raw ZeroMQ
            ping-pong of the same sizes and socket layout, alternating tick by tick, over ipc
            then tcp; replies matched by sequence number (stale and unanswered counted per arm)
  peer      when ddsperf is installed (Debian cyclonedds-tools): Cyclone DDS's ping/pong at
            5 kHz, 100 bytes, on the same CPU, reported beside ours
The shipped graphs' real-time profile applies (loop threads and the peer on one CPU, CPU
latency request held, SCHED_FIFO 80 ordered as in a launch file) unless --no-profile;
--fifo P changes the priority (0: normal scheduling). Refusals are said, the bench runs.

options:
  --seconds S       each round-trip case and the 44 kHz case (default 5)
  --jitter-ticks N  ticks of the 5 kHz timer comparison, both arms (default 100000: 20 s)
  --json FILE       every figure, with the machine's state
JSON: distributed_rtt_p50_ratio (bus / raw ZeroMQ, ipc; expected 0.7-1.3),
colocated_jitter_p99_ratio, colocated_latency_p99_us, colocated_44khz_missed_fraction, ...
Total time at the defaults: about 45 s. (--peer DIR --peer-of ENDPOINTS: the second
process, started by the bench itself.)
)";

constexpr double kRate_hz = 5000.0;
constexpr std::int64_t kBlockTicks = 250;  // 50 ms at 5 kHz
constexpr std::size_t kRawSize = 64;       // raw payload: seq (8 bytes) then filler

double us(std::int64_t ns) { return static_cast<double>(ns) * 1e-3; }

// per-block ratios: the value at quantile q (0..1) of a sorted copy
double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5)];
}

double ratio(std::int64_t a, std::int64_t b) { return static_cast<double>(a) / static_cast<double>(std::max<std::int64_t>(1, b)); }

// which arm tick n belongs to: blocks of `block` ticks (1: tick by tick), the order of each
// pair flipped every other pair
int arm_of(std::int64_t n, std::int64_t block) {
  const std::int64_t b = n / block;
  return static_cast<int>((b + (b / 2)) % 2);
}

// ratios of p50s, over the run and per block
struct Ratios {
  double overall = 0.0;
  std::vector<double> blocks;
  void add_block(rt::LatencyHistogram& num, rt::LatencyHistogram& den) {
    if (num.count() > 0 && den.count() > 0) blocks.push_back(ratio(num.percentile(50.0), den.percentile(50.0)));
    num.reset();
    den.reset();
  }
};

// ---- the machine -------------------------------------------------------------------

struct CpuTimes {
  std::uint64_t total = 0, steal = 0;
};

CpuTimes cpu_times() {
  std::ifstream in("/proc/stat");
  std::string cpu;
  in >> cpu;
  CpuTimes t;
  for (int i = 0; i < 10; ++i) {
    std::uint64_t v = 0;
    if (!(in >> v)) break;
    t.total += i < 8 ? v : 0;  // guest time is already in user time
    if (i == 7) t.steal = v;
  }
  return t;
}

std::string load_average() {
  std::ifstream in("/proc/loadavg");
  std::string one, five, fifteen;
  in >> one >> five >> fifteen;
  return one + " " + five + " " + fifteen;
}

struct Machine {
  unsigned cores = std::thread::hardware_concurrency();
  CpuTimes start = cpu_times();
  std::string load_start = load_average();
  std::string profile;  // the launcher's and this thread's profile notes
  bool latency_held = false;
  std::vector<int> loop_cpus;
  bool fifo = false;

  double steal_pct() const {
    const CpuTimes end = cpu_times();
    return 100.0 * static_cast<double>(end.steal - start.steal) / static_cast<double>(std::max<std::uint64_t>(1, end.total - start.total));
  }
};

// ---- timer: bare thread and co-located tick ------------------------------------------

struct TimerArm {
  rt::LatencyHistogram sleep_late, block, latency;
  std::uint64_t slept = 0, overshoot = 0;
};

struct TimerResult {
  TimerArm arm[2];  // 0: bare, 1: co-located
  Ratios p50;
  std::int64_t spin_ns = 0;
};

struct Colocated {
  sim::Simulator simulator;
  std::unique_ptr<devices::SafeForceDevice> force;
  devices::SimulatedTactileDevice tactile;
  std::unique_ptr<graph::ColocatedLoop> loop;

  Colocated(const std::string& scene, double rate_hz) {
    sim::SimParams p;
    p.scene = scene;
    p.rate_hz = rate_hz;
    simulator.configure(p);
    devices::SimulatedForceParams f;
    f.start_m = {-0.0074246, -0.0222739, 0.0119};  // resting on the start of the bridge
    force = std::make_unique<devices::SafeForceDevice>(std::make_unique<devices::SimulatedForceDevice>(f));
    force->configure();
    tactile.configure();
    loop = std::make_unique<graph::ColocatedLoop>(simulator, *force, tactile, &rt::now_ns);
    loop->activate();
  }
  ~Colocated() { loop->deactivate(); }
  std::int64_t tick(std::int64_t now) {
    const graph::Observation& o = loop->tick(now);
    return o.force_ns - o.sample.time_ns;
  }
};

// runs `body` in a thread set up like the loop's (timer slack 1 ns; the calling thread's
// CPUs and scheduling are inherited)
template <class Body>
void loop_thread(Body body) {
  std::thread t([&] {
    rt::apply_rt_setup({});
    body();
  });
  t.join();
}

TimerResult timer_5khz(const std::string& scene, std::int64_t ticks, bool fifo) {
  TimerResult r;
  Colocated col(scene, kRate_hz);
  loop_thread([&] {
    rt::PeriodicScheduler s({.rate_hz = kRate_hz, .spin_ns = 50'000, .sleep_every_tick = fifo});
    r.spin_ns = s.spin_ns();
    s.start(rt::now_ns() + 1'000'000);
    for (std::int64_t n = 0; n < ticks; ++n) {
      const std::int64_t woke = s.wait();
      TimerArm& arm = r.arm[arm_of(n, kBlockTicks)];
      const std::int64_t late = s.last_sleep_late_ns();
      if (late >= 0) {
        arm.sleep_late.record(late);
        arm.block.record(late);
        ++arm.slept;
        arm.overshoot += late > s.spin_ns() ? 1 : 0;
      }
      if (&arm == &r.arm[1]) arm.latency.record(col.tick(woke));
      if (n % (2 * kBlockTicks) == 2 * kBlockTicks - 1) r.p50.add_block(r.arm[1].block, r.arm[0].block);
    }
  });
  r.p50.overall = ratio(r.arm[1].sleep_late.percentile(50.0), r.arm[0].sleep_late.percentile(50.0));
  return r;
}

struct Rate44 {
  rt::LoopSummary loop;
  std::uint64_t deadlines = 0, missed = 0;
};

Rate44 colocated_44khz(const std::string& scene, double seconds, bool fifo) {
  Rate44 r;
  Colocated col(scene, 44000.0);
  loop_thread([&] {
    rt::PeriodicScheduler s({.rate_hz = 44000.0, .spin_ns = 50'000, .sleep_every_tick = fifo});
    rt::LoopStats stats;
    const std::int64_t start = rt::now_ns() + 1'000'000;
    const std::int64_t end = start + static_cast<std::int64_t>(seconds * 1e9);
    s.start(start);
    for (std::int64_t now = s.wait(); now < end; now = s.wait()) stats.latency.record(col.tick(now));
    rt::take_timing(s, stats);
    r.loop = rt::summarize(stats, 44000.0);
    r.deadlines = s.ticks() + s.skipped();
    r.missed = s.overruns();
  });
  return r;
}

// ---- round trip: the peer process ---------------------------------------------------

// the peer's endpoints, bound by the peer and printed on its stdout: bus ipc, raw ipc, bus tcp, raw tcp
struct PeerEndpoints {
  std::string bus[2], raw[2];
};

// the peer: a simulator answering DeviceStates on the bus, and a raw echo, on ipc and tcp
int run_peer(const std::string& dir, const std::string& scene, const std::string& parent_list) {
  graph::install_stop_handlers();
  graph::apply_rt_profile("peer");
  std::vector<std::string> parent;
  std::stringstream in(parent_list);
  for (std::string e; std::getline(in, e, ',');) parent.push_back(e);
  if (parent.size() != 4) throw UsageError("--peer-of needs 4 endpoints");
  sim::SimParams p;
  p.scene = scene;
  sim::Simulator simulator;
  simulator.configure(p);
  simulator.activate(0);
  struct Side {
    std::unique_ptr<bus::BytePublisher> out;
    std::unique_ptr<bus::Publisher<msgs::ForceCommand>> forces;
    bus::ByteSubscriber in;
    std::unique_ptr<bus::Subscriber<msgs::DeviceState>> states;
    zmq::socket_t raw_pub{bus::context(), zmq::socket_type::pub}, raw_sub{bus::context(), zmq::socket_type::sub};
  } sides[2];
  const std::string binds[2][2] = {{"ipc://" + dir + "/peer-bus", "ipc://" + dir + "/peer-raw"}, {"tcp://127.0.0.1:*", "tcp://127.0.0.1:*"}};
  for (int i = 0; i < 2; ++i) {
    Side& s = sides[i];
    s.out = std::make_unique<bus::BytePublisher>(binds[i][0], bus::PublisherOptions{.node = "sim", .send_hwm = 10000});
    s.forces = std::make_unique<bus::Publisher<msgs::ForceCommand>>(*s.out, "ffd/force");
    s.states = std::make_unique<bus::Subscriber<msgs::DeviceState>>(s.in, "ffd/state");
    s.in.connect(parent[2 * i]);
    for (zmq::socket_t* z : {&s.raw_pub, &s.raw_sub}) z->set(zmq::sockopt::linger, 0);
    s.raw_pub.bind(binds[i][1]);
    s.raw_sub.set(zmq::sockopt::subscribe, "");
    s.raw_sub.connect(parent[2 * i + 1]);
  }
  std::printf("%s %s %s %s\n", sides[0].out->endpoint().c_str(), sides[0].raw_pub.get(zmq::sockopt::last_endpoint).c_str(),
              sides[1].out->endpoint().c_str(), sides[1].raw_pub.get(zmq::sockopt::last_endpoint).c_str());
  std::fflush(stdout);
  msgs::DeviceState state;
  msgs::ForceCommand command;
  zmq::message_t m;
  zmq::pollitem_t items[4] = {{sides[0].in.socket().handle(), 0, ZMQ_POLLIN, 0}, {sides[0].raw_sub.handle(), 0, ZMQ_POLLIN, 0},
                              {sides[1].in.socket().handle(), 0, ZMQ_POLLIN, 0}, {sides[1].raw_sub.handle(), 0, ZMQ_POLLIN, 0}};
  // answer until told to stop (SIGTERM) or the parent is gone (its stdin pipe closed)
  while (!graph::stop_requested() && getppid() != 1) {
    try {
      if (zmq::poll(items, 4, std::chrono::milliseconds(100)) == 0) continue;
    } catch (const zmq::error_t&) {
      continue;
    }
    for (int i = 0; i < 2; ++i) {
      Side& s = sides[i];
      while (s.states->receive(state, 0)) {
        const sim::StepOutput& o = simulator.step(state.header().stamp_ns(), graph::get(state.position()));
        graph::fill(command, state.header().seq(), o.force_n, o.fault);
        s.forces->publish(command);
      }
      while (s.raw_sub.recv(m, zmq::recv_flags::dontwait)) s.raw_pub.send(zmq::buffer(m.data(), m.size()), zmq::send_flags::dontwait);
    }
  }
  return 0;
}

// the peer process, started with the loop's profile, stopped by SIGTERM
class Peer {
 public:
  Peer(const std::string& dir, const std::string& scene, const std::string& parent_list, const std::string& profile_env) {
    // its command line and environment, made before fork (the child only execs)
    const std::string self = std::filesystem::read_symlink("/proc/self/exe").string();
    std::vector<std::string> args = {self, "bench", "loop", "--peer", dir, "--scene", scene, "--peer-of", parent_list};
    std::vector<std::string> env;
    const std::string profile_key = std::string(rt::kProfileEnv) + "=";
    for (char** e = environ; *e; ++e) {
      if (std::strncmp(*e, profile_key.c_str(), profile_key.size()) != 0) env.emplace_back(*e);
    }
    if (!profile_env.empty()) env.push_back(profile_key + profile_env);
    std::vector<char*> argv, envp;
    for (std::string& s : args) argv.push_back(s.data());
    for (std::string& s : env) envp.push_back(s.data());
    argv.push_back(nullptr);
    envp.push_back(nullptr);
    int out[2];
    if (pipe(out) != 0) throw std::runtime_error("bench loop: pipe failed");
    pid_ = fork();
    if (pid_ == 0) {
      dup2(out[1], STDOUT_FILENO);
      close(out[0]);
      close(out[1]);
      execve(self.c_str(), argv.data(), envp.data());
      _exit(127);
    }
    close(out[1]);
    // the peer's endpoints: the first line it prints, once bound
    FILE* f = fdopen(out[0], "r");
    char line[4096] = {};
    const bool got = f && std::fgets(line, sizeof line, f);
    if (f) std::fclose(f);
    std::stringstream words(got ? line : "");
    words >> ends_.bus[0] >> ends_.raw[0] >> ends_.bus[1] >> ends_.raw[1];
    if (ends_.raw[1].empty()) throw std::runtime_error("bench loop: the peer process did not start (see above)");
  }
  ~Peer() {
    kill(pid_, SIGTERM);
    int status = 0;
    waitpid(pid_, &status, 0);
  }
  const PeerEndpoints& endpoints() const { return ends_; }

 private:
  pid_t pid_ = -1;
  PeerEndpoints ends_;
};

// ---- round trip: this side ----------------------------------------------------------

struct RttResult {
  rt::RoundTrip arm[2];  // 0: bus, 1: raw
  Ratios p50;
  std::uint64_t lost = 0;
};

// one transport: the bus and the raw ping-pong, alternating tick by tick
class RttCase {
 public:
  RttCase(const std::string& bus_bind, const std::string& raw_bind)
      : out_(bus_bind, {.node = "ffd", .send_hwm = 10000}), states_(out_, "ffd/state"), forces_(in_, "ffd/force") {
    for (zmq::socket_t* z : {&raw_pub_, &raw_sub_}) z->set(zmq::sockopt::linger, 0);
    raw_pub_.bind(raw_bind);
    raw_sub_.set(zmq::sockopt::subscribe, "");
    graph::set(*state_.mutable_position(), {-0.0074246, -0.0222739, 0.0119});
    std::fill(raw_.begin(), raw_.end(), 'a');
  }
  std::string bus_endpoint() const { return out_.endpoint(); }
  std::string raw_endpoint() { return raw_pub_.get(zmq::sockopt::last_endpoint); }

  // connect to the peer, then ping both arms until each has answered (at most 10 s)
  void handshake(const std::string& peer_bus, const std::string& peer_raw) {
    in_.connect(peer_bus);
    raw_sub_.connect(peer_raw);
    const std::int64_t give_up = rt::now_ns() + 10'000'000'000;
    bool ok[2] = {false, false};
    while (!(ok[0] && ok[1]) && rt::now_ns() < give_up) {
      for (int a = 0; a < 2; ++a) ok[a] = ok[a] || exchange(a, rt::now_ns(), rt::now_ns() + 2'000'000, handshake_[a]);
    }
    if (!(ok[0] && ok[1])) throw std::runtime_error("bench loop: the peer did not answer within 10 s");
    // replies to the handshake's unanswered pings come back as stale: let them arrive now
    rt::sleep_until_ns(rt::now_ns() + 20'000'000);
    for (int a = 0; a < 2; ++a) exchange(a, rt::now_ns(), rt::now_ns(), handshake_[a]);
  }

  RttResult run(double seconds, bool fifo) {
    RttResult r;
    rt::LatencyHistogram block[2];
    loop_thread([&] {
      rt::PeriodicScheduler s({.rate_hz = kRate_hz, .spin_ns = 50'000, .sleep_every_tick = fifo});
      const std::int64_t start = rt::now_ns() + 1'000'000;
      const std::int64_t end = start + static_cast<std::int64_t>(seconds * 1e9);
      s.start(start);
      for (std::int64_t n = 0;; ++n) {
        const std::int64_t now = s.wait();
        if (now >= end) break;
        const int a = arm_of(n, 1);
        // the answer to this tick's request, until just before the next tick
        if (exchange(a, now, s.next_deadline_ns() - s.spin_ns(), r.arm[a])) block[a].record(r.arm[a].last_rtt_ns());
        if (n % (2 * kBlockTicks) == 2 * kBlockTicks - 1) r.p50.add_block(block[0], block[1]);
      }
    });
    r.p50.overall = ratio(r.arm[0].rtt().percentile(50.0), r.arm[1].rtt().percentile(50.0));
    r.lost = forces_.counters().lost;
    return r;
  }

 private:
  // arm 0 (bus) or 1 (raw): send request, wait for the reply carrying its number until
  // answer_by; replies to earlier requests are counted stale by `trip`
  bool exchange(int arm, std::int64_t now, std::int64_t answer_by, rt::RoundTrip& trip) {
    if (arm == 0) {
      state_.mutable_header()->set_stamp_ns(now);
      states_.publish(state_);
      trip.sent(state_.header().seq(), now);
      while (graph::wait_readable(in_.socket(), answer_by)) {
        while (forces_.receive(command_, 0)) {
          if (trip.reply(command_.answered_seq(), rt::now_ns())) return true;
        }
      }
    } else {
      ++raw_seq_;
      std::memcpy(raw_.data(), &raw_seq_, sizeof raw_seq_);
      raw_pub_.send(zmq::buffer(raw_), zmq::send_flags::dontwait);
      trip.sent(raw_seq_, now);
      while (graph::wait_readable(raw_sub_, answer_by)) {
        while (raw_sub_.recv(reply_, zmq::recv_flags::dontwait)) {
          std::uint64_t seq = 0;
          if (reply_.size() >= sizeof seq) std::memcpy(&seq, reply_.data(), sizeof seq);
          if (trip.reply(seq, rt::now_ns())) return true;
        }
      }
    }
    trip.close();
    return false;
  }

  bus::BytePublisher out_;
  bus::Publisher<msgs::DeviceState> states_;
  bus::ByteSubscriber in_;
  bus::Subscriber<msgs::ForceCommand> forces_;
  zmq::socket_t raw_pub_{bus::context(), zmq::socket_type::pub}, raw_sub_{bus::context(), zmq::socket_type::sub};
  msgs::DeviceState state_;
  msgs::ForceCommand command_;
  std::array<char, kRawSize> raw_{};
  std::uint64_t raw_seq_ = 0;
  zmq::message_t reply_;
  rt::RoundTrip handshake_[2];
};

// ---- peer arm: Cyclone DDS's ddsperf ping/pong, when installed ----------------------

struct DdsPerf {
  bool ran = false;
  double p50_us = 0.0, p99_us = 0.0;  // medians over its per-second reports
  std::uint64_t round_trips = 0, expected = 0;
};

// the number after `key` in a ddsperf report line ("50% 16.6us", "cnt 1370"), -1 if absent
double after(const std::string& line, const std::string& key) {
  const std::size_t at = line.find(key);
  return at == std::string::npos ? -1.0 : std::atof(line.c_str() + at + key.size());
}

// the same 5 kHz ping/pong of 100 bytes, both processes started from this thread (they
// inherit its CPU and scheduling: the loop's)
DdsPerf ddsperf(double seconds) {
  DdsPerf r;
  const std::string exe = launch::default_resolver()("ddsperf");
  if (exe.empty()) return r;
  const int s = static_cast<int>(std::ceil(seconds));
  FILE* pong = popen((exe + " -D " + std::to_string(s + 3) + " pong >/dev/null 2>&1").c_str(), "r");
  FILE* ping = popen((exe + " -D " + std::to_string(s) + " -Qminmatch:1 ping 5000Hz size 100 2>&1").c_str(), "r");
  std::vector<double> p50, p99;
  char buf[1024];
  while (ping && std::fgets(buf, sizeof buf, ping)) {
    const std::string line = buf;
    if (line.find(" size 100 mean ") == std::string::npos) continue;
    p50.push_back(after(line, " 50% "));
    p99.push_back(after(line, " 99% "));
    r.round_trips += static_cast<std::uint64_t>(std::max(0.0, after(line, " cnt ")));
  }
  if (ping) pclose(ping);
  if (pong) pclose(pong);
  r.ran = !p50.empty();
  r.p50_us = quantile(p50, 0.5);
  r.p99_us = quantile(p99, 0.5);
  r.expected = static_cast<std::uint64_t>(kRate_hz * static_cast<double>(p50.size()));
  return r;
}

// ---- output -------------------------------------------------------------------------

void print_ratios(const char* what, const Ratios& r) {
  std::printf("  %s p50 ratio %.2f; per block of %lld ticks: median %.2f, p10 %.2f, p90 %.2f (%zu blocks)\n", what, r.overall,
              static_cast<long long>(2 * kBlockTicks), quantile(r.blocks, 0.5), quantile(r.blocks, 0.1), quantile(r.blocks, 0.9), r.blocks.size());
}

void json_ratios(Json& j, const std::string& key, const Ratios& r) {
  j.key(key).begin_object().field("overall", r.overall).field("block_median", quantile(r.blocks, 0.5));
  j.field("block_p10", quantile(r.blocks, 0.1)).field("block_p90", quantile(r.blocks, 0.9)).field("blocks", static_cast<long long>(r.blocks.size())).end_object();
}

void print_timer_arm(const char* name, const TimerArm& a, std::int64_t spin_ns) {
  std::printf("  %-12s sleep lateness p50 %7.2f  p99 %7.2f  p99.9 %8.2f  max %8.2f us; past the %.0f us spin window: %.3f %% of %llu ticks\n", name,
              us(a.sleep_late.percentile(50.0)), us(a.sleep_late.percentile(99.0)), us(a.sleep_late.percentile(99.9)), us(a.sleep_late.max()), us(spin_ns),
              100.0 * static_cast<double>(a.overshoot) / static_cast<double>(std::max<std::uint64_t>(1, a.slept)), static_cast<unsigned long long>(a.slept));
}

void print_trip(const char* name, const rt::RoundTrip& t) {
  std::printf("  %-12s round trip p50 %7.2f  p99 %7.2f  p99.9 %8.2f  max %8.2f us; %llu requests, stale %llu, unanswered %llu\n", name,
              us(t.rtt().percentile(50.0)), us(t.rtt().percentile(99.0)), us(t.rtt().percentile(99.9)), us(t.rtt().max()),
              static_cast<unsigned long long>(t.requests()), static_cast<unsigned long long>(t.stale()), static_cast<unsigned long long>(t.unanswered()));
}

void json_trip(Json& j, const std::string& key, const rt::RoundTrip& t) {
  j.key(key).begin_object().field("p50_us", us(t.rtt().percentile(50.0))).field("p99_us", us(t.rtt().percentile(99.0)));
  j.field("p999_us", us(t.rtt().percentile(99.9))).field("max_us", us(t.rtt().max())).field("requests", static_cast<long long>(t.requests()));
  j.field("stale", static_cast<long long>(t.stale())).field("unanswered", static_cast<long long>(t.unanswered())).end_object();
}

void json_timer_arm(Json& j, const std::string& key, const TimerArm& a) {
  j.key(key).begin_object().field("sleep_late_p50_us", us(a.sleep_late.percentile(50.0))).field("sleep_late_p99_us", us(a.sleep_late.percentile(99.0)));
  j.field("sleep_late_p999_us", us(a.sleep_late.percentile(99.9))).field("sleep_late_max_us", us(a.sleep_late.max()));
  j.field("past_spin_window_fraction", static_cast<double>(a.overshoot) / static_cast<double>(std::max<std::uint64_t>(1, a.slept)));
  j.field("ticks", static_cast<long long>(a.slept)).end_object();
}

}  // namespace

int bench_loop(int argc, char** argv) {
  const Args a = parse(argc, argv, 3, {"json", "seconds", "jitter-ticks", "scene", "fifo", "peer", "peer-of"}, {"no-profile"});
  if (a.flag("help")) {
    std::fputs(kHelp, stdout);
    return 0;
  }
  const std::string scene = find_file(a.get("scene", "launch/scenes/bridge.yaml"));
  if (a.has("peer")) return run_peer(a.get("peer"), scene, a.get("peer-of"));
  const double seconds = a.number("seconds", 5.0);
  const auto jitter_ticks = static_cast<std::int64_t>(a.number("jitter-ticks", 100000.0));
  const int fifo = static_cast<int>(a.number("fifo", 80.0));
  if (seconds <= 0.0 || jitter_ticks < 2 * kBlockTicks) throw UsageError("--seconds must be > 0 and --jitter-ticks at least 500");

  // the graph's profile: this thread and the peer are the loop
  Machine machine;
  const rt::GraphProfile graph_profile{.enabled = !a.flag("no-profile"), .loop = {"bench", "peer"}, .fifo_priority = fifo, .cpu_latency = true};
  const rt::LauncherProfile profile(graph_profile);
  const rt::NodeProfileReport self = rt::apply_node_profile(profile.node("bench"));
  bus::set_io_threads({self.io_cpus, self.io_fifo_priority});
  machine.profile = profile.summary() + (self.notes.empty() ? "" : "; this process: " + self.summary());
  machine.latency_held = profile.cpu_latency_held();
  machine.loop_cpus = profile.loop_cpus();
  machine.fifo = self.fifo;
  std::fprintf(stderr, "enact bench loop: %s\nabout %.0f s: timer %lld ticks at 5 kHz, 44 kHz %.1f s, round trips ipc, tcp and ddsperf %.1f s each\n", machine.profile.c_str(),
               static_cast<double>(jitter_ticks) / kRate_hz + 4.0 * seconds, static_cast<long long>(jitter_ticks), seconds, seconds);

  const TimerResult timer = timer_5khz(scene, jitter_ticks, machine.fifo);
  const Rate44 r44 = colocated_44khz(scene, seconds, machine.fifo);
  const graph::TempFolder dir("/tmp/enact-bench-");
  RttCase ipc("ipc://" + dir.path() + "/ffd-bus", "ipc://" + dir.path() + "/ffd-raw");
  RttCase tcp("tcp://127.0.0.1:*", "tcp://127.0.0.1:*");
  const std::string parent = ipc.bus_endpoint() + "," + ipc.raw_endpoint() + "," + tcp.bus_endpoint() + "," + tcp.raw_endpoint();
  RttResult ipc_r, tcp_r;
  {
    const Peer peer(dir.path(), scene, parent, profile.in_loop("peer") ? profile.node("peer").to_env() : "");
    ipc.handshake(peer.endpoints().bus[0], peer.endpoints().raw[0]);
    tcp.handshake(peer.endpoints().bus[1], peer.endpoints().raw[1]);
    ipc_r = ipc.run(seconds, machine.fifo);
    tcp_r = tcp.run(seconds, machine.fifo);
  }
  const DdsPerf dds = ddsperf(seconds);
  const double steal = machine.steal_pct();

  // report
  const double jitter_p99_ratio = ratio(timer.arm[1].sleep_late.percentile(99.0), timer.arm[0].sleep_late.percentile(99.0));
  const double missed44 = static_cast<double>(r44.missed) / static_cast<double>(std::max<std::uint64_t>(1, r44.deadlines));
  std::printf("timer at 5 kHz, bare thread and co-located tick in alternating blocks (us)\n");
  print_timer_arm("bare", timer.arm[0], timer.spin_ns);
  print_timer_arm("co-located", timer.arm[1], timer.spin_ns);
  print_ratios("co-located / bare sleep lateness", timer.p50);
  std::printf("  jitter p99 ratio %.2f; co-located sample-to-force p50 %.2f, p99 %.2f us\n", jitter_p99_ratio, us(timer.arm[1].latency.percentile(50.0)),
              us(timer.arm[1].latency.percentile(99.0)));
  std::printf("co-located at 44 kHz: %llu of %llu deadlines missed (%.3f %%), sample-to-force p99 %.2f us\n", static_cast<unsigned long long>(r44.missed),
              static_cast<unsigned long long>(r44.deadlines), 100.0 * missed44, us(r44.loop.latency_p99_ns));
  std::printf("round trip ffd -> sim (second process) -> ffd at 5 kHz, bus and raw ZeroMQ tick by tick (us)\n");
  print_trip("bus ipc", ipc_r.arm[0]);
  print_trip("raw ipc", ipc_r.arm[1]);
  print_ratios("bus / raw ipc", ipc_r.p50);
  print_trip("bus tcp", tcp_r.arm[0]);
  print_trip("raw tcp", tcp_r.arm[1]);
  print_ratios("bus / raw tcp", tcp_r.p50);
  std::printf("lost bus messages (seq gaps): %llu\n", static_cast<unsigned long long>(ipc_r.lost + tcp_r.lost));
  if (dds.ran) {
    std::printf("peer: Cyclone DDS ddsperf ping/pong, 5 kHz, 100 B: round trip p50 %.2f us, p99 %.2f us (medians of its per-second reports); %llu of %llu pings answered\n",
                dds.p50_us, dds.p99_us, static_cast<unsigned long long>(dds.round_trips), static_cast<unsigned long long>(dds.expected));
  } else {
    std::printf("peer: ddsperf not installed (Debian cyclonedds-tools): no DDS arm\n");
  }
  std::printf("machine: %u cores, steal %.2f %% during the run, load %s at the start; %s\n", machine.cores, steal, machine.load_start.c_str(), machine.profile.c_str());
  if (a.has("json")) {
    Json j;
    j.begin_object().field("seconds_per_case", seconds).field("jitter_ticks", static_cast<long long>(jitter_ticks)).field("fifo_priority", fifo);
    j.field("distributed_rtt_p50_ratio", ipc_r.p50.overall).field("distributed_rtt_p50_ratio_tcp", tcp_r.p50.overall);
    j.field("colocated_jitter_p99_ratio", jitter_p99_ratio).field("colocated_jitter_p50_ratio", timer.p50.overall);
    j.field("colocated_latency_p99_us", us(timer.arm[1].latency.percentile(99.0))).field("colocated_44khz_missed_fraction", missed44);
    j.field("colocated_44khz_latency_p99_us", us(r44.loop.latency_p99_ns)).field("lost_messages", static_cast<long long>(ipc_r.lost + tcp_r.lost));
    json_ratios(j, "rtt_ratio_ipc", ipc_r.p50);
    json_ratios(j, "rtt_ratio_tcp", tcp_r.p50);
    json_ratios(j, "jitter_ratio", timer.p50);
    json_timer_arm(j, "timer_bare_5khz", timer.arm[0]);
    json_timer_arm(j, "timer_colocated_5khz", timer.arm[1]);
    json_trip(j, "rtt_bus_ipc", ipc_r.arm[0]);
    json_trip(j, "rtt_raw_ipc", ipc_r.arm[1]);
    json_trip(j, "rtt_bus_tcp", tcp_r.arm[0]);
    json_trip(j, "rtt_raw_tcp", tcp_r.arm[1]);
    j.key("ddsperf").begin_object().field("ran", dds.ran).field("p50_us", dds.p50_us).field("p99_us", dds.p99_us);
    j.field("round_trips", static_cast<long long>(dds.round_trips)).field("expected", static_cast<long long>(dds.expected)).end_object();
    j.key("machine").begin_object().field("cores", static_cast<long long>(machine.cores)).field("steal_pct", steal).field("load_start", machine.load_start);
    j.field("cpu_latency_held", machine.latency_held).field("loop_cpus", rt::cpu_list(machine.loop_cpus)).field("fifo", machine.fifo);
    j.field("profile", machine.profile).end_object();
    j.end_object();
    std::ofstream(a.get("json")) << j.str() << "\n";
  }
  return 0;
}

}  // namespace enact::cli
