#include "core/rt/probe.h"

#include <fcntl.h>
#include <pthread.h>
#include <sched.h>
#include <sys/prctl.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>
#include <vector>

#include "core/rt/clock.h"
#include "core/rt/histogram.h"
#include "core/rt/profile.h"
#include "core/rt/scheduler.h"

namespace enact::rt {
namespace {

constexpr int kFormat = 3;           // the cache's format; another one is measured again
constexpr int kProbeFifo = 50;       // the priority the FIFO sleeps are measured at
constexpr int kSameCpuTrips = 2000;  // pipe round trips on one CPU (~14-40 ms)
constexpr int kCrossCpuTrips = 1000;  // and across two (~15-100 ms)

constexpr int kRounds = 5;           // each figure is measured in rounds: the quietest is the machine's
constexpr std::int64_t kSpinRound_ns = 100'000'000;  // a round of the spinning floor: 4,400 deadlines at 44 kHz

Spread spread_of(const LatencyHistogram& h) {
  return {h.percentile(50.0), h.percentile(99.0), h.max(), static_cast<std::int64_t>(h.count())};
}

// `measure` (one round of `n` samples into a histogram) kRounds times: the round with the
// lowest p99 (a burst of load elsewhere is not the machine), counting every sample
template <class Measure>
Spread quietest_round(int n, Measure measure) {
  Spread best;
  std::int64_t total = 0;
  for (int r = 0; r < kRounds; ++r) {
    LatencyHistogram h;
    measure(n, h);
    if (h.count() == 0) return {};
    total += static_cast<std::int64_t>(h.count());
    const Spread s = spread_of(h);
    if (r == 0 || s.p99_ns < best.p99_ns) best = s;
  }
  best.count = total;
  return best;
}

// runs `body` on a thread of its own and waits for it
template <class Body>
void on_thread(Body body) {
  std::thread t(body);
  t.join();
}

// the calling thread on `cpu` alone: false when refused
bool pin_to(int cpu) { return system_calls().pin_thread({cpu}) == 0; }

// `sleeps` absolute sleeps at period_ns: how late each wake-up is (count 0 when FIFO is refused)
void sleep_lateness(std::int64_t period_ns, int sleeps, bool fifo, LatencyHistogram& late) {
  on_thread([&] {
    prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
    if (fifo && system_calls().set_fifo(kProbeFifo) != 0) return;
    std::int64_t deadline = now_ns() + period_ns;
    for (int i = 0; i < sleeps; ++i) {
      sleep_until_ns(deadline);
      const std::int64_t woke = now_ns();
      late.record(woke - deadline);
      deadline = std::max(deadline + period_ns, woke + period_ns / 2);
    }
  });
}

// a byte ping-ponged between two threads through two pipes, `trips` times, the threads on
// cpu_a and cpu_b (nothing recorded when a CPU was refused)
void pipe_round_trip(int cpu_a, int cpu_b, int trips, LatencyHistogram& rtt) {
  int ping[2], pong[2];
  if (pipe2(ping, O_CLOEXEC) != 0) return;
  if (pipe2(pong, O_CLOEXEC) != 0) {
    close(ping[0]);
    close(ping[1]);
    return;
  }
  std::thread echo([&] {
    const bool pinned = pin_to(cpu_b);
    char c = 0;
    while (read(ping[0], &c, 1) == 1) {
      if (!pinned || write(pong[1], &c, 1) != 1) break;
    }
    close(pong[1]);
  });
  on_thread([&] {
    if (!pin_to(cpu_a)) return;
    char c = 'x';
    for (int i = -50; i < trips; ++i) {  // 50 to warm up
      const std::int64_t t0 = now_ns();
      if (write(ping[1], &c, 1) != 1 || read(pong[0], &c, 1) != 1) return;
      if (i >= 0) rtt.record(now_ns() - t0);
    }
  });
  close(ping[1]);
  echo.join();
  close(ping[0]);
  close(pong[0]);
}

void put(std::ostream& out, const char* key, const Spread& s) {
  out << key << " " << s.p50_ns << " " << s.p99_ns << " " << s.max_ns << " " << s.count << "\n";
}

std::string spread_text(const Spread& s) {
  char text[160];
  std::snprintf(text, sizeof text, "p50 %.1f us, p99 %.1f us, max %.1f us (%lld samples)", to_us(s.p50_ns), to_us(s.p99_ns), to_us(s.max_ns),
                static_cast<long long>(s.count));
  return text;
}

}  // namespace

void measure_spin_floor(int cpu, MachineProbe& p) {
  p.spin_missed_44k = -1.0;
  p.spin_longest_late_ns = 0;
  p.spin_deadlines = 0;
  p.spin_cpu = cpu;
  on_thread([&] {
    // normal scheduling at nice 0: on an idle CPU it is all the same, and on a CPU where a
    // running graph's loop spins (at nice -20) the probe takes a sliver, never the loop's time
    if (!pin_to(cpu)) return;
    SchedulerParams params;
    params.rate_hz = kMaxRate_hz;
    params.spin_ns = std::llround(1e9 / kMaxRate_hz) + 1;  // a window longer than the period: never sleeps
    PeriodicScheduler scheduler(params);
    const auto per_round = static_cast<std::uint64_t>(kSpinRound_ns / scheduler.period_ns());
    std::uint64_t missed = 0;
    for (int r = 0; r < kRounds; ++r) {
      scheduler.start(now_ns() + 100'000);
      while (scheduler.ticks() + scheduler.skipped() < per_round) scheduler.wait();
      missed += scheduler.overruns();
      p.spin_deadlines += static_cast<std::int64_t>(scheduler.ticks() + scheduler.skipped());
      p.spin_longest_late_ns = std::max(p.spin_longest_late_ns, scheduler.jitter().max());
    }
    p.spin_missed_44k = static_cast<double>(missed) / static_cast<double>(p.spin_deadlines);
  });
}

MachineProbe probe_machine(std::int64_t period_ns, int sleeps) {
  MachineProbe p;
  p.period_ns = period_ns;
  p.boot_id = first_line("/proc/sys/kernel/random/boot_id");
  p.probed_at_ns = static_cast<std::int64_t>(std::time(nullptr)) * 1'000'000'000;
  const std::vector<int> cpus = system_calls().allowed_cpus();
  p.cpus = static_cast<int>(cpus.size());
  // the whole machine's load (the average counts every CPU's runnable tasks)
  p.load_per_cpu = std::atof(first_line("/proc/loadavg").c_str()) / static_cast<double>(std::max(1L, sysconf(_SC_NPROCESSORS_ONLN)));
  on_thread([&] { p.default_timer_slack_ns = prctl(PR_GET_TIMERSLACK, 0UL, 0UL, 0UL, 0UL); });
  p.rt_runtime_us = std::atol(first_line("/proc/sys/kernel/sched_rt_runtime_us").c_str());
  p.rt_period_us = std::atol(first_line("/proc/sys/kernel/sched_rt_period_us").c_str());
  // the CPU latency request, held while measuring, as the loop holds it
  int latency_fd = -1;
  const ProfileSystem sys = system_calls();
  p.cpu_latency_held = sys.hold_cpu_latency(latency_fd) == 0;
  const int per_round = std::max(1, sleeps / kRounds);
  p.sleep_late = quietest_round(per_round, [&](int n, LatencyHistogram& h) { sleep_lateness(period_ns, n, false, h); });
  p.sleep_late_fifo = quietest_round(per_round, [&](int n, LatencyHistogram& h) { sleep_lateness(period_ns, n, true, h); });
  p.fifo_permitted = p.sleep_late_fifo.count > 0;
  if (!cpus.empty()) {
    p.pipe_same_cpu = quietest_round(kSameCpuTrips / kRounds, [&](int n, LatencyHistogram& h) { pipe_round_trip(cpus.back(), cpus.back(), n, h); });
  }
  if (cpus.size() >= 2) {
    p.pipe_cross_cpu = quietest_round(kCrossCpuTrips / kRounds, [&](int n, LatencyHistogram& h) { pipe_round_trip(cpus.back(), cpus.front(), n, h); });
  }
  if (!cpus.empty()) measure_spin_floor(cpus.back(), p);
  if (p.cpu_latency_held) sys.release_cpu_latency(latency_fd);
  return p;
}

std::string cache_path() {
  const char* xdg = std::getenv("XDG_CACHE_HOME");
  const char* home = std::getenv("HOME");
  if (xdg && *xdg) return std::string(xdg) + "/enact/machine-probe";
  if (home && *home) return std::string(home) + "/.cache/enact/machine-probe";
  return "/tmp/enact-" + std::to_string(getuid()) + "/machine-probe";
}

MachineProbe cached_probe(bool fresh) {
  const std::string path = cache_path();
  const std::string boot = first_line("/proc/sys/kernel/random/boot_id");
  if (!fresh) {
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    // (a probe made by a process confined to fewer CPUs than this one may use is made again)
    const auto cached = from_text(text.str());
    const bool current = cached && cached->boot_id == boot && cached->cpus >= static_cast<int>(system_calls().allowed_cpus().size());
    const std::int64_t age_ns = current ? static_cast<std::int64_t>(std::time(nullptr)) * 1'000'000'000 - cached->probed_at_ns : 0;
    if (current && (cached->load_per_cpu <= kBusyLoadPerCpu || age_ns < kBusyProbeLife_ns)) return *cached;
  }
  const MachineProbe p = probe_machine();
  std::error_code ec;
  std::filesystem::create_directories(std::filesystem::path(path).parent_path(), ec);
  // written whole, then renamed: a reader never sees half a file
  const std::string tmp = path + "." + std::to_string(getpid());
  {
    std::ofstream out(tmp);
    out << to_text(p);
  }
  std::filesystem::rename(tmp, path, ec);
  if (ec) std::filesystem::remove(tmp, ec);
  return p;
}

std::string to_text(const MachineProbe& p) {
  std::ostringstream out;
  out << "enact_probe " << kFormat << "\n";
  out << "boot_id " << p.boot_id << "\n";
  out << "probed_at_ns " << p.probed_at_ns << "\n";
  out << "period_ns " << p.period_ns << "\n";
  out << "cpus " << p.cpus << "\n";
  put(out, "sleep_late", p.sleep_late);
  put(out, "sleep_late_fifo", p.sleep_late_fifo);
  out << "fifo_permitted " << p.fifo_permitted << "\n";
  out << "default_timer_slack_ns " << p.default_timer_slack_ns << "\n";
  put(out, "pipe_same_cpu", p.pipe_same_cpu);
  put(out, "pipe_cross_cpu", p.pipe_cross_cpu);
  out << "rt_throttling_us " << p.rt_runtime_us << " " << p.rt_period_us << "\n";
  out << "cpu_latency_held " << p.cpu_latency_held << "\n";
  out << "load_per_cpu " << p.load_per_cpu << "\n";
  out << "spin_floor_44k " << p.spin_missed_44k << " " << p.spin_longest_late_ns << " " << p.spin_deadlines << " " << p.spin_cpu << "\n";
  return out.str();
}

std::optional<MachineProbe> from_text(const std::string& text) {
  std::map<std::string, std::string> rows;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    const std::size_t space = line.find(' ');
    if (space != std::string::npos) rows[line.substr(0, space)] = line.substr(space + 1);
  }
  if (rows["enact_probe"] != std::to_string(kFormat)) return std::nullopt;
  MachineProbe p;
  bool ok = true;
  auto words = [&](const char* key) {
    const auto it = rows.find(key);
    ok = ok && it != rows.end();
    return std::istringstream(ok ? it->second : "");
  };
  auto spread = [&](const char* key, Spread& s) {
    auto w = words(key);
    ok = ok && static_cast<bool>(w >> s.p50_ns >> s.p99_ns >> s.max_ns >> s.count);
  };
  auto one = [&](const char* key, auto& value) {
    auto w = words(key);
    ok = ok && static_cast<bool>(w >> value);
  };
  one("boot_id", p.boot_id);
  one("probed_at_ns", p.probed_at_ns);
  one("period_ns", p.period_ns);
  one("cpus", p.cpus);
  spread("sleep_late", p.sleep_late);
  spread("sleep_late_fifo", p.sleep_late_fifo);
  one("fifo_permitted", p.fifo_permitted);
  one("default_timer_slack_ns", p.default_timer_slack_ns);
  spread("pipe_same_cpu", p.pipe_same_cpu);
  spread("pipe_cross_cpu", p.pipe_cross_cpu);
  {
    auto w = words("rt_throttling_us");
    ok = ok && static_cast<bool>(w >> p.rt_runtime_us >> p.rt_period_us);
  }
  one("cpu_latency_held", p.cpu_latency_held);
  one("load_per_cpu", p.load_per_cpu);
  {
    auto w = words("spin_floor_44k");
    ok = ok && static_cast<bool>(w >> p.spin_missed_44k >> p.spin_longest_late_ns >> p.spin_deadlines >> p.spin_cpu);
  }
  if (!ok) return std::nullopt;
  return p;
}

std::string spin_floor_text(const MachineProbe& p) {
  if (p.spin_missed_44k < 0.0) return "a spinning thread's floor: not measured (no CPU could be pinned)";
  char text[256];
  std::snprintf(text, sizeof text,
                "a thread spinning to 44 kHz deadlines (22.7 us apart) on CPU %d, no work, misses %.3f %% of them by itself, the latest %.1f us late "
                "(%lld deadlines): the floor of any spinning loop here",
                p.spin_cpu, 100.0 * p.spin_missed_44k, to_us(p.spin_longest_late_ns), static_cast<long long>(p.spin_deadlines));
  return text;
}

WaitPlan plan_wait(const MachineProbe& probe, std::int64_t period_ns, bool fifo, bool must_sleep, bool own_cpu) {
  fifo = fifo && probe.fifo_permitted;
  const Spread& late = fifo ? probe.sleep_late_fifo : probe.sleep_late;
  const std::int64_t window = late.p99_ns + late.p99_ns / 4 + 5'000;
  char why[256];
  // a period shorter than twice the lateness: a sleep would miss the deadline it sleeps for.
  // Spun whole under normal scheduling (a FIFO thread that never sleeps is throttled)
  if (!must_sleep && own_cpu && period_ns < 2 * late.p99_ns) {
    std::snprintf(why, sizeof why, "spins the whole %.1f us period on a CPU of its own, normal scheduling: this machine wakes a sleeping thread %.1f us late (p99)",
                  to_us(period_ns), to_us(late.p99_ns));
    return {true, period_ns, false, why, probe.spin_missed_44k};
  }
  // a FIFO loop, or one whose CPU's other thread must run, sleeps every tick
  const std::int64_t spin = fifo || must_sleep ? std::min(window, period_ns / 2) : std::min(window, period_ns);
  std::snprintf(why, sizeof why, "sleeps to %.1f us before each deadline, then spins%s: this machine wakes a sleeping thread %.1f us late (p99)%s", to_us(spin),
                fifo ? " (SCHED_FIFO)" : "", to_us(late.p99_ns), spin < window ? ", more than half the period: some ticks will be late" : "");
  return {false, spin, fifo, why};
}

WaitPlan loop_wait(double spin_us, std::int64_t period_ns, bool fifo, bool must_sleep, bool own_cpu) {
  if (spin_us < 0.0) return plan_wait(cached_probe(), period_ns, fifo, must_sleep, own_cpu);
  const auto spin = static_cast<std::int64_t>(spin_us * 1e3);
  char why[160];
  std::snprintf(why, sizeof why, "sleeps to %.1f us before each deadline, then spins (spin_us, set by hand)",
                to_us(fifo || must_sleep ? std::min(spin, period_ns / 2) : spin));
  return {false, spin, fifo, why};
}

double sleeping_rate_limit_hz(const MachineProbe& probe, bool fifo, std::int64_t work_ns) {
  const Spread& late = fifo && probe.fifo_permitted ? probe.sleep_late_fifo : probe.sleep_late;
  const double period_ns = static_cast<double>(2 * (late.p99_ns + late.p99_ns / 4 + 5'000) + work_ns);
  return std::min(44'000.0, 1e9 / period_ns);
}

std::string describe(const MachineProbe& p) {
  std::ostringstream out;
  out << "machine probe (" << p.cpus << " CPUs; cached per boot in " << cache_path() << "):\n";
  out << "  sleep to a deadline every " << to_us(p.period_ns) << " us, normal scheduling: late " << spread_text(p.sleep_late) << "\n";
  out << "  the same under SCHED_FIFO: " << (p.fifo_permitted ? "late " + spread_text(p.sleep_late_fifo) : std::string("refused (no privilege)")) << "\n";
  out << "  pipe round trip between two threads on one CPU: " << spread_text(p.pipe_same_cpu) << "\n";
  out << "  the same across two CPUs: " << (p.pipe_cross_cpu.count ? spread_text(p.pipe_cross_cpu) : std::string("one CPU only")) << "\n";
  out << "  default timer slack " << p.default_timer_slack_ns << " ns (loops set 1 ns); real-time throttling "
      << (p.rt_runtime_us < 0 ? std::string("off") : std::to_string(p.rt_runtime_us) + " of every " + std::to_string(p.rt_period_us) + " us")
      << "; CPU latency request " << (p.cpu_latency_held ? "held while measuring" : "refused") << "\n";
  out << "  " << spin_floor_text(p) << "\n";
  return out.str();
}

std::string first_line(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  return line;
}

}  // namespace enact::rt
