// enact bench loop, the report: the machine's state, the figures printed, and the JSON file.
#include <algorithm>
#include <cstdio>
#include <fstream>

#include "core/rt/profile.h"
#include "nodes/enact-bench/bench_loop.h"
#include "nodes/enact/json.h"

namespace enact::cli::loop {

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5)];
}

void Ratios::add_block(rt::LatencyHistogram& num, rt::LatencyHistogram& den) {
  if (num.count() > 0 && den.count() > 0) blocks.push_back(ratio(num.percentile(50.0), den.percentile(50.0)));
  num.reset();
  den.reset();
}

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

double Machine::steal_pct() const {
  const CpuTimes end = cpu_times();
  return 100.0 * static_cast<double>(end.steal - start.steal) / static_cast<double>(std::max<std::uint64_t>(1, end.total - start.total));
}

namespace {

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

void report(const LoopResults& r, const std::string& json_path) {
  const TimerResult& timer = r.timer;
  const Machine& machine = r.machine;
  const RttResult &ipc_r = r.rtt.ipc, &tcp_r = r.rtt.tcp;
  const double jitter_p99_ratio = ratio(timer.arm[1].sleep_late.percentile(99.0), timer.arm[0].sleep_late.percentile(99.0));
  const double missed44 = static_cast<double>(r.r44.missed) / static_cast<double>(std::max<std::uint64_t>(1, r.r44.deadlines));
  std::printf("timer at 5 kHz, bare thread and co-located tick in alternating blocks (us)\n");
  print_timer_arm("bare", timer.arm[0], timer.spin_ns);
  print_timer_arm("co-located", timer.arm[1], timer.spin_ns);
  print_ratios("co-located / bare sleep lateness", timer.p50);
  std::printf("  jitter p99 ratio %.2f; co-located sample-to-force p50 %.2f, p99 %.2f us\n", jitter_p99_ratio, us(timer.arm[1].latency.percentile(50.0)),
              us(timer.arm[1].latency.percentile(99.0)));
  std::printf("co-located at 44 kHz: %llu of %llu deadlines missed (%.3f %%), sample-to-force p99 %.2f us; the loop %s\n",
              static_cast<unsigned long long>(r.r44.missed), static_cast<unsigned long long>(r.r44.deadlines), 100.0 * missed44,
              us(r.r44.loop.latency_p99_ns), r.r44.how.c_str());
  const double link_p50_us = us(ipc_r.arm[kLink].rtt().percentile(50.0));
  const double dds_ratio = r.dds.ran && r.dds.p50_us > 0.0 ? link_p50_us / r.dds.p50_us : 0.0;
  std::printf("round trip ffd -> sim (second process) -> ffd at 5 kHz, the arms tick by tick (us)\n");
  print_trip("link", ipc_r.arm[kLink]);
  print_trip("pipe floor", ipc_r.arm[kPipe]);
  print_ratios("local link / pipe floor", ipc_r.floor);
  print_trip("bus ipc", ipc_r.arm[kBus]);
  print_trip("raw ipc", ipc_r.arm[kRaw]);
  print_ratios("bus / raw ipc", ipc_r.p50);
  print_trip("bus tcp", tcp_r.arm[kBus]);
  print_trip("raw tcp", tcp_r.arm[kRaw]);
  print_ratios("bus / raw tcp", tcp_r.p50);
  std::printf("lost bus messages (seq gaps): %llu\n", static_cast<unsigned long long>(ipc_r.lost + tcp_r.lost));
  if (r.dds.ran) {
    std::printf("peer: Cyclone DDS ddsperf ping/pong, 5 kHz, 100 B: round trip p50 %.2f us, p99 %.2f us (medians of its per-second reports); %llu of %llu pings answered\n",
                r.dds.p50_us, r.dds.p99_us, static_cast<unsigned long long>(r.dds.round_trips), static_cast<unsigned long long>(r.dds.expected));
    std::printf("  local link / ddsperf p50 ratio %.2f\n", dds_ratio);
  } else {
    std::printf("peer: ddsperf not installed (Debian cyclonedds-tools): no DDS arm\n");
  }
  std::printf("machine: %u cores, steal %.2f %% during the run, load %s at the start; %s\n", machine.cores, r.steal_pct, machine.load_start.c_str(), machine.profile.c_str());
  std::printf("%s", rt::describe(machine.probe).c_str());
  if (!json_path.empty()) {
    Json j;
    j.begin_object().field("seconds_per_case", r.seconds).field("jitter_ticks", static_cast<long long>(r.jitter_ticks)).field("fifo_priority", r.fifo_priority);
    j.field("distributed_rtt_p50_ratio", ipc_r.p50.overall).field("distributed_rtt_p50_ratio_tcp", tcp_r.p50.overall);
    j.field("floor_rtt_p50_ratio", ipc_r.floor.overall).field("ddsperf_rtt_p50_ratio", dds_ratio);
    j.field("colocated_jitter_p99_ratio", jitter_p99_ratio).field("colocated_jitter_p50_ratio", timer.p50.overall);
    j.field("colocated_latency_p99_us", us(timer.arm[1].latency.percentile(99.0))).field("colocated_44khz_missed_fraction", missed44);
    j.field("colocated_44khz_latency_p99_us", us(r.r44.loop.latency_p99_ns)).field("lost_messages", static_cast<long long>(ipc_r.lost + tcp_r.lost));
    json_ratios(j, "rtt_ratio_ipc", ipc_r.p50);
    json_ratios(j, "rtt_ratio_floor", ipc_r.floor);
    json_ratios(j, "rtt_ratio_tcp", tcp_r.p50);
    json_ratios(j, "jitter_ratio", timer.p50);
    json_timer_arm(j, "timer_bare_5khz", timer.arm[0]);
    json_timer_arm(j, "timer_colocated_5khz", timer.arm[1]);
    json_trip(j, "rtt_link", ipc_r.arm[kLink]);
    json_trip(j, "rtt_pipe", ipc_r.arm[kPipe]);
    json_trip(j, "rtt_bus_ipc", ipc_r.arm[kBus]);
    json_trip(j, "rtt_raw_ipc", ipc_r.arm[kRaw]);
    json_trip(j, "rtt_bus_tcp", tcp_r.arm[kBus]);
    json_trip(j, "rtt_raw_tcp", tcp_r.arm[kRaw]);
    j.key("ddsperf").begin_object().field("ran", r.dds.ran).field("p50_us", r.dds.p50_us).field("p99_us", r.dds.p99_us);
    j.field("round_trips", static_cast<long long>(r.dds.round_trips)).field("expected", static_cast<long long>(r.dds.expected)).end_object();
    j.key("machine").begin_object().field("cores", static_cast<long long>(machine.cores)).field("steal_pct", r.steal_pct).field("load_start", machine.load_start);
    j.field("cpu_latency_held", machine.latency_held).field("loop_cpus", rt::cpu_list(machine.loop_cpus)).field("fifo", machine.fifo);
    j.field("profile", machine.profile);
    j.field("probe_sleep_late_p50_us", us(machine.probe.sleep_late.p50_ns)).field("probe_sleep_late_p99_us", us(machine.probe.sleep_late.p99_ns));
    j.field("probe_sleep_late_fifo_p99_us", us(machine.probe.sleep_late_fifo.p99_ns));
    j.field("probe_pipe_same_cpu_p50_us", us(machine.probe.pipe_same_cpu.p50_ns)).field("probe_pipe_cross_cpu_p50_us", us(machine.probe.pipe_cross_cpu.p50_ns));
    j.end_object();
    j.end_object();
    std::ofstream(json_path) << j.str() << "\n";
  }
}

}  // namespace enact::cli::loop
