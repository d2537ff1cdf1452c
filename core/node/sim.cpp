#include "core/node/sim.h"

#include <array>
#include <climits>
#include <cstdio>
#include <cstdlib>

#include "core/bus/loop_link.h"
#include "core/bus/typed.h"
#include "core/node/components.h"
#include "core/params/device_config.h"
#include "core/params/node_params.h"
#include "core/params/param_table.h"
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
#include "core/node/sim_feed.h"
#include "core/config/yaml.h"
#include "core/rt/rt_section.h"
#include "core/rt/rt_setup.h"
#include "core/rt/spsc_queue.h"
#include "core/rt/wakeup.h"
#include "core/rt/clock.h"
#include "core/rt/loop_stats.h"

namespace enact::node {

namespace {

// the --help text after the simulator's parameters: the stages of the libraries given
std::string stage_help() {
  std::string out;
  for (const graph::ComponentKind& k : graph::component_kinds()) {
    if (k.role == graph::ComponentRole::stage) out += std::string(" plugin ") + k.plugin + ":\n" + graph::help_lines(k.table(), std::string(k.plugin) + ".");
  }
  return out.empty() ? "" : "stage parameters (--param COMPONENT.NAME=VALUE; the plugin libraries given by --library):\n" + out;
}

}  // namespace

const NodeKind kSim{.executable = "enact-sim", .default_name = "sim", .help = R"(usage: enact-sim [--name NAME] [--library=PATH... --component=NAME:PLUGIN...] --param NAME=VALUE...

The simulator of a distributed graph: for every ffd/state it steps the model and answers
on ffd/force (answered_seq = the state's seq), over the driver's same-host link when it has
one; publishes tactile/frame (down-sampled), sim/scene (scene_rate_hz), task/event,
task/state (10 Hz and on change) and node/status (1 Hz) from a thread beside its loop.
Parameter changes on param/set (NAME.model, NAME.stiffness_n_per_m, ...: docs/parameters.md)
are planned on that side, applied between two DeviceStates and answered on param/ack.
Stages of a user's (plugin libraries: --library=PATH, --component=NAME:PLUGIN, their
parameters --param NAME.PARAM=VALUE; docs/components.md) step after the model, in order,
before the answer is sent, as in enact-rt's tick.

parameters (--param NAME=VALUE; live: enact param set NAME.PARAM VALUE while it runs):
)", .loop = true, .plugins = true, .more_help = stage_help};

namespace {

// the feed's round when nothing wakes it sooner
constexpr std::int64_t kFeedRound_ns = 1'000'000;

// the launcher's respawn count ($ENACT_RESPAWN), 0 for a first start
int respawn_count() {
  const char* n = std::getenv(env::kRespawn);
  return n ? std::atoi(n) : 0;
}

}  // namespace

struct Sim::Io {
  // one step of the loop, for the feed: what it made, and the device state it answered
  struct Answered {
    graph::Observation o;
    std::uint64_t state_seq = 0;
  };
  // the loop's status, once a second
  struct LoopStatus {
    rt::LoopSummary loop;
    bus::TopicCounters states;  // ffd/state received (over the link too), lost
    std::uint64_t faults = 0;
    physics::Fault last_fault = physics::Fault::none;
  };

