// enact-sim: the simulator of a distributed graph. It steps once per DeviceState and
// answers at once with the ForceCommand carrying the sequence number it answers; it also
// publishes the down-sampled tactile frames, the scene (decimated), task events and status.
#include <cstdio>
#include <cstdlib>

#include "core/bus/loop_link.h"
#include "core/bus/typed.h"
#include "core/config/yaml.h"
#include "core/graph/components.h"
#include "core/graph/messages.h"
#include "core/graph/node.h"
#include "core/graph/node_params.h"
#include "core/graph/param_board.h"
#include "core/graph/param_bus.h"
#include "core/graph/task_state.h"
#include "core/graph/topics.h"
#include "core/rt/clock.h"
#include "core/rt/loop_stats.h"
#include "core/sim/reengage.h"

namespace {

using namespace enact;

constexpr const char* kHelp = R"(usage: enact-sim [--name NAME] --param NAME=VALUE...

The simulator of a distributed graph: for every ffd/state it steps the model and answers
on ffd/force (answered_seq = the state's seq); publishes tactile/frame (down-sampled),
sim/scene (scene_rate_hz), task/event, task/state (10 Hz and on change) and node/status
(1 Hz). Parameter changes on
param/set (NAME.model, NAME.stiffness_n_per_m, ...: docs/parameters.md) are applied
between two DeviceStates and answered on param/ack.

parameters (--param NAME=VALUE; live: enact param set NAME.PARAM VALUE while it runs):
)";

// how often parameter requests are looked for while states flow
constexpr std::int64_t kParamPoll_ns = 10'000'000;

// the launcher's respawn count ($ENACT_RESPAWN), 0 for a first start
int respawn_count() {
  const char* n = std::getenv("ENACT_RESPAWN");
  return n ? std::atoi(n) : 0;
}

int run(int argc, char** argv) {
  graph::NodeArgs args = graph::parse_node_args(argc, argv, "sim");
  if (args.help) {
    std::fputs((kHelp + graph::help_lines(*graph::node_table("enact-sim"))).c_str(), stdout);
    return 0;
  }
  graph::apply_rt_profile(args.name);
  graph::Params& p = args.params;
  p.declare(*graph::node_table("enact-sim"));
  p.refuse_unknown();
  sim::Simulator simulator;
  simulator.configure(graph::sim_params(p));
  const std::string ffd_node = p.text("ffd_node");
  const double scene_rate_hz = p.number("scene_rate_hz");
  const int observers = p.integer("observers");
  sim::Reengagement reengage(p.number("reengage_s"));
  const bool local_hop = p.text("loop_transport") != "zeromq";
  if (args.check) return 0;

  graph::install_stop_handlers();
  bus::BytePublisher out(graph::node_endpoint(args.name), {.node = args.name, .send_hwm = 1000});
  bus::Publisher<msgs::ForceCommand> force_pub(out, graph::kForceCommand);
  bus::Publisher<msgs::TactileFrame> frame_pub(out, graph::kTactileFrame);
  bus::Publisher<msgs::SceneState> scene_pub(out, graph::kSceneState);
  bus::Publisher<msgs::TaskEvent> event_pub(out, graph::kTaskEvent);
  bus::Publisher<msgs::NodeStatus> status_pub(out, graph::kNodeStatus);
  bus::ByteSubscriber in;
  bus::Subscriber<msgs::DeviceState> states(in, graph::kDeviceState);
  // the hop from the FFD driver: its same-host link once it listens (tried each time no
  // state came for a while, so again after it restarts), the bus until then and whenever the
  // node feeding the simulator has no link (`enact play` of a recording, a remote driver)
  const std::string ffd_endpoint = graph::node_endpoint(ffd_node);
  const std::string link_path = local_hop ? bus::loop_link_path(graph::graph_dir(), ffd_node) : "";
  bus::LoopLink link;
  force_pub.also_over(&link);
  in.connect(ffd_endpoint);
  char sample[bus::LoopLink::kMaxMessage];
  msgs::DeviceState state;
  std::int64_t next_link_try_ns = 0;  // the link is tried every 100 ms while there is none
  // the next state within timeout_ns: false when none came
  auto next_state = [&](std::int64_t timeout_ns) {
    const std::int64_t deadline = rt::now_ns() + timeout_ns;
    if (local_hop && !link.connected() && rt::now_ns() >= next_link_try_ns) {
      next_link_try_ns = rt::now_ns() + 100'000'000;
      link = bus::LoopLink::connect(link_path, 0);
      // the states come over the link alone now (the bus would deliver each twice)
      if (link.connected()) in.disconnect(ffd_endpoint);
    }
    if (!link.connected()) return states.receive(state, static_cast<int>(timeout_ns / 1'000'000));
    for (long n; (n = link.receive(sample, sizeof sample, deadline)) > 0;) {
      if (states.accept_payload(sample, static_cast<std::size_t>(n), state)) return true;
    }
    if (!link.connected()) in.connect(ffd_endpoint);  // the driver left: back to the bus
    return false;
  };
  graph::ParamBoard board(args.name);
  board.add(p, args.name);
  graph::ParamPort params(simulator, args.name, out, event_pub, &board);
  graph::TaskStateTracker task_state(out);
  graph::announce_topics(out);
  board.start();

  msgs::ForceCommand command;
  msgs::TactileFrame frame;
  msgs::SceneState scene;
  graph::SceneSnapshot snap;
  msgs::TaskEvent event;
  msgs::NodeStatus status;
  rt::LoopStats stats;
  const physics::Proxy& body = simulator.model().proxies[0];
  const std::int64_t scene_period_ns = scene_rate_hz > 0.0 ? static_cast<std::int64_t>(1e9 / scene_rate_hz) : INT64_MAX;
  std::int64_t first_ns = -1, next_scene = 0, next_status = 0, next_params = 0, last_step_ns = 0;
  std::uint64_t steps = 0;
  // observers asked for (a logger recording a replay from its first step) listen first
  graph::wait_for_subscribers(out, graph::kForceCommand, observers, args.name, "observer (logger)");
  // a new simulator: physics and task start over, said now and recorded. The attach point
  // reconnects to its endpoint within its reconnect interval: the first answer waits for it
  // (a second at most; the driver holds the force at zero meanwhile), or the recording and
  // every observer would miss the new stream's start
  const int respawn = respawn_count();
  bool restart_event_due = respawn > 0;
  const std::int64_t restart_ns = rt::now_ns();
  if (restart_event_due) graph::await_subscribers(out, graph::kForceCommand, local_hop ? 1 : 2, restart_ns + 1'000'000'000);
  simulator.activate(0);
  reengage.interrupt();
  graph::report_ready();
  const std::string restart_detail = "simulator restarted (respawn " + std::to_string(respawn) + "): physics and task start over";
  if (restart_event_due) graph::say(args.name, restart_detail);
  auto publish_restart = [&] {
    if (!restart_event_due) return;
    restart_event_due = false;
    event.set_kind(msgs::TaskEvent::TRIAL_START);
    event.set_time_ns(restart_ns);
    event.set_condition(simulator.computer_model().name);
    event.set_detail(restart_detail);
    event_pub.publish(event);
  };
  // parameter changes, between two steps
  auto apply_params = [&] {
    while (const auto change = params.next()) {
      const sim::ParamApplied done = simulator.apply(*change, rt::now_ns());
      params.applied(done);
      task_state.applied(done.kind);
    }
  };
  while (!graph::stop_requested()) {
    task_state.publish_due(rt::now_ns(), simulator.computer_model().name);
    if (!next_state(100'000'000)) {
      apply_params();
      continue;
    }
    const std::int64_t received = rt::now_ns();
    if (first_ns < 0) {
      first_ns = state.header().stamp_ns();
      next_scene = next_status = received;
    }
    // step on this sample and answer it at once; after an interruption (the driver's
    // watchdog or a device error cut the force) from a body re-synchronised with the device
    if (graph::force_path_cut(state.faults())) reengage.interrupt();
    last_step_ns = state.header().stamp_ns() - first_ns;
    const sim::StepOutput& o = simulator.step(last_step_ns, reengage.position(simulator, last_step_ns, graph::get(state.position())));
    graph::fill(command, state.header().seq(), o.force_n, o.fault);
    force_pub.publish(command);
    stats.latency.record(rt::now_ns() - received);
    params.stepped(simulator.steps(), state.header().seq(), state.header().stamp_ns());
    ++steps;
    task::TaskEvent when = o.event;
    when.time_ns += first_ns;  // back on the device's clock
    task_state.step(last_step_ns, o);
    if (o.frame_due) {
      graph::fill(frame, body.rows, body.cols, o.frame);
      frame_pub.publish(frame);
    }
    if (graph::fill(event, when, simulator.computer_model().name)) event_pub.publish(event);
    if (received >= next_scene) {
      next_scene = received + scene_period_ns;
      graph::snapshot(simulator, o.pins, o.force_n, snap);
      graph::fill(scene, snap, simulator.computer_model().name);
      scene_pub.publish(scene);
    }
    if (received >= next_status) {
      next_status = received + 1'000'000'000;
      stats.ticks = steps;
      graph::fill(status, args.name, rt::summarize(stats, simulator.model().rate_hz), simulator.state().faults,
                  physics::to_string(simulator.state().last_fault));
      graph::add_counters(status, out, &in);
      status_pub.publish(status);
    }
    // answered and every output of this step sent: now is between two steps (a change
    // applied earlier would alter this step's tactile frame, which replay would not see)
    if (received >= next_params) {
      next_params = received + kParamPoll_ns;
      apply_params();
      publish_restart();
    }
  }
  simulator.deactivate();
  const task::Metrics m = simulator.metrics();
  graph::say(args.name, std::to_string(steps) + " steps; receive-to-answer " + rt::format(rt::summarize(stats, simulator.model().rate_hz)) +
                            " Task: falls " + std::to_string(m.falls) + ", progress " + std::to_string(m.progress) + (m.completed ? " (completed)" : "") +
                            "; device states lost (seq gaps): " + std::to_string(states.counters().lost) + "; re-synchronised with the device " +
                            std::to_string(reengage.count()) + " times (largest offset " + std::to_string(reengage.largest_offset_m() * 1e3) + " mm).");
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return enact::graph::node_main("enact-sim", run, argc, argv); }
