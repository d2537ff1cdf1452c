// enact-ffd: the force-feedback device driver of a distributed graph, and its clock master.
// Each tick it reads the device, publishes DeviceState, waits (until just before the next
// tick) for the simulator's ForceCommand answering that sample, and writes the force. The
// safety layer's watchdog ramps the force to zero when answers stop coming.
#include <algorithm>
#include <cstdio>

#include "core/bus/loop_link.h"
#include "core/bus/typed.h"
#include "core/config/yaml.h"
#include "core/devices/hand.h"
#include "core/devices/safety.h"
#include "core/graph/components.h"
#include "core/graph/messages.h"
#include "core/graph/node.h"
#include "core/graph/node_params.h"
#include "core/graph/param_board.h"
#include "core/graph/topics.h"
#include "core/graph/watchdog_log.h"
#include "core/rt/clock.h"
#include "core/rt/loop_stats.h"
#include "core/rt/probe.h"
#include "core/rt/profile.h"
#include "core/rt/round_trip.h"
#include "core/rt/rt_setup.h"
#include "core/rt/scheduler.h"

namespace {

using namespace enact;

constexpr const char* kHelp = R"(usage: enact-ffd [--name NAME] --param NAME=VALUE...

The force-feedback device driver and clock master of a distributed graph: publishes
ffd/state at rate_hz, applies the ffd/force answering each sample, publishes node/status
at 1 Hz (sample-to-force latency percentiles, jitter, drops).

Stops on SIGINT/SIGTERM: zero force first.

parameters (--param NAME=VALUE):
)";

// what the safety layer did, and the force it left the device with
std::string safety_summary(devices::ForceDevice& device) {
  const auto* safe = dynamic_cast<const devices::SafeForceDevice*>(&device);
  if (!safe) return "no safety layer";
  const bool zero = safe->sent_force_n() == math::Vec3{};
  return "force steps held to the profile's limit: " + std::to_string(safe->slew_limited()) + ", re-engagements: " +
         std::to_string(safe->reengagements()) + "; force at exit: " + (zero ? "zeroed before the device was switched off" : "NOT zero");
}

