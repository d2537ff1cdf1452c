#include "core/node/container.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <thread>

#include "core/bus/typed.h"
#include "core/config/env.h"
#include "core/config/yaml.h"
#include "core/devices/hand.h"
#include "core/node/colocated.h"
#include "core/node/components.h"
#include "core/node/sim_feed.h"
#include "core/graph/messages.h"
#include "core/graph/process.h"
#include "core/graph/sockets.h"
#include "core/graph/stop.h"
#include "core/params/node_params.h"
#include "core/params/param_binding.h"
#include "core/params/param_bus.h"
#include "core/params/param_table.h"
#include "core/graph/task_state.h"
#include "core/graph/topics.h"
#include "core/graph/watchdog_log.h"
#include "core/launch/launch_file.h"
#include "core/rt/clock.h"
#include "core/rt/loop_stats.h"
#include "core/rt/probe.h"
#include "core/rt/profile.h"
#include "core/rt/rt_section.h"
#include "core/rt/spsc_queue.h"

namespace enact::node {

namespace {

// the --help text after the container's parameters: each plugin's
std::string plugin_help() {
  std::string out =
      "component parameters (--param COMPONENT.NAME=VALUE, e.g. sim.scene=launch/scenes/bridge.yaml; live:\n"
      "enact param set COMPONENT.NAME VALUE while it runs):\n";
  for (const graph::ComponentKind& k : graph::component_kinds()) {
    out += std::string(" plugin ") + k.plugin + ":\n" + graph::help_lines(k.table(), std::string(k.plugin) + ".");
  }
  return out;
}

// the components the container was given (--component NAME:PLUGIN, in order; none: the
// default sim, ffd and tactile), refused unless they can run: the name of each role's one
// (tactile_device empty: none)
struct ComponentNames {
  std::string model, force_device, tactile_device;
  std::vector<std::pair<std::string, std::string>> others;  // observers and stages: name, plugin
};
ComponentNames component_names(const graph::NodeArgs& args) {
  std::vector<std::pair<std::string, std::string>> list = args.components;
  if (list.empty()) {
    for (const char* plugin : launch::kDefaultComponents) list.emplace_back(plugin, plugin);
  }
  if (const auto problem = graph::component_list_problem(list)) throw config::Error(args.name + ": " + problem->text);
  ComponentNames names;
  for (const auto& [name, plugin] : list) {
    switch (graph::find_component_kind(plugin)->role) {
      case graph::ComponentRole::model: names.model = name; break;
      case graph::ComponentRole::force_device: names.force_device = name; break;
      case graph::ComponentRole::tactile_device: names.tactile_device = name; break;
      case graph::ComponentRole::observer:
      case graph::ComponentRole::stage: names.others.emplace_back(name, plugin); break;
    }
  }
  return names;
}

}  // namespace

const NodeKind kContainer{.executable = "enact-rt", .default_name = "rt", .help = R"(usage: enact-rt [--name NAME] [--library=PATH...] [--component=NAME:PLUGIN...] --param NAME=VALUE...

The co-located real-time container: components sim, ffd and tactile (one of each, any names,
the tactile display optional; no --component: sim:sim, ffd:ffd and tactile:tactile) in one
process and one real-time thread, ticking at rate_hz: read the device, step the model, write
the force, write the pins (down-sampled), in the same tick. Observer components (plugin
logger, plugin foxglove: any number) run beside the loop, each on a thread of its own,
attached to the graph as their nodes are; the loop waits for each logger before its first
tick, and when it ends each logger takes what is on its way before its file is closed. Stages a
user writes (plugin libraries given by --library=PATH: docs/components.md) run in the tick, in
the order listed, between the model's step and the force's write. Without a tactile component the
model's frames are published and written nowhere, and tactile/shown is not published. A non-real-time thread,
fed through lock-free queues, publishes every topic for observers: ffd/state, ffd/force,
tactile/frame and task/event at their rates, task/state at 10 Hz and on change, sim/scene
at scene_rate_hz, tactile/shown at shown_rate_hz, node/status at 1 Hz (at $ENACT_GRAPH_DIR/<name>.pub). Parameter changes on
param/set (SIM.model, SIM.stiffness_n_per_m, ...: docs/parameters.md; SIM is the sim
component's name) are checked on that thread, handed to the real-time thread through a
lock-free queue, applied at the top of a tick, and answered on param/ack.

container parameters (--param NAME=VALUE; rate_hz is the simulator's rate too):
)", .plugins = true, .send_hwm = 10000, .more_help = plugin_help};

struct Container::Io {
  Io(Container& c)
      : out(c.host_.out()),
        rows(c.tactile_ ? c.tactile_->rows() : c.simulator_.model().proxies[0].rows),
        cols(c.tactile_ ? c.tactile_->cols() : c.simulator_.model().proxies[0].cols),
        state_pub(out, graph::kDeviceState),
        shown_pub(out, graph::kTactileShown),
        feed(c.simulator_, c.sim_name_, out, &c.host_.board(), rows, cols, c.clock_ == rt::GraphClock::simulated),
        loop(c.simulator_, c.force_->device(), c.tactile_.get(), c.clock_ == rt::GraphClock::real ? &rt::now_ns : nullptr) {}
  bus::BytePublisher& out;
  const int rows, cols;  // the tactile display's (none: the model's body grid)
  bus::Publisher<msgs::DeviceState> state_pub;
  bus::Publisher<msgs::TactileShown> shown_pub;
  SimFeed feed;  // the simulator's topics, its parameter requests and acks
  graph::ColocatedLoop loop;
  // real-time thread -> publisher thread: every tick, scene snapshots, pin levels, loop stats
  rt::SpscQueue<graph::Observation, 16384> queue;
  rt::SpscQueue<Scene, 64> scenes;
  rt::SpscQueue<PinsShown, 64> shown_queue;
  rt::SpscQueue<rt::LoopSummary, 8> summaries;
  graph::ParamQueue changes;
  graph::AppliedQueue applied;
  KeyframeSlot keyframes;  // the real-time thread's, once a second, for the publisher thread
  std::atomic<int> fifo_in_force{-1};  // the loop thread's FIFO priority, once it has set up
  rt::LoopStats stats;
  std::atomic<std::uint64_t> dropped{0};
  rt::RtReport report;
  // the publisher thread's
  msgs::DeviceState state_msg;
  msgs::TactileShown shown_msg;
  msgs::NodeStatus status_msg;
  // what the hand felt, accumulated by the non-real-time thread
  struct Felt {
    std::uint64_t ticks = 0, frames = 0, dropped = 0, device_faults = 0, sim_faults = 0;
    double force_sum_n = 0.0, force_max_n = 0.0, pins_sum = 0.0;
    std::uint64_t on_top = 0;
    bool completed = false;

    void add(const graph::Observation& o) {
      const double f = math::norm(o.step.force_n);
      ticks += 1;
      force_sum_n += f;
      force_max_n = std::max(force_max_n, f);
      pins_sum += __builtin_popcount(o.step.pins);
      frames += o.step.frame_due;
      on_top += o.step.on_top;
      device_faults += o.sample.faults != 0;
      sim_faults += o.step.fault;
      completed = completed || o.step.event.kind == task::TaskEventKind::completed;
    }
  };
  Felt felt;
  graph::Observation o;
  Scene scene;
  PinsShown levels;
  rt::LoopSummary summary;
  std::array<rt::LoopSummary, 8> summaries_taken;  // a round's, published after its ticks
};

Container::Container(Host& host) : host_(host), observers_(host.name()) {
  const graph::NodeArgs& args = host.args();
  graph::Params& p = host.params();
  const ComponentNames names = component_names(args);
  sim_name_ = names.model;
  ffd_name_ = names.force_device;
  tac_name_ = names.tactile_device;
  sim_p_ = p.scoped(sim_name_);
  ffd_p_ = p.scoped(ffd_name_);
  if (!tac_name_.empty()) tac_p_ = p.scoped(tac_name_);
  for (const auto& [name, plugin] : names.others) members_.push_back({name, plugin, p.scoped(name)});
  p.refuse_unknown();
  config_ = graph::rt_bindings().read(p);
  sched_.rate_hz = config_.loop.rate_hz;
  sched_.validate();
  rtp_.lock_memory = config_.loop.lock_memory;
  rtp_.fifo_priority = config_.loop.fifo_priority;
  if (p.has("cpus")) rtp_.cpus.push_back(p.integer("cpus"));
  // the graph's real-time profile (launch entry realtime:) places the loop thread, not the
  // process: the publisher thread and the bus stay with the observers
  if (const char* profile = std::getenv(env::kRtProfile)) {
    const rt::NodeProfile np = rt::NodeProfile::from_env(profile);
    if (!np.cpus.empty()) rtp_.cpus = np.cpus;
    if (np.fifo_priority > 0) rtp_.fifo_priority = np.fifo_priority;
  }
  clock_ = graph::graph_clock();
  if (clock_ == rt::GraphClock::simulated) {
    // simulated time: the loop never waits, so it needs no CPU or priority of its own (a FIFO
    // thread that never sleeps would starve the publisher thread)
    sched_.simulated = true;
    rtp_.fifo_priority = 0;
    rtp_.cpus.clear();
    wait_why_ = "ticks back to back: the graph's clock is simulated (a tick's time is its index over rate_hz)";
  } else {
    plan_wait(config_.loop.spin_us);
  }
  // components, configured (bad input is refused here, before anything moves)
  sim::SimParams sp = graph::sim_params(sim_p_);
  sp.rate_hz = sched_.rate_hz;
  simulator_.configure(sp);
  force_ = std::make_unique<ForceDriver>(graph::make_force_device(ffd_p_), args.name,
                                         "force path cut (a late tick or a device error): body re-synchronised, force back from zero");
  if (!tac_name_.empty()) tactile_ = graph::make_tactile_device(tac_p_);
  for (Member& m : members_) {
    m.params.declare(*graph::component_table(m.plugin));
    if (graph::find_component_kind(m.plugin)->role == graph::ComponentRole::observer) {
      observers_.add(m.name, m.plugin, m.params);
    } else {
      try {
        stages_.push_back(make_stage(m.plugin, m.params));
      } catch (const std::exception& e) {
        throw config::Error(args.name + ": component '" + m.name + "' (plugin " + m.plugin + "): " + e.what());
      }
    }
    m.params.refuse_unknown();
  }
  sim_p_.refuse_unknown();
  ffd_p_.refuse_unknown();
  tac_p_.refuse_unknown();
  if (!tactile_ && force_->feeling_hand()) {
    throw config::Error(args.name + ": component '" + ffd_name_ + "' drives the device with a virtual subject, who feels the pins, and there is no tactile display\n"
                        "  fix: add {name: tactile, plugin: tactile} to the component list, or give '" + ffd_name_ + "' a scripted hand (" + ffd_name_ +
                        ".hand_path) instead of a virtual subject");
  }
}

Container::~Container() = default;

// how the loop waits in real time, from this machine's probe: a period shorter than twice its
// wake-up lateness is spun whole, on the loop's own CPU under normal scheduling (a FIFO thread
// that never sleeps is throttled by the kernel); otherwise it sleeps and spins the lateness
void Container::plan_wait(double spin_us) {
  const bool own_cpu = !rtp_.cpus.empty() && std::thread::hardware_concurrency() >= 2;
  const rt::WaitPlan wait = rt::loop_wait(spin_us, rt::PeriodicScheduler(sched_).period_ns(), rtp_.fifo_priority > 0, false, own_cpu);
  if (!wait.fifo) rtp_.fifo_priority = 0;
  if (wait.spin_whole_period) rtp_.nice = -20;
  sched_.spin_ns = wait.spin_ns;
  wait_why_ = wait.why;
  spin_floor_ = wait.spin_floor;
}

// into a queue to the publisher thread (in simulated time waiting for room)
template <typename Queue, typename Item>
bool Container::deliver(Queue& queue, const Item& item) {
  return node::deliver(queue, item, clock_ == rt::GraphClock::simulated);
}

// the real-time thread: set up, then tick on absolute deadlines
void Container::rt_main() {
  Io& io = *io_;
  io.report = rt::apply_rt_setup(rtp_);
  io.fifo_in_force.store(rt::fifo_priority_now());
  rt::prefault_stack();
  // under SCHED_FIFO the loop sleeps every tick, or the kernel throttles it (~50 ms a second)
  rt::SchedulerParams tick = sched_;
  tick.sleep_every_tick = io.report.fifo;
  rt::PeriodicScheduler scheduler(tick);
  const std::int64_t start = rt::now_ns() + 1'000'000;
  const std::int64_t scene_every = std::max<std::int64_t>(1, std::llround(sched_.rate_hz / config_.scene_rate_hz));
  const std::int64_t shown_every = std::max<std::int64_t>(1, std::llround(sched_.rate_hz / config_.shown_rate_hz));
  const std::int64_t status_every = std::max<std::int64_t>(1, std::llround(sched_.rate_hz));
  Scene scene{};
  PinsShown levels{};
  io.loop.activate();
  scheduler.start(start);
  const std::int64_t began_ns = rt::now_ns();
  const std::int64_t end = config_.loop.end_ns(start);
  std::int64_t last_ns = start;  // the last tick's time
  for (std::int64_t n = 0; !graph::stop_requested(); ++n) {
    // the tick's time is its deadline, on either clock: the model never reads the wall clock
    const std::int64_t woke = scheduler.wait();
    const std::int64_t tick_ns = scheduler.deadline_ns();
    if (tick_ns >= end) {
      limit_ns_.store(last_ns);
      break;
    }
    last_ns = tick_ns;
    const rt::RtSection section;  // the tick and its hand-over: nothing allocated, nothing read
    const graph::Observation& o = io.loop.tick(tick_ns);
    io.stats.latency.record(o.force_ns - woke);  // from the device read to the force written
    // the keyframe before its tick's observation: the publisher thread sends it right after
    if (n % status_every == 0) io.keyframes.save(simulator_, o.seq);
    if (!deliver(io.queue, o)) io.dropped.fetch_add(1, std::memory_order_relaxed);
    // in simulated time nobody is there after the bridge is completed: the run ends with it
    if (clock_ == rt::GraphClock::simulated && o.step.event.kind == task::TaskEventKind::completed) break;
    if (n % scene_every == 0) {
      scene.tick_ns = tick_ns;
      graph::snapshot(simulator_, o.step.pins, o.step.force_n, scene.snap);
      deliver(io.scenes, scene);
    }
    if (tactile_ && n % shown_every == 0) {
      io.loop.tactile()->show(tick_ns, levels);
      deliver(io.shown_queue, levels);
    }
    if (n % status_every == status_every - 1) {
      rt::take_timing(scheduler, io.stats);
      deliver(io.summaries, rt::summarize(io.stats, sched_.rate_hz));
    }
  }
  io.loop.deactivate();
  run_ns_ = rt::now_ns() - began_ns;
  // the whole run's timing, in the last node/status (a recording's count of missed deadlines)
  rt::take_timing(scheduler, io.stats);
  deliver(io.summaries, rt::summarize(io.stats, sched_.rate_hz));
  rt_done_.store(true);
}

// what the real-time thread applied, before anything it did after: a tick's messages name
// the computer model in force at that tick
void Container::take_applied() { io_->feed.take_applied(io_->applied); }

// one tick (io.o) for observers
void Container::publish_tick() {
  Io& io = *io_;
  const graph::Observation& o = io.o;
  graph::fill(io.state_msg, o.sample);
  io.state_pub.publish(io.state_msg);
  io.feed.step(o, io.state_msg.header().seq());
}

void Container::publish_status() {
  Io& io = *io_;
  graph::fill(io.status_msg, host_.name(), io.summary, io.felt.device_faults + io.felt.sim_faults, "");
  force_->cuts().fill(io.status_msg);
  graph::fill_verdict(io.status_msg, sched_.rate_hz, io.summary.ticks, io.summary.overruns, force_->cuts());
  host_.publish_status(io.status_msg, io.feed.params().subscriber().all_counters());
}

// the publisher thread's round: parameter changes to the real-time thread (never more than
// the queue holds), and every topic for observers; the ticks it took
std::size_t Container::drain() {
  Io& io = *io_;
  std::size_t ticks = 0;
  // the loop's summaries taken before its ticks, published after them: each then follows
  // every tick the loop handed over before it (the last node/status counts the last state;
  // taken after the ticks, a summary that came while they were published went out before the
  // last of them)
  const std::size_t summaries = io.summaries.take(io.summaries_taken);
  // the parameter in force is what the loop runs at (a profile may have set it, FIFO refused)
  if (const int fifo = io.fifo_in_force.exchange(-1); fifo >= 0) host_.board().set(host_.name() + ".fifo_priority", std::to_string(fifo));
  io.feed.intake(io.changes);
  for (; io.queue.try_pop(io.o); ++ticks) {
    take_applied();
    io.felt.add(io.o);
    force_->path_cut(io.o.cut, io.o.cut ? io.o.cut_since_ns : io.o.sample.time_ns);
    publish_tick();
    io.keyframes.after(io.o.seq, [&](const sim::Keyframe& k) { io.feed.keyframe(k, simulator_.model()); });
  }
  io.feed.due(rt::now_ns());
  while (io.scenes.try_pop(io.scene)) {
    take_applied();
    io.feed.scene(io.scene);
  }
  take_applied();
  while (io.shown_queue.try_pop(io.levels)) {
    graph::fill(io.shown_msg, io.rows, io.cols, io.levels.level, io.feed.frame_seq(), io.levels.moves ? &io.levels.motion : nullptr);
    io.shown_msg.mutable_header()->set_stamp_ns(io.levels.time_ns);
    io.shown_pub.publish(io.shown_msg);
  }
  for (std::size_t k = 0; k < summaries; ++k) {
    io.summary = io.summaries_taken[k];
    publish_status();
  }
  return ticks;
}

// the trial stopped at duration_s, said as a live `sim.trial stop` is (TRIAL_END "stopped",
// at the last tick): whoever runs the trial stops the graph at once, on either clock
void Container::publish_limit() { io_->feed.stopped(limit_ns_.load()); }

void Container::print_summary() {
  Io& io = *io_;
  const char* name = host_.name().c_str();
  const Io::Felt& felt = io.felt;
  std::printf("%s: %s\n", name, rt::format(rt::summarize(io.stats, sched_.rate_hz)).c_str());
  const double n = static_cast<double>(std::max<std::uint64_t>(felt.ticks, 1));
  // on the top: of the task's surface (a scene without a task has none)
  char on_top[48] = "";
  if (simulator_.has_task()) std::snprintf(on_top, sizeof on_top, "on the top %.1f %% of ticks, ", 100.0 * static_cast<double>(felt.on_top) / n);
  std::printf("%s: the hand felt: mean |F| %.3f N, peak |F| %.3f N, mean pins up %.2f, %s"
              "%llu tactile frames; device faults on %llu ticks, model faults %llu, queue drops %llu\n",
              name, felt.force_sum_n / n, felt.force_max_n, felt.pins_sum / n, on_top,
              static_cast<unsigned long long>(felt.frames), static_cast<unsigned long long>(felt.device_faults), static_cast<unsigned long long>(felt.sim_faults),
              static_cast<unsigned long long>(io.dropped.load()));
  const rt::LoopSummary whole = rt::summarize(io.stats, sched_.rate_hz);
  const std::string verdict = clock_ == rt::GraphClock::simulated ? graph::simulated_verdict(sched_.rate_hz, whole.ticks, run_ns_)
                                                                   : graph::rate_verdict(sched_.rate_hz, whole.ticks, whole.overruns, force_->cuts());
  std::printf("%s: verdict: %s\n", name, verdict.c_str());
  // each component's lines, as its own process prints them
  std::printf("%s: %s\n", sim_name_.c_str(), simulator_.summary().c_str());
  if (clock_ == rt::GraphClock::simulated && felt.completed) std::printf("%s: %s\n", ffd_name_.c_str(), graph::kRunOverLine);
  std::printf("%s: %s\n", ffd_name_.c_str(), force_->summary().c_str());
  if (const TactileDriver* tactile = io.loop.tactile()) std::printf("%s: %s\n", tac_name_.c_str(), tactile->summary().c_str());
  // what the machine itself takes from a spinning loop, beside what this one missed
  if (spin_floor_ >= 0.0 && clock_ == rt::GraphClock::real) {
    std::printf("%s: the machine's floor: a thread spinning to 44 kHz deadlines with no work misses %.3f %% of them here (enact doctor)\n", name,
                100.0 * spin_floor_);
  }
  std::fflush(stdout);
}

void Container::open_ports() {
  graph::ParamBoard& board = host_.board();
  board.add(sim_p_, sim_name_, sim_name_ + ".");
  board.add(ffd_p_, ffd_name_, ffd_name_ + ".");
  if (tactile_) board.add(tac_p_, tac_name_, tac_name_ + ".");
  for (const Member& m : members_) board.add(m.params, m.name, m.name + ".");
  // the parameter port copies the simulator's model, the keyframe is sized: before the
  // real-time thread starts
  io_ = std::make_unique<Io>(*this);
  for (const auto& stage : stages_) io_->loop.add_stage(*stage);
  io_->keyframes.size(simulator_);
}

void Container::activate() {
  io_->loop.connect_params(io_->changes, io_->applied);
  // a recording from the first tick needs its loggers subscribed first (its own among them)
  observers_.start(true);
  graph::wait_for_subscribers(io_->out, graph::kDeviceState, config_.observers + observers_.recorders(graph::kDeviceState), host_.name(), "observer (logger)");
  observers_.start(false);
  rt_thread_ = std::thread([this] { rt_main(); });
  // what the loop thread set up (memory locked, SCHED_FIFO, pinned), said before the node is ready
  while (io_->fifo_in_force.load() < 0 && !rt_done_.load() && !graph::stop_requested()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  graph::say(host_.name(), io_->report.summary());
  graph::say(host_.name(), "the loop " + wait_why_);
}

void Container::run() {
  while (!rt_done_.load()) {
    // in simulated time the loop waits for this thread: no pause while there is work
    if (drain() == 0 || clock_ == rt::GraphClock::real) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

int Container::deactivate() {
  rt_thread_.join();
  drain();
  if (limit_ns_.load() >= 0) publish_limit();
  print_summary();
  // the observers take what is on its way, then close their files
  return observers_.stop_all() ? 0 : 1;
}

}  // namespace enact::node