  explicit Io(Sim& s)
      : out(s.host_.out()),
        feed(s.simulator_, s.host_.name(), out, &s.host_.board(), s.simulator_.model().proxies[0].rows, s.simulator_.model().proxies[0].cols,
             s.simulated_),
        states(in, graph::kDeviceState),
        ffd_endpoint(graph::node_endpoint(s.config_.ffd_node)),
        link_path(s.local_hop_ ? bus::loop_link_path(graph::graph_dir(), s.config_.ffd_node) : "") {}
  bus::BytePublisher& out;
  SimFeed feed;  // the simulator's topics, its parameter requests and acks: this thread's
  // the loop thread's
  bus::ByteSubscriber in;
  bus::Subscriber<msgs::DeviceState> states;
  // the hop from the FFD driver: its same-host link once it listens (tried each time no
  // state came for a while, so again after it restarts), the bus until then and whenever the
  // node feeding the simulator has no link (`enact play` of a recording, a remote driver)
  const std::string ffd_endpoint, link_path;
  bus::LoopLink link;
  bool on_bus = true;      // subscribed to the driver's states on the bus too
  bool over_link = false;  // the state in hand came over the link
  char sample[bus::LoopLink::kMaxMessage];
  std::uint8_t answer[bus::LoopLink::kMaxMessage];
  bus::ReusedMessage<msgs::DeviceState> state;  // the state in hand
  msgs::ForceCommand command;
  Answered step;
  Scene scene_taken;  // a snapshot the loop takes
  rt::LoopStats stats;
  // loop -> feed
  rt::SpscQueue<Answered, 16384> steps;
  rt::SpscQueue<Scene, 64> scenes;
  rt::SpscQueue<LoopStatus, 8> statuses;
  KeyframeSlot keyframes;
  std::atomic<std::uint64_t> dropped{0};
  rt::Wakeup wake;  // the feed, at once: an answer on the bus hop, a frame, a task event
  // feed <-> loop: parameter changes planned, and applied
  graph::ParamQueue changes;
  graph::AppliedQueue applied;
  // the feed's
  Answered taken;
  Scene scene;  // a snapshot the feed publishes
  std::array<LoopStatus, 8> statuses_taken;  // a round's, published after its steps
  msgs::NodeStatus status;
};

Sim::Sim(Host& host)
    : host_(host),
      config_(graph::sim_node_bindings().read(host.params())),
      local_hop_(config_.loop_transport != "zeromq"),
      simulated_(graph::graph_clock() == rt::GraphClock::simulated) {
  simulator_.configure(graph::sim_params(host.params()));
  make_stages();
}

// the stages the node was given (--component NAME:PLUGIN, each from a plugin library),
// configured: bad input refused here, with the component named
void Sim::make_stages() {
  const graph::NodeArgs& args = host_.args();
  graph::Params& p = host_.params();
  if (const auto problem = graph::stage_list_problem(kSim.executable, args.components)) throw config::Error(args.name + ": " + problem->text);
  for (const auto& [name, plugin] : args.components) {
    Stage& s = stages_.emplace_back(Stage{name, plugin, p.scoped(name), nullptr});
    s.params.declare(*graph::component_table(plugin));
    try {
      s.stage = make_stage(plugin, s.params);
    } catch (const std::exception& e) {
      throw config::Error(args.name + ": component '" + name + "' (plugin " + plugin + "): " + e.what());
    }
    s.params.refuse_unknown();
    step_.add_stage(*s.stage);
  }
  p.refuse_unknown();
}

Sim::~Sim() {
  if (loop_.joinable()) loop_.join();
}

// the next state before deadline_ns, into io.state: false when none came. One that came over
// the link opens the loop's real-time section (rt/rt_section.h): it is answered from here
bool Sim::next_state(std::int64_t deadline_ns) {
  Io& io = *io_;
  if (local_hop_ && !io.link.connected() && rt::now_ns() >= next_link_try_ns_) {
    next_link_try_ns_ = rt::now_ns() + 100'000'000;  // tried every 100 ms while there is none
    io.link = bus::LoopLink::connect(io.link_path, 0);
  }
  io.over_link = false;
  if (!io.link.connected()) return io.states.receive(io.state.fresh(), static_cast<int>((deadline_ns - rt::now_ns()) / 1'000'000));
  // over the link the wait sets no timer: the stop's descriptor or the driver's end ends it
  const int stop = graph::stop_fd();
  for (long n; (n = io.link.receive(io.sample, sizeof io.sample, stop >= 0 ? bus::LoopLink::kNoDeadline : deadline_ns, stop)) > 0;) {
    rt::enter_rt_section();
    if (!io.states.accept_payload(io.sample, static_cast<std::size_t>(n), io.state.fresh())) {
      rt::leave_rt_section();
      continue;
    }
    // the states come over the link alone now (the bus would deliver each twice). Left only
    // now: until the driver's loop starts it counts this subscription with its observers, as
    // on the bus hop, so the count it waits for does not change under it. Unsubscribed, not
    // disconnected: the driver stops queueing states for this node at once (a disconnect
    // ends only once this socket is called again, and a full queue would hold a driver that
    // waits for room, in simulated time)
    if (io.on_bus) io.in.unsubscribe(graph::kDeviceState);
    io.on_bus = false;
    io.over_link = true;
    return true;
  }
  if (!io.link.connected() && !io.on_bus) {
    // the driver left: back to the bus, less what it queued there before this node left it
    // (states answered over the link already)
    while (io.states.receive(io.state.fresh(), 0)) {
    }
    io.in.subscribe(graph::kDeviceState);
    io.on_bus = true;
  }
  return false;
}

// step on io.state and answer it at once, the parameter changes planned since the last step
// swapped in first; after an interruption (the driver's watchdog or a device error cut the
// force) from a body re-synchronised with the device
void Sim::answer(std::int64_t received_ns) {
  Io& io = *io_;
  graph::Observation& o = io.step.o;
  o.sample.time_ns = io.state->header().stamp_ns();
  o.sample.position_m = graph::get(io.state->position());
  o.sample.velocity_m_per_s = graph::get(io.state->velocity());
  o.sample.buttons = io.state->buttons();
  o.sample.force_n = graph::get(io.state->force());
  o.cut = graph::force_path_cut(io.state->faults());
  step_.step(o.sample.time_ns, o);
  o.force_ns = rt::now_ns();
  io.step.state_seq = io.state->header().seq();
  if (io.over_link) {
    SimFeed::answer(io.command, o, io.step.state_seq, simulated_);
    bus::send_over(io.link, io.command, io.answer);
  }
  io.stats.latency.record(rt::now_ns() - received_ns);
}

// the step to the feed (which publishes the answer on the bus too), and when due the
// scene, a keyframe and the loop's status
void Sim::hand_over(std::int64_t received_ns) {
  Io& io = *io_;
  const graph::Observation& o = io.step.o;
  if (o.seq == 1) next_scene_ = next_status_ = next_keyframe_ = received_ns;
  // the keyframe before its step: the feed publishes it right after the step's messages
  if (received_ns >= next_keyframe_) {
    next_keyframe_ = received_ns + graph::kKeyframePeriod_ns;
    io.keyframes.save(simulator_, o.seq);
  }
  if (!deliver(io.steps, io.step, simulated_)) io.dropped.fetch_add(1, std::memory_order_relaxed);
  if (received_ns >= next_scene_) {
    next_scene_ = received_ns + scene_period_ns_;
    Scene& scene = io.scene_taken;
    scene.tick_ns = o.sample.time_ns;
    graph::snapshot(simulator_, o.step.pins, o.step.force_n, scene.snap);
    deliver(io.scenes, scene, simulated_);
  }
  if (received_ns >= next_status_) {
    next_status_ = received_ns + 1'000'000'000;
    io.stats.ticks = step_.steps();
    const Io::LoopStatus status{rt::summarize(io.stats, simulator_.model().rate_hz), io.states.counters(), simulator_.state().faults,
                            simulator_.state().last_fault};
    deliver(io.statuses, status, simulated_);
  }
  // the driver waits for an answer on the bus; the tactile driver for a frame
  if (!io.over_link || o.frame_seq != 0 || o.step.event.kind != task::TaskEventKind::none) io.wake.notify();
}

// the answering thread: a state, its answer, its record handed over; nothing else
void Sim::loop_main() {
  Io& io = *io_;
  rt::prefault_stack();
  // the simulator from its time 0, then the stages, on this thread before the feed takes a
  // request (planning reads the model the activation resets)
  step_.activate();
  io.keyframes.size(simulator_);
  loop_active_.store(true);
  io.wake.notify();
  while (!graph::stop_requested()) {
    if (!next_state(rt::now_ns() + 100'000'000)) continue;
    const std::int64_t received = rt::now_ns();
    rt::enter_rt_section();  // a state from the bus: from here
    answer(received);
    hand_over(received);
    rt::leave_rt_section();
  }
  step_.deactivate();
  loop_done_.store(true);
  io.wake.notify();
}

// the feed's round: parameter requests to the loop, and everything the loop handed over
// published; the steps it took
std::size_t Sim::drain() {
  Io& io = *io_;
  io.feed.intake(io.changes);
  // the loop's statuses taken before its steps, published after them: each then follows every
  // step the loop handed over before it (as the container's summaries)
  const std::size_t statuses = io.statuses.take(io.statuses_taken);
  std::size_t n = 0;
  for (; io.steps.try_pop(io.taken); ++n) {
    io.feed.take_applied(io.applied);
    io.feed.step(io.taken.o, io.taken.state_seq);
    io.keyframes.after(io.taken.o.seq, [&](const sim::Keyframe& k) { io.feed.keyframe(k, simulator_.model()); });
  }
  io.feed.take_applied(io.applied);
  io.feed.due(rt::now_ns());
  while (io.scenes.try_pop(io.scene)) io.feed.scene(io.scene);
  for (std::size_t k = 0; k < statuses; ++k) {
    const Io::LoopStatus& s = io.statuses_taken[k];
    graph::fill(io.status, host_.name(), s.loop, s.faults, physics::to_string(s.last_fault));
    host_.publish_status(io.status, {{graph::kDeviceState, s.states}});
  }
  return n;
}

// a new simulator: physics and task start over, said now and recorded. The attach point
// reconnects to its endpoint within its reconnect interval: the first answer waits for it
// (a second at most; the driver holds the force at zero meanwhile), or the recording and
// every observer would miss the new stream's start
void Sim::restart_begins() {
  respawn_ = respawn_count();
  restart_ns_ = rt::now_ns();
  if (respawn_ == 0) return;
  graph::await_subscribers(io_->out, graph::kForceCommand, local_hop_ ? 1 : 2, restart_ns_ + 1'000'000'000);
  graph::say(host_.name(), "simulator restarted (respawn " + std::to_string(respawn_) + "): physics and task start over");
}

std::string Sim::summary() const {
  const rt::LoopSummary s = rt::summarize(io_->stats, simulator_.model().rate_hz);
  char latency[160];
  auto us = [](std::int64_t ns) { return static_cast<double>(ns) * 1e-3; };
  std::snprintf(latency, sizeof latency, "receive-to-answer p50 %.2f us, p99 %.2f us, p99.9 %.2f us, max %.2f us", us(s.latency_p50_ns),
                us(s.latency_p99_ns), us(s.latency_p999_ns), us(s.latency_max_ns));
  const std::uint64_t dropped = io_->dropped.load();
  const std::string unpublished = dropped ? "; " + std::to_string(dropped) + " steps not published (the feed's queue was full)" : "";
  return std::to_string(step_.steps()) + " steps, device states lost (seq gaps): " + std::to_string(io_->states.counters().lost) + unpublished + "; " + latency + ".";
}

void Sim::open_ports() {
  for (const Stage& s : stages_) host_.board().add(s.params, s.name, s.name + ".");
  io_ = std::make_unique<Io>(*this);
  scene_period_ns_ = static_cast<std::int64_t>(1e9 / config_.scene_rate_hz);
  // the answer's parts made once, before the loop: it fills them in place
  io_->command.mutable_header()->set_source(host_.name());
  SimFeed::answer(io_->command, io_->step.o, 0, simulated_);
  step_.connect_params(io_->changes, io_->applied);
}

void Sim::activate() {
  restart_begins();
}

void Sim::run() {
  Io& io = *io_;
  // observers asked for (a logger recording a replay from its first step) listen before the
  // first answer (on the bus hop the driver subscribes too). After "ready": the launcher
  // starts the rest of the graph meanwhile; the driver waits for the simulator on the loop
  // link, so its loop starts after this wait
  const int subscribers = config_.observers > 0 ? config_.observers + (local_hop_ ? 0 : 1) : 0;
  graph::wait_for_subscribers(io.out, graph::kForceCommand, subscribers, host_.name(), "observer (logger)", false);
  // only now the states: a player (`enact play` of a recording) waits for this subscription,
  // so no state waits in a queue meanwhile to be answered later in a burst, faster than the
  // observers take the answers (red CI: a late logger lost 2,000 forces of a replay)
  io.in.connect(io.ffd_endpoint);
  // in simulated time the driver waits for the pins of each frame: the tactile driver (started
  // before it) listens before the first, where there is one
  if (simulated_) graph::await_subscribers(io.out, graph::kTactileFrame, 1, rt::now_ns() + 2'000'000'000);
  // the loop thread takes the process's real-time profile; this one then leaves it
  loop_ = std::thread([this] { loop_main(); });
  rt::leave_fifo();
  while (!loop_active_.load() && !loop_done_.load()) io.wake.wait(rt::now_ns() + kFeedRound_ns);
  // a new simulator's trial start, recorded now that the attach point listens
  if (respawn_ > 0) {
    io.feed.say_event(msgs::TaskEvent::TRIAL_START, restart_ns_,
                      "simulator restarted (respawn " + std::to_string(respawn_) + "): physics and task start over");
  }
  while (!loop_done_.load()) {
    const std::int64_t round_end = rt::now_ns() + kFeedRound_ns;
    // in simulated time the loop may wait for this thread: no pause while there is work
    if (drain() == 0 || !simulated_) io.wake.wait(round_end);
  }
}

int Sim::deactivate() {
  if (loop_.joinable()) loop_.join();
  drain();  // what the loop handed over last
  graph::say(host_.name(), summary());
  graph::say(host_.name(), simulator_.summary());
  return 0;
}

}  // namespace enact::node
