// enact bench loop: the real-time loop measured side by side with the machine's floor.
//  - co-located at 5 and 44 kHz (the bridge, simulated devices) next to a bare periodic
//    thread with the same timer settings (cyclictest-like floor);
//  - the distributed ffd -> sim -> ffd round trip over ipc and tcp next to a raw ZeroMQ
//    ping-pong of the same message sizes; messages lost at 5 kHz by sequence number.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
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
#include "core/rt/clock.h"
#include "core/rt/rt_setup.h"
#include "core/rt/scheduler.h"
#include "nodes/enact/commands.h"
#include "nodes/enact/json.h"

namespace enact::cli {
namespace {

constexpr const char* kHelp = R"(usage: enact bench loop [--json FILE] [--seconds S] [--scene PATH] [--fifo PRIORITY]

The real-time loop against the machine's floor, measured side by side in one run:
  bare      a periodic thread that does nothing (the timer's floor, like cyclictest)
  colocated the co-located tick (bridge scene, simulated ERGOS and cells) on the same timer,
            at 5 kHz and 44 kHz: wake-up jitter p50/p99/p99.9/max, overruns, sample-to-force
  rtt       ffd -> sim -> ffd over the bus (DeviceState out, the simulator steps, ForceCommand
            back), two threads, over ipc and tcp, next to a raw ZeroMQ ping-pong of the same
            message sizes; messages lost by sequence number
Each case runs --seconds (default 3). --fifo asks for SCHED_FIFO (reported if refused).
JSON: colocated_latency_p99_us, colocated_jitter_p99_ratio (ours / bare thread, 5 kHz),
distributed_rtt_p50_ratio (ours / raw ZeroMQ, ipc), lost_messages, and every figure.
Targets (not asserted): sample-to-force p99 <= 5 us, 44 kHz sustained, jitter ratio <= 1.1,
round-trip ratio <= 1.3, zero lost messages.
)";

struct Timing {
  std::string name;
  double rate_hz = 0.0;
  rt::LoopSummary loop;
};

// a periodic thread on the same timer settings, doing `work` each tick
template <class Work>
rt::LoopSummary periodic(double rate_hz, double seconds, int fifo, Work work) {
  rt::LoopSummary out;
  std::thread t([&] {
    rt::RtParams p;
    p.fifo_priority = fifo;
    rt::apply_rt_setup(p);
    rt::SchedulerParams s;
    s.rate_hz = rate_hz;
    rt::PeriodicScheduler sched(s);
    rt::LoopStats stats;
    const std::int64_t start = rt::now_ns() + 1'000'000;
    const std::int64_t end = start + static_cast<std::int64_t>(seconds * 1e9);
    sched.start(start);
    for (std::int64_t now = sched.wait(); now < end; now = sched.wait()) stats.latency.record(work(now));
    rt::take_timing(sched, stats);
    out = rt::summarize(stats, rate_hz);
  });
  t.join();
  return out;
}

std::int64_t g_now_for_loop() { return rt::now_ns(); }

rt::LoopSummary colocated(const std::string& scene, double rate_hz, double seconds, int fifo) {
  sim::SimParams p;
  p.scene = scene;
  p.rate_hz = rate_hz;
  sim::Simulator simulator;
  simulator.configure(p);
  devices::SimulatedForceParams f;
  f.start_m = {-0.0074246, -0.0222739, 0.0119};  // resting on the start of the bridge
  devices::SafeForceDevice force(std::make_unique<devices::SimulatedForceDevice>(f));
  force.configure();
  devices::SimulatedTactileDevice tactile;
  tactile.configure();
  graph::ColocatedLoop loop(simulator, force, tactile, &g_now_for_loop);
  loop.activate();
  const auto summary = periodic(rate_hz, seconds, fifo, [&](std::int64_t now) {
    const graph::Observation& o = loop.tick(now);
    return o.force_ns - o.sample.time_ns;
  });
  loop.deactivate();
  return summary;
}

struct Rtt {
  rt::LoopSummary loop;  // latency = round trip
  std::uint64_t lost = 0;
  std::uint64_t unanswered = 0;
};

// ffd thread: publish a DeviceState each tick, wait for its answer; sim thread: step, answer
Rtt bus_rtt(const std::string& scene, const std::string& out_endpoint, const std::string& back_endpoint, double seconds, int fifo) {
  bus::BytePublisher ffd_out(out_endpoint, {.node = "ffd", .send_hwm = 10000});
  bus::BytePublisher sim_out(back_endpoint, {.node = "sim", .send_hwm = 10000});
  bus::ByteSubscriber sim_in, ffd_in;
  bus::Publisher<msgs::DeviceState> states(ffd_out, "ffd/state");
  bus::Publisher<msgs::ForceCommand> forces(sim_out, "ffd/force");
  bus::Subscriber<msgs::DeviceState> sim_states(sim_in, "ffd/state");
  bus::Subscriber<msgs::ForceCommand> ffd_forces(ffd_in, "ffd/force");
  sim_in.connect(ffd_out.endpoint());
  ffd_in.connect(sim_out.endpoint());
  while (!ffd_out.has_subscribers("ffd/state") || !sim_out.has_subscribers("ffd/force")) rt::sleep_until_ns(rt::now_ns() + 1'000'000);
  sim::SimParams p;
  p.scene = scene;
  sim::Simulator simulator;
  simulator.configure(p);
  simulator.activate(0);
  std::atomic<bool> done{false};
  std::thread sim_thread([&] {
    msgs::DeviceState s;
    msgs::ForceCommand c;
    while (!done.load()) {
      if (!sim_states.receive(s, 50)) continue;
      const sim::StepOutput& o = simulator.step(s.header().stamp_ns(), graph::get(s.position()));
      graph::fill(c, s.header().seq(), o.force_n, o.fault);
      forces.publish(c);
    }
  });
  Rtt r;
  msgs::DeviceState s;
  msgs::ForceCommand c;
  graph::set(*s.mutable_position(), {-0.0074246, -0.0222739, 0.0119});
  r.loop = periodic(5000.0, seconds, fifo, [&](std::int64_t now) -> std::int64_t {
    s.mutable_header()->set_stamp_ns(now);
    states.publish(s);
    const std::int64_t give_up = now + 1'000'000;
    while (graph::wait_readable(ffd_in.socket(), give_up)) {
      if (ffd_forces.receive(c, 0) && c.answered_seq() == s.header().seq()) return rt::now_ns() - now;
    }
    ++r.unanswered;
    return rt::now_ns() - now;
  });
  done.store(true);
  sim_thread.join();
  r.lost = sim_states.counters().lost + ffd_forces.counters().lost;
  return r;
}

// the same exchange with raw ZeroMQ PUB/SUB and fixed byte payloads of the same sizes
Rtt raw_rtt(const std::string& out_endpoint, const std::string& back_endpoint, std::size_t out_size, std::size_t back_size, double seconds, int fifo) {
  zmq::context_t& ctx = bus::context();
  zmq::socket_t a_pub(ctx, zmq::socket_type::pub), b_sub(ctx, zmq::socket_type::sub), b_pub(ctx, zmq::socket_type::pub), a_sub(ctx, zmq::socket_type::sub);
  for (zmq::socket_t* s : {&a_pub, &b_sub, &b_pub, &a_sub}) s->set(zmq::sockopt::linger, 0);
  a_pub.bind(out_endpoint);
  b_pub.bind(back_endpoint);
  b_sub.set(zmq::sockopt::subscribe, "");
  a_sub.set(zmq::sockopt::subscribe, "");
  b_sub.connect(a_pub.get(zmq::sockopt::last_endpoint));
  a_sub.connect(b_pub.get(zmq::sockopt::last_endpoint));
  rt::sleep_until_ns(rt::now_ns() + 200'000'000);  // let the connections settle
  std::atomic<bool> done{false};
  std::thread echo([&] {
    std::vector<char> back(back_size, 'b');
    zmq::message_t m;
    while (!done.load()) {
      if (!graph::wait_readable(b_sub, rt::now_ns() + 50'000'000)) continue;
      if (!b_sub.recv(m, zmq::recv_flags::dontwait)) continue;
      b_pub.send(zmq::buffer(back), zmq::send_flags::dontwait);
    }
  });
  std::vector<char> out(out_size, 'a');
  zmq::message_t m;
  Rtt r;
  r.loop = periodic(5000.0, seconds, fifo, [&](std::int64_t now) -> std::int64_t {
    a_pub.send(zmq::buffer(out), zmq::send_flags::dontwait);
    while (graph::wait_readable(a_sub, now + 1'000'000)) {
      if (a_sub.recv(m, zmq::recv_flags::dontwait)) return rt::now_ns() - now;
    }
    ++r.unanswered;
    return rt::now_ns() - now;
  });
  done.store(true);
  echo.join();
  return r;
}

double us(std::int64_t ns) { return static_cast<double>(ns) * 1e-3; }

void print_loop(const char* name, const rt::LoopSummary& l) {
  std::printf("%-24s jitter p50 %7.2f  p99 %7.2f  p99.9 %8.2f  max %8.2f us | latency p50 %7.2f  p99 %7.2f  p99.9 %8.2f  max %8.2f us | overruns %llu\n",
              name, us(l.jitter_p50_ns), us(l.jitter_p99_ns), us(l.jitter_p999_ns), us(l.jitter_max_ns), us(l.latency_p50_ns), us(l.latency_p99_ns),
              us(l.latency_p999_ns), us(l.latency_max_ns), static_cast<unsigned long long>(l.overruns));
}

void json_loop(Json& j, const std::string& key, const rt::LoopSummary& l) {
  j.key(key).begin_object().field("rate_hz", l.rate_hz).field("jitter_p50_us", us(l.jitter_p50_ns)).field("jitter_p99_us", us(l.jitter_p99_ns));
  j.field("jitter_p999_us", us(l.jitter_p999_ns)).field("jitter_max_us", us(l.jitter_max_ns)).field("latency_p50_us", us(l.latency_p50_ns));
  j.field("latency_p99_us", us(l.latency_p99_ns)).field("latency_p999_us", us(l.latency_p999_ns)).field("latency_max_us", us(l.latency_max_ns));
  j.field("overruns", static_cast<long long>(l.overruns)).field("ticks", static_cast<long long>(l.ticks)).end_object();
}

}  // namespace

int bench_loop(int argc, char** argv) {
  const Args a = parse(argc, argv, 3, {"json", "seconds", "scene", "fifo"}, {});
  if (a.flag("help")) {
    std::fputs(kHelp, stdout);
    return 0;
  }
  const double seconds = a.number("seconds", 3.0);
  const int fifo = static_cast<int>(a.number("fifo", 0.0));
  const std::string scene = find_file(a.get("scene", "launch/scenes/bridge.yaml"));
  if (seconds <= 0.0) throw UsageError("--seconds must be > 0");
  std::fprintf(stderr, "enact bench loop: 8 cases of %.1f s each\n", seconds);
  // bare and co-located alternate, three times each: the ratio is of medians (noisy machine)
  auto idle = [](std::int64_t) -> std::int64_t { return 0; };
  auto median_of_three = [](rt::LoopSummary first, rt::LoopSummary second, rt::LoopSummary third) {
    rt::LoopSummary runs[3] = {first, second, third};
    std::sort(runs, runs + 3, [](const auto& x, const auto& y) { return x.jitter_p99_ns < y.jitter_p99_ns; });
    return runs[1];
  };
  rt::LoopSummary b5[3], c5[3];
  for (int i = 0; i < 3; ++i) {
    b5[i] = periodic(5000.0, seconds / 3.0, fifo, idle);
    c5[i] = colocated(scene, 5000.0, seconds / 3.0, fifo);
  }
  const rt::LoopSummary bare5 = median_of_three(b5[0], b5[1], b5[2]);
  const rt::LoopSummary col5 = median_of_three(c5[0], c5[1], c5[2]);
  const rt::LoopSummary bare44 = periodic(44000.0, seconds, fifo, idle);
  const rt::LoopSummary col44 = colocated(scene, 44000.0, seconds, fifo);
  // message sizes of the bus exchange, for the raw ping-pong
  msgs::DeviceState s;
  s.mutable_header()->set_seq(1000000);
  s.mutable_header()->set_stamp_ns(rt::now_ns());
  s.mutable_header()->set_source("ffd");
  graph::set(*s.mutable_position(), {-0.0074246, -0.0222739, 0.0119});
  msgs::ForceCommand c;
  graph::fill(c, 1000000, {0.1, 0.2, 4.8}, false);
  c.mutable_header()->set_seq(1000000);
  c.mutable_header()->set_source("sim");
  const std::size_t out_size = s.ByteSizeLong() + 9 + 22, back_size = c.ByteSizeLong() + 9 + 23;  // + topic and type frames
  const graph::TempFolder folder;  // the ipc sockets, removed at the end
  const std::string& dir = folder.path();
  const Rtt ipc = bus_rtt(scene, "ipc://" + dir + "/bench-a", "ipc://" + dir + "/bench-b", seconds, fifo);
  const Rtt raw_ipc = raw_rtt("ipc://" + dir + "/bench-c", "ipc://" + dir + "/bench-d", out_size, back_size, seconds, fifo);
  const Rtt tcp = bus_rtt(scene, "tcp://127.0.0.1:*", "tcp://127.0.0.1:*", seconds, fifo);
  const Rtt raw_tcp = raw_rtt("tcp://127.0.0.1:*", "tcp://127.0.0.1:*", out_size, back_size, seconds, fifo);

  std::printf("timer and loop (us; 5 kHz rows: the median of 3 alternating runs by jitter p99)\n");
  print_loop("bare thread 5 kHz", bare5);
  print_loop("co-located 5 kHz", col5);
  print_loop("bare thread 44 kHz", bare44);
  print_loop("co-located 44 kHz", col44);
  std::printf("round trip ffd -> sim -> ffd at 5 kHz (latency = round trip, us)\n");
  print_loop("bus ipc", ipc.loop);
  print_loop("raw zmq ipc", raw_ipc.loop);
  print_loop("bus tcp", tcp.loop);
  print_loop("raw zmq tcp", raw_tcp.loop);
  const double jitter_ratio = static_cast<double>(col5.jitter_p99_ns) / static_cast<double>(std::max<std::int64_t>(1, bare5.jitter_p99_ns));
  const double rtt_ratio = static_cast<double>(ipc.loop.latency_p50_ns) / static_cast<double>(std::max<std::int64_t>(1, raw_ipc.loop.latency_p50_ns));
  const double rtt_ratio_tcp = static_cast<double>(tcp.loop.latency_p50_ns) / static_cast<double>(std::max<std::int64_t>(1, raw_tcp.loop.latency_p50_ns));
  const std::uint64_t lost = ipc.lost + tcp.lost;
  std::printf("\nco-located sample-to-force p99 %.2f us (target 5); 44 kHz overruns %llu of %llu ticks; jitter p99 ratio (co-located / bare, 5 kHz) %.2f (target 1.1)\n",
              us(col5.latency_p99_ns), static_cast<unsigned long long>(col44.overruns), static_cast<unsigned long long>(col44.ticks), jitter_ratio);
  std::printf("round-trip p50 ratio (bus / raw ZeroMQ): ipc %.2f, tcp %.2f (target 1.3); lost messages %llu; unanswered within 1 ms: ipc %llu, tcp %llu\n",
              rtt_ratio, rtt_ratio_tcp, static_cast<unsigned long long>(lost), static_cast<unsigned long long>(ipc.unanswered), static_cast<unsigned long long>(tcp.unanswered));
  std::printf("machine: %u cores; SCHED_FIFO %s; %.1f s per case (5 kHz: 3 runs of a third)\n", std::thread::hardware_concurrency(), fifo > 0 ? "requested" : "not requested", seconds);
  if (a.has("json")) {
    Json j;
    j.begin_object().field("seconds_per_case", seconds).field("fifo_priority", fifo);
    j.field("colocated_latency_p99_us", us(col5.latency_p99_ns)).field("colocated_jitter_p99_ratio", jitter_ratio);
    j.field("distributed_rtt_p50_ratio", rtt_ratio).field("distributed_rtt_p50_ratio_tcp", rtt_ratio_tcp).field("lost_messages", static_cast<long long>(lost));
    json_loop(j, "bare_5khz", bare5);
    json_loop(j, "colocated_5khz", col5);
    json_loop(j, "bare_44khz", bare44);
    json_loop(j, "colocated_44khz", col44);
    json_loop(j, "rtt_bus_ipc", ipc.loop);
    json_loop(j, "rtt_raw_ipc", raw_ipc.loop);
    json_loop(j, "rtt_bus_tcp", tcp.loop);
    json_loop(j, "rtt_raw_tcp", raw_tcp.loop);
    j.end_object();
    std::ofstream(a.get("json")) << j.str() << "\n";
  }
  return 0;
}

}  // namespace enact::cli