int run(int argc, char** argv) {
  graph::NodeArgs args = graph::parse_node_args(argc, argv, "ffd");
  if (args.help) {
    std::fputs((kHelp + graph::help_lines(*graph::node_table("enact-ffd"))).c_str(), stdout);
    return 0;
  }
  graph::apply_rt_profile(args.name);
  graph::Params& p = args.params;
  p.declare(*graph::node_table("enact-ffd"));
  p.refuse_unknown();
  rt::SchedulerParams sched;
  sched.rate_hz = p.number("rate_hz");
  sched.validate();
  const double spin_us = p.number("spin_us");
  const std::string sim_node = p.text("sim_node");
  const double duration_s = p.number("duration_s");
  const int observers = p.integer("observers");
  rt::RtParams rtp;
  rtp.lock_memory = p.flag("lock_memory");
  rtp.fifo_priority = p.integer("fifo_priority");
  auto device = graph::make_force_device(p);
  const std::string tactile_node = p.text("tactile_node");
  const bool local_hop = p.text("loop_transport") != "zeromq";
  if (args.check) return 0;

  // the bus: publish the samples, receive the answers straight from the simulator
  graph::install_stop_handlers();
  bus::BytePublisher out(graph::node_endpoint(args.name), {.node = args.name, .send_hwm = 1000});
  bus::Publisher<msgs::DeviceState> state_pub(out, graph::kDeviceState);
  bus::Publisher<msgs::NodeStatus> status_pub(out, graph::kNodeStatus);
  graph::announce_topics(out);
  graph::ParamBoard board(args.name);
  board.add(p, args.name);
  board.start();
  bus::ByteSubscriber in;
  bus::Subscriber<msgs::ForceCommand> commands(in, graph::kForceCommand);
  // the hop to the simulator: the same-host link (the bus still carries every state to the
  // observers), or the bus itself
  bus::LoopLink link;
  if (local_hop) {
    link = bus::LoopLink::listen(bus::loop_link_path(graph::graph_dir(), args.name));
    state_pub.also_over(&link);
  } else {
    in.connect(graph::node_endpoint(sim_node));
  }
  char answer[bus::LoopLink::kMaxMessage];
  msgs::ForceCommand command;
  // the next answer from the simulator until deadline_ns: false when none came
  auto next_answer = [&](std::int64_t deadline_ns) {
    if (!local_hop) {
      while (graph::wait_readable(in.socket(), deadline_ns)) {
        if (commands.receive(command, 0)) return true;
      }
      return false;
    }
    for (long n; (n = link.receive(answer, sizeof answer, deadline_ns)) > 0;) {
      if (commands.accept_payload(answer, static_cast<std::size_t>(n), command)) return true;
    }
    return false;
  };
  // a virtual subject's fingertip: the latest pins the tactile driver shows
  devices::HandSource* hand = device->simulated_hand();
  const bool feels_pins = hand && hand->feels_pins();
  bus::ByteSubscriber shown_in;
  shown_in.set_conflate(true);
  bus::Subscriber<msgs::TactileShown> shown(shown_in, graph::kTactileShown);
  if (feels_pins) shown_in.connect(graph::node_endpoint(tactile_node));
  msgs::TactileShown shown_msg;
  float levels[32] = {};
  std::uint64_t pins_felt = 0;
  // wait until the simulator (and the observers asked for) listen: ZeroMQ drops what it
  // sends before that
  if (local_hop) {
    graph::wait_for_loop_peer(link, args.name, sim_node);
    graph::wait_for_subscribers(out, graph::kDeviceState, observers, args.name, "observer");
  } else {
    graph::wait_for_subscribers(out, graph::kDeviceState, 1 + observers, args.name, "subscriber (the simulator, then observers)");
  }
  graph::say(args.name, local_hop ? "loop hop to " + sim_node + ": local (Unix link " + link.path() + ", read by the loop thread)"
                                  : "loop hop to " + sim_node + ": ZeroMQ (loop_transport=zeromq)");

  const rt::RtReport report = rt::apply_rt_setup(rtp);
  graph::say(args.name, report.summary());
  // how to wait, from this machine's probe: the spin window covers its wake-up lateness; a
  // period shorter than twice the lateness is spun whole on the loop's CPU, under normal
  // scheduling (the simulator, woken by each state, still gets the CPU it needs)
  const bool fifo = rt::running_fifo();
  const rt::WaitPlan wait = rt::loop_wait(spin_us, rt::PeriodicScheduler(sched).period_ns(), fifo, false, graph::loop_pinned());
  if (fifo && !wait.fifo) rt::system_calls().set_fifo(0);
  sched.spin_ns = wait.spin_ns;
  sched.sleep_every_tick = !wait.spin_whole_period;
  graph::say(args.name, "the loop " + wait.why);
  rt::PeriodicScheduler scheduler(sched);
  rt::LoopStats stats;
  devices::ForceSample sample;
  msgs::DeviceState state;
  msgs::NodeStatus status;
  // each sample and the answer that carries its seq: unanswered samples, late (stale) answers
  rt::RoundTrip answers;
  graph::WatchdogLog watchdog(args.name, "no force answer: force ramped to zero");
  device->activate();
  const std::int64_t start = rt::now_ns() + 1'000'000;
  const std::int64_t end = duration_s > 0.0 ? start + static_cast<std::int64_t>(duration_s * 1e9) : INT64_MAX;
  std::int64_t next_status = start + 1'000'000'000;
  scheduler.start(start);
  graph::report_ready();
  while (!graph::stop_requested()) {
    const std::int64_t now = scheduler.wait();
    if (now >= end) break;
    if (feels_pins && shown.receive(shown_msg, 0)) {
      const int n = std::min(shown_msg.level_size(), 32);
      for (int i = 0; i < n; ++i) levels[i] = shown_msg.level(i);
      hand->feel_pins(levels, static_cast<int>(shown_msg.rows()), static_cast<int>(shown_msg.cols()));
      ++pins_felt;
    }
    device->read(now, sample);
    watchdog.update(devices::has(sample.faults, devices::DeviceFault::watchdog), now);
    state.mutable_header()->set_stamp_ns(0);
    graph::fill(state, sample);
    if (local_hop && !link.connected()) link.accept_peer();  // a respawned simulator
    state_pub.publish(state);
    answers.sent(state.header().seq(), now);
    // the answer to this sample, until just before the next tick; an answer to an older
    // sample is too late to apply (counted stale)
    const std::int64_t answer_by = scheduler.next_deadline_ns() - scheduler.spin_ns();
    while (next_answer(answer_by)) {
      if (!answers.reply(command.answered_seq(), rt::now_ns())) continue;
      device->write(rt::now_ns(), command.zero() ? math::Vec3{} : graph::get(command.force()));
      stats.latency.record(rt::now_ns() - sample.time_ns);
      break;
    }
    answers.close();
    if (now >= next_status) {
      next_status += 1'000'000'000;
      rt::take_timing(scheduler, stats);
      graph::fill(status, args.name, rt::summarize(stats, sched.rate_hz), answers.unanswered(),
                  answers.unanswered() ? "samples without a force answer in time" : "");
      graph::add_counters(status, out, &in);
      watchdog.fill(status);
      // every deadline: a sample taken and answered in time, or not (a skipped tick is missed)
      graph::fill_verdict(status, sched.rate_hz, answers.requests() + scheduler.skipped(), answers.unanswered() + scheduler.skipped(), watchdog);
      status.mutable_header()->set_stamp_ns(0);
      status_pub.publish(status);
    }
  }
  device->deactivate();  // zero force first
  rt::take_timing(scheduler, stats);
  graph::say(args.name, rt::format(rt::summarize(stats, sched.rate_hz)) + " Samples without an answer in time: " + std::to_string(answers.unanswered()) +
                            " of " + std::to_string(answers.requests()) + ", late answers: " + std::to_string(answers.stale()) +
                            ", lost answers (seq gaps): " + std::to_string(commands.counters().lost) + ".");
  graph::say(args.name, watchdog.summary() + "; " + safety_summary(*device));
  graph::say(args.name, "verdict: " + graph::rate_verdict(sched.rate_hz, answers.requests() + scheduler.skipped(),
                                                          answers.unanswered() + scheduler.skipped(), watchdog));
  if (feels_pins) graph::say(args.name, "the virtual subject felt " + std::to_string(pins_felt) + " pin states from " + tactile_node + " (tactile/shown).");
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return enact::graph::node_main("enact-ffd", run, argc, argv); }
