#include "core/node/sim.h"

#include <climits>
#include <cstdio>
#include <cstdlib>

#include "core/bus/loop_link.h"
#include "core/bus/typed.h"
#include "core/node/components.h"
#include "core/params/device_config.h"
#include "core/params/node_params.h"
#include "core/params/param_binding.h"
#include "core/graph/messages.h"
#include "core/graph/graph_dir.h"
#include "core/graph/process.h"
#include "core/graph/sockets.h"
#include "core/graph/stop.h"
#include "core/params/param_bus.h"
#include "core/graph/task_state.h"
#include "core/graph/topics.h"
#include "core/config/env.h"
#include "core/node/sim_topics.h"
#include "core/rt/clock.h"
#include "core/rt/loop_stats.h"

namespace enact::node {

const NodeKind kSim{.executable = "enact-sim", .default_name = "sim", .help = R"(usage: enact-sim [--name NAME] --param NAME=VALUE...

The simulator of a distributed graph: for every ffd/state it steps the model and answers
on ffd/force (answered_seq = the state's seq); publishes tactile/frame (down-sampled),
sim/scene (scene_rate_hz), task/event, task/state (10 Hz and on change) and node/status
(1 Hz). Parameter changes on
param/set (NAME.model, NAME.stiffness_n_per_m, ...: docs/parameters.md) are applied
between two DeviceStates and answered on param/ack.

parameters (--param NAME=VALUE; live: enact param set NAME.PARAM VALUE while it runs):
)", .loop = true};

namespace {

// how often parameter requests are looked for while states flow
constexpr std::int64_t kParamPoll_ns = 10'000'000;

// the launcher's respawn count ($ENACT_RESPAWN), 0 for a first start
int respawn_count() {
  const char* n = std::getenv(env::kRespawn);
  return n ? std::atoi(n) : 0;
}

}  // namespace

struct Sim::Io : SimTopics {
  explicit Io(Sim& s)
      : SimTopics(s.host_.out()),
        out(s.host_.out()),
        states(in, graph::kDeviceState),
        ffd_endpoint(graph::node_endpoint(s.config_.ffd_node)),
        link_path(s.local_hop_ ? bus::loop_link_path(graph::graph_dir(), s.config_.ffd_node) : ""),
        params(s.simulator_, s.host_.name(), out, event_pub, &s.host_.board()),
        task_state(out) {
    force_pub.also_over(&link);
  }
  bus::BytePublisher& out;
  bus::ByteSubscriber in;
  bus::Subscriber<msgs::DeviceState> states;
  // the hop from the FFD driver: its same-host link once it listens (tried each time no
  // state came for a while, so again after it restarts), the bus until then and whenever the
  // node feeding the simulator has no link (`enact play` of a recording, a remote driver)
  const std::string ffd_endpoint, link_path;
  bus::LoopLink link;
  bool on_bus = true;  // subscribed to the driver's states on the bus too
  char sample[bus::LoopLink::kMaxMessage];
  graph::ParamPort params;
  graph::TaskStateTracker task_state;
  msgs::ForceCommand command;
  msgs::TactileFrame frame;
  msgs::SceneState scene;
  graph::SceneSnapshot snap;
  msgs::TaskEvent event;
  msgs::NodeStatus status;
  sim::Keyframe keyframe;  // sized by a first save before the loop
  msgs::SimKeyframe keyframe_msg;
  rt::LoopStats stats;
};

Sim::Sim(Host& host)
    : host_(host),
      config_(graph::sim_node_bindings().read(host.params())),
      local_hop_(config_.loop_transport != "zeromq"),
      simulated_(graph::graph_clock() == rt::GraphClock::simulated) {
  simulator_.configure(graph::sim_params(host.params()));
}

Sim::~Sim() = default;

// the next state within timeout_ns, into state_: false when none came
bool Sim::next_state(std::int64_t timeout_ns) {
  Io& io = *io_;
  const std::int64_t deadline = rt::now_ns() + timeout_ns;
  if (local_hop_ && !io.link.connected() && rt::now_ns() >= next_link_try_ns_) {
    next_link_try_ns_ = rt::now_ns() + 100'000'000;  // tried every 100 ms while there is none
    io.link = bus::LoopLink::connect(io.link_path, 0);
  }
  if (!io.link.connected()) return io.states.receive(state_, static_cast<int>(timeout_ns / 1'000'000));
  for (long n; (n = io.link.receive(io.sample, sizeof io.sample, deadline)) > 0;) {
    if (!io.states.accept_payload(io.sample, static_cast<std::size_t>(n), state_)) continue;
    // the states come over the link alone now (the bus would deliver each twice). Left only
    // now: until the driver's loop starts it counts this subscription with its observers, as
    // on the bus hop, so the count it waits for does not change under it. Unsubscribed, not
    // disconnected: the driver stops queueing states for this node at once (a disconnect
    // ends only once this socket is called again, and a full queue would hold a driver that
    // waits for room, in simulated time)
    if (io.on_bus) io.in.unsubscribe(graph::kDeviceState);
    io.on_bus = false;
    return true;
  }
  if (!io.link.connected() && !io.on_bus) {
    // the driver left: back to the bus, less what it queued there before this node left it
    // (states answered over the link already)
    while (io.states.receive(state_, 0)) {
    }
    io.in.subscribe(graph::kDeviceState);
    io.on_bus = true;
  }
  return false;
}

// step on state_ and answer it at once; after an interruption (the driver's watchdog or a
// device error cut the force) from a body re-synchronised with the device
void Sim::answer(std::int64_t received_ns) {
  Io& io = *io_;
  if (steps_ == 0) next_scene_ = next_status_ = next_keyframe_ = received_ns;
  const std::int64_t sample_ns = state_.header().stamp_ns();
  const sim::StepOutput& o = simulator_.step_sample(sample_ns, graph::get(state_.position()), graph::force_path_cut(state_.faults()));
  graph::fill(io.command, state_.header().seq(), o.force_n, o.fault);
  io.command.set_tactile_frame_seq(o.frame_due ? io.frame_pub.last_seq() + 1 : 0);  // published just after
  io.command.set_run_over(simulated_ && o.event.kind == task::TaskEventKind::completed);
  io.force_pub.publish(io.command);
  io.stats.latency.record(rt::now_ns() - received_ns);
  io.params.stepped(simulator_.steps(), state_.header().seq(), sample_ns);
  ++steps_;
  io.task_state.step(sample_ns, o);
  publish_outputs(o, received_ns);
}

// what observers see of a step: its frame, task event, the scene and status when due
void Sim::publish_outputs(const sim::StepOutput& o, std::int64_t received_ns) {
  Io& io = *io_;
  const physics::Proxy& body = simulator_.model().proxies[0];
  if (o.frame_due) {
    graph::fill(io.frame, body.rows, body.cols, o.frame);
    // in simulated time the tactile driver takes its time from the frames: the sample's
    if (simulated_) io.frame.mutable_header()->set_stamp_ns(state_.header().stamp_ns());
    io.frame_pub.publish(io.frame);
  }
  if (graph::fill(io.event, o.event, simulator_.computer_model().name)) io.event_pub.publish(io.event);
  if (received_ns >= next_scene_) {
    next_scene_ = received_ns + scene_period_ns_;
    graph::snapshot(simulator_, o.pins, o.force_n, io.snap);
    graph::fill(io.scene, io.snap, simulator_.computer_model().name);
    io.scene_pub.publish(io.scene);
  }
  if (received_ns >= next_keyframe_) {
    // after this step's outputs: replay continues from here with the next state
    next_keyframe_ = received_ns + graph::kKeyframePeriod_ns;
    simulator_.save(io.keyframe);
    graph::fill(io.keyframe_msg, io.keyframe, simulator_.model());
    io.keyframe_pub.publish(io.keyframe_msg);
  }
  if (received_ns >= next_status_) {
    next_status_ = received_ns + 1'000'000'000;
    io.stats.ticks = steps_;
    graph::fill(io.status, host_.name(), rt::summarize(io.stats, simulator_.model().rate_hz), simulator_.state().faults,
                physics::to_string(simulator_.state().last_fault));
    host_.publish_status(io.status, &io.in);
  }
}

// parameter changes (planned on the port's thread), between two steps
void Sim::apply_params() {
  Io& io = *io_;
  while (const auto change = io.params.next()) {
    const sim::ParamApplied done = simulator_.apply(*change, rt::now_ns());
    io.params.applied(done);
    io.task_state.applied(done.kind);
  }
  // a new simulator's trial start, recorded once the attach point listens
  if (!restart_event_due_) return;
  restart_event_due_ = false;
  io.event.set_kind(msgs::TaskEvent::TRIAL_START);
  io.event.set_time_ns(restart_ns_);
  io.event.set_condition(simulator_.computer_model().name);
  io.event.set_detail("simulator restarted (respawn " + std::to_string(respawn_) + "): physics and task start over");
  io.event_pub.publish(io.event);
}

// a new simulator: physics and task start over, said now and recorded. The attach point
// reconnects to its endpoint within its reconnect interval: the first answer waits for it
// (a second at most; the driver holds the force at zero meanwhile), or the recording and
// every observer would miss the new stream's start
void Sim::restart_begins() {
  respawn_ = respawn_count();
  restart_event_due_ = respawn_ > 0;
  restart_ns_ = rt::now_ns();
  if (!restart_event_due_) return;
  graph::await_subscribers(io_->out, graph::kForceCommand, local_hop_ ? 1 : 2, restart_ns_ + 1'000'000'000);
  graph::say(host_.name(), "simulator restarted (respawn " + std::to_string(respawn_) + "): physics and task start over");
}

std::string Sim::summary() const {
  const rt::LoopSummary s = rt::summarize(io_->stats, simulator_.model().rate_hz);
  char latency[160];
  auto us = [](std::int64_t ns) { return static_cast<double>(ns) * 1e-3; };
  std::snprintf(latency, sizeof latency, "receive-to-answer p50 %.2f us, p99 %.2f us, p99.9 %.2f us, max %.2f us", us(s.latency_p50_ns),
                us(s.latency_p99_ns), us(s.latency_p999_ns), us(s.latency_max_ns));
  return std::to_string(steps_) + " steps, device states lost (seq gaps): " + std::to_string(io_->states.counters().lost) + "; " + latency + ".";
}

void Sim::open_ports() {
  io_ = std::make_unique<Io>(*this);
  scene_period_ns_ = static_cast<std::int64_t>(1e9 / config_.scene_rate_hz);
}

void Sim::activate() {
  restart_begins();
  simulator_.activate(0);
  simulator_.save(io_->keyframe);  // sized before the loop
}

void Sim::run() {
  // observers asked for (a logger recording a replay from its first step) listen before the
  // first answer (on the bus hop the driver subscribes too). After "ready": the launcher
  // starts the rest of the graph meanwhile; the driver waits for the simulator on the loop
  // link, so its loop starts after this wait
  const int subscribers = config_.observers > 0 ? config_.observers + (local_hop_ ? 0 : 1) : 0;
  graph::wait_for_subscribers(io_->out, graph::kForceCommand, subscribers, host_.name(), "observer (logger)", false);
  // only now the states: a player (`enact play` of a recording) waits for this subscription,
  // so no state waits in a queue meanwhile to be answered later in a burst, faster than the
  // observers take the answers (red CI: a late logger lost 2,000 forces of a replay)
  io_->in.connect(io_->ffd_endpoint);
  // in simulated time the driver waits for the pins of each frame: the tactile driver (started
  // before it) listens before the first, where there is one
  if (simulated_) graph::await_subscribers(io_->out, graph::kTactileFrame, 1, rt::now_ns() + 2'000'000'000);
  while (!graph::stop_requested()) {
    io_->task_state.publish_due(rt::now_ns(), simulator_.computer_model().name);
    if (!next_state(100'000'000)) {
      apply_params();
      continue;
    }
    const std::int64_t received = rt::now_ns();
    answer(received);
    // answered and every output of this step sent: now is between two steps (a change
    // applied earlier would alter this step's tactile frame, which replay would not see)
    if (received >= next_params_) {
      next_params_ = received + kParamPoll_ns;
      apply_params();
    }
  }
}

int Sim::deactivate() {
  simulator_.deactivate();
  graph::say(host_.name(), summary());
  graph::say(host_.name(), simulator_.summary());
  return 0;
}

}  // namespace enact::node
