// enact-rt: the co-located real-time container. The simulator and both device drivers run
// in one process and one real-time thread (read device, step, write force, write pins, in
// the same tick); observers are fed from a lock-free queue by a non-real-time thread.
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <thread>

#include "core/bus/typed.h"
#include "core/config/yaml.h"
#include "core/graph/colocated.h"
#include "core/graph/components.h"
#include "core/graph/messages.h"
#include "core/graph/node.h"
#include "core/graph/node_params.h"
#include "core/graph/param_board.h"
#include "core/graph/param_bus.h"
#include "core/graph/task_state.h"
#include "core/graph/topics.h"
#include "core/graph/watchdog_log.h"
#include "core/rt/clock.h"
#include "core/rt/loop_stats.h"
#include "core/rt/probe.h"
#include "core/rt/profile.h"
#include "core/rt/rt_setup.h"
#include "core/rt/scheduler.h"
#include "core/rt/spsc_queue.h"

namespace {

using namespace enact;

constexpr const char* kHelp = R"(usage: enact-rt [--name NAME] --component=NAME:PLUGIN... --param NAME=VALUE...

The co-located real-time container: components sim, ffd and tactile (one of each) in one
process and one real-time thread, ticking at rate_hz: read the device, step the model,
write the force, write the pins (down-sampled), in the same tick. A non-real-time thread,
fed through lock-free queues, publishes every topic for observers: ffd/state, ffd/force,
tactile/frame and task/event at their rates, task/state at 10 Hz and on change, sim/scene
at scene_rate_hz, tactile/shown at shown_rate_hz, node/status at 1 Hz (at $ENACT_GRAPH_DIR/<name>.pub). Parameter changes on
param/set (SIM.model, SIM.stiffness_n_per_m, ...: docs/parameters.md; SIM is the sim
component's name) are checked on that thread, handed to the real-time thread through a
lock-free queue, applied at the top of a tick, and answered on param/ack.

container parameters (--param NAME=VALUE; rate_hz is the simulator's rate too):
)";

// the --help text: the container's parameters, then each plugin's
std::string help() {
  std::string out = std::string(kHelp) + graph::help_lines(*graph::node_table("enact-rt"));
  out += "component parameters (--param COMPONENT.NAME=VALUE, e.g. sim.scene=launch/scenes/bridge.yaml; live:\n"
         "enact param set COMPONENT.NAME VALUE while it runs):\n";
  for (const char* plugin : {"sim", "ffd", "tactile"}) out += std::string(" plugin ") + plugin + ":\n" + graph::help_lines(*graph::component_table(plugin), std::string(plugin) + ".");
  return out;
}

// what the hand felt, accumulated by the non-real-time thread
struct Felt {
  std::uint64_t ticks = 0, frames = 0, dropped = 0, device_faults = 0, sim_faults = 0;
  double force_sum_n = 0.0, force_max_n = 0.0, pins_sum = 0.0;
  std::uint64_t on_top = 0;
  int falls = 0;
  bool completed = false;
  double progress = 0.0;
};

void consume(const graph::Observation& o, Felt& felt) {
  const double f = math::norm(o.step.force_n);
  felt.ticks += 1;
  felt.force_sum_n += f;
  felt.force_max_n = std::max(felt.force_max_n, f);
  felt.pins_sum += __builtin_popcount(o.step.pins);
  felt.frames += o.step.frame_due;
  felt.on_top += o.step.on_top;
  felt.device_faults += o.sample.faults != 0;
  felt.sim_faults += o.step.fault;
  felt.falls += o.step.event.kind == task::TaskEventKind::fall_start;
  felt.completed = felt.completed || o.step.event.kind == task::TaskEventKind::completed;
  felt.progress = std::max(felt.progress, o.step.on_top ? o.step.progress : 0.0);
}

std::string find_component(const graph::NodeArgs& args, const std::string& plugin) {
  std::string name;
  for (const auto& [n, p] : args.components) {
    if (p != plugin) continue;
    if (!name.empty()) throw config::Error(args.name + ": two " + plugin + " components\n  fix: one sim, one ffd and one tactile");
    name = n;
  }
  if (name.empty()) throw config::Error(args.name + ": no " + plugin + " component\n  fix: add --component=" + plugin + ":" + plugin);
  return name;
}

int run(int argc, char** argv) {
  graph::NodeArgs args = graph::parse_node_args(argc, argv, "rt");
  if (args.help) {
    std::fputs(help().c_str(), stdout);
    return 0;
  }
  for (const auto& [n, p] : args.components) {
    if (p != "sim" && p != "ffd" && p != "tactile") throw config::Error(args.name + ": unknown plugin '" + p + "'\n  fix: use sim, ffd or tactile");
  }
  // container params; the components' own are declared as they are built
  const std::string sim_name = find_component(args, "sim"), ffd_name = find_component(args, "ffd"), tac_name = find_component(args, "tactile");
  graph::Params sim_p = args.params.scoped(sim_name), ffd_p = args.params.scoped(ffd_name), tac_p = args.params.scoped(tac_name);
  args.params.declare(*graph::node_table("enact-rt"));
  args.params.refuse_unknown();
  rt::SchedulerParams sched;
  sched.rate_hz = args.params.number("rate_hz");
  sched.validate();
  const double duration_s = args.params.number("duration_s");
  rt::RtParams rtp;
  rtp.lock_memory = args.params.flag("lock_memory");
  rtp.fifo_priority = args.params.integer("fifo_priority");
  if (args.params.has("cpus")) rtp.cpus.push_back(args.params.integer("cpus"));
  // the graph's real-time profile (launch entry realtime:) places the loop thread, not the
  // process: the publisher thread and the bus stay with the observers
  if (const char* profile = std::getenv(rt::kProfileEnv)) {
    const rt::NodeProfile np = rt::NodeProfile::from_env(profile);
    if (!np.cpus.empty()) rtp.cpus = np.cpus;
    if (np.fifo_priority > 0) rtp.fifo_priority = np.fifo_priority;
  }
  // how the loop waits, from this machine's probe: a period shorter than twice its wake-up
  // lateness is spun whole, on the loop's own CPU under normal scheduling (a FIFO thread that
  // never sleeps is throttled by the kernel); otherwise it sleeps and spins the lateness
  const bool own_cpu = !rtp.cpus.empty() && std::thread::hardware_concurrency() >= 2;
  const double spin_us = args.params.number("spin_us");
  const std::int64_t period_ns = rt::PeriodicScheduler(sched).period_ns();
  const rt::WaitPlan wait = rt::loop_wait(spin_us, period_ns, rtp.fifo_priority > 0, false, own_cpu);
  if (!wait.fifo) rtp.fifo_priority = 0;
  if (wait.spin_whole_period) rtp.nice = -20;
  sched.spin_ns = wait.spin_ns;
  // components, configured (bad input is refused here, before anything moves)
  sim::SimParams sp = graph::sim_params(sim_p);
  const double reengage_s = sim_p.number("reengage_s");
  sp.rate_hz = sched.rate_hz;
  sim::Simulator simulator;
  simulator.configure(sp);
  auto force = graph::make_force_device(ffd_p);
  auto tactile = graph::make_tactile_device(tac_p);
  sim_p.refuse_unknown();
  ffd_p.refuse_unknown();
  tac_p.refuse_unknown();
  const double scene_rate_hz = args.params.number("scene_rate_hz");
  const double shown_rate_hz = args.params.number("shown_rate_hz");
  const int observers = args.params.integer("observers");
  if (args.check) return 0;

  graph::install_stop_handlers();
  // the publishers, and the parameter port (it copies the simulator's model: before the
  // real-time thread starts)
  bus::BytePublisher out(graph::node_endpoint(args.name), {.node = args.name, .send_hwm = 10000});
  bus::Publisher<msgs::DeviceState> state_pub(out, graph::kDeviceState);
  bus::Publisher<msgs::ForceCommand> force_pub(out, graph::kForceCommand);
  bus::Publisher<msgs::TactileFrame> frame_pub(out, graph::kTactileFrame);
  bus::Publisher<msgs::TactileShown> shown_pub(out, graph::kTactileShown);
  bus::Publisher<msgs::SceneState> scene_pub(out, graph::kSceneState);
  bus::Publisher<msgs::TaskEvent> event_pub(out, graph::kTaskEvent);
  bus::Publisher<msgs::NodeStatus> status_pub(out, graph::kNodeStatus);
  graph::ParamBoard board(args.name);
  board.add(args.params, args.name);
  board.add(sim_p, sim_name, sim_name + ".");
  board.add(ffd_p, ffd_name, ffd_name + ".");
  board.add(tac_p, tac_name, tac_name + ".");
  graph::ParamPort params(simulator, sim_name, out, event_pub, &board);
  graph::TaskStateTracker task_state(out);
  graph::announce_topics(out);
  board.start();
  graph::ColocatedLoop loop(simulator, *force, *tactile, &rt::now_ns, reengage_s);
  // real-time thread -> publisher thread: every tick, scene snapshots, pin levels, loop stats
  struct Shown {
    std::int64_t time_ns;
    float level[32];
  };
  struct Scene {
    std::int64_t tick_ns;  // the tick it was taken at (names its computer model)
    graph::SceneSnapshot snap;
  };
  static rt::SpscQueue<graph::Observation, 16384> queue;
  static rt::SpscQueue<Scene, 64> scenes;
  static rt::SpscQueue<Shown, 64> shown_queue;
  static rt::SpscQueue<rt::LoopSummary, 8> summaries;
  static graph::ParamQueue changes;
  static graph::AppliedQueue applied;
  loop.connect_params(changes, applied);
  rt::LoopStats stats;
  std::atomic<std::uint64_t> dropped{0};
  rt::RtReport report;
  std::atomic<bool> rt_done{false};
  const int rows = tactile->rows(), cols = tactile->cols();

  // a recording from the first tick needs its logger subscribed first
  graph::wait_for_subscribers(out, graph::kDeviceState, observers, args.name, "observer (logger)");

  // the real-time thread: set up, then tick on absolute deadlines
  std::thread rt_thread([&] {
    report = rt::apply_rt_setup(rtp);
    rt::prefault_stack();
    // under SCHED_FIFO the loop sleeps every tick, or the kernel throttles it (~50 ms a second)
    rt::SchedulerParams tick = sched;
    tick.sleep_every_tick = report.fifo;
    rt::PeriodicScheduler scheduler(tick);
    const std::int64_t start = rt::now_ns() + 1'000'000;
    const std::int64_t scene_every = std::max<std::int64_t>(1, std::llround(sched.rate_hz / scene_rate_hz));
    const std::int64_t shown_every = std::max<std::int64_t>(1, std::llround(sched.rate_hz / shown_rate_hz));
    const std::int64_t status_every = std::max<std::int64_t>(1, std::llround(sched.rate_hz));
    Scene scene{};
    Shown levels{};
    loop.activate();
    scheduler.start(start);
    const std::int64_t end = duration_s > 0.0 ? start + static_cast<std::int64_t>(duration_s * 1e9) : INT64_MAX;
    for (std::int64_t n = 0; !graph::stop_requested(); ++n) {
      const std::int64_t woke = scheduler.wait();
      if (woke >= end) break;
      const graph::Observation& o = loop.tick(woke);
      stats.latency.record(o.force_ns - o.sample.time_ns);
      if (!queue.try_push(o)) dropped.fetch_add(1, std::memory_order_relaxed);
      if (n % scene_every == 0) {
        scene.tick_ns = woke;
        graph::snapshot(simulator, o.step.pins, o.step.force_n, scene.snap);
        scenes.try_push(scene);
      }
      if (n % shown_every == 0) {
        levels.time_ns = woke;
        tactile->shown(woke, levels.level, rows * cols);
        shown_queue.try_push(levels);
      }
      if (n % status_every == status_every - 1) {
        rt::take_timing(scheduler, stats);
        summaries.try_push(rt::summarize(stats, sched.rate_hz));
      }
    }
    loop.deactivate();
    rt::take_timing(scheduler, stats);
    rt_done.store(true);
  });

  // the publisher thread (this one): every topic for observers
  msgs::DeviceState state_msg;
  msgs::ForceCommand force_msg;
  msgs::TactileFrame frame_msg;
  msgs::TactileShown shown_msg;
  msgs::SceneState scene_msg;
  msgs::TaskEvent event_msg;
  msgs::NodeStatus status_msg;
  std::uint64_t frame_seq = 0;
  // what the real-time thread applied, before anything it did after: a tick's messages name
  // the computer model in force at that tick
  sim::ParamApplied done;
  auto take_applied = [&] {
    while (applied.try_pop(done)) {
      params.applied(done);
      task_state.applied(done.kind);
    }
  };
  auto publish = [&](const graph::Observation& o) {
    graph::fill(state_msg, o.sample);
    state_pub.publish(state_msg);
    params.stepped(o.seq, state_msg.header().seq(), state_msg.header().stamp_ns());
    graph::fill(force_msg, state_msg.header().seq(), o.step.force_n, o.step.fault);
    force_msg.mutable_header()->set_stamp_ns(o.force_ns);
    force_pub.publish(force_msg);
    if (o.step.frame_due) {
      graph::fill(frame_msg, rows, cols, o.step.frame);
      frame_msg.mutable_header()->set_stamp_ns(o.sample.time_ns);
      frame_pub.publish(frame_msg);
      frame_seq = frame_msg.header().seq();
    }
    if (graph::fill(event_msg, o.step.event, params.model_name_at(o.sample.time_ns))) event_pub.publish(event_msg);
  };
  Felt felt;
  // each cut of the force path (a late tick, a device error) said once, counted
  graph::WatchdogLog cuts(args.name, "force path cut (a late tick or a device error): body re-synchronised, force back from zero");
  graph::Observation o;
  Scene scene;
  Shown levels;
  rt::LoopSummary summary;
  auto drain = [&] {
    // parameter changes to the real-time thread (never more than the queue holds), and back
    while (const auto change = params.next()) changes.try_push(*change);
    while (queue.try_pop(o)) {
      take_applied();
      consume(o, felt);
      if (o.cut != cuts.tripped()) cuts.update(o.cut, o.cut ? o.cut_since_ns : o.sample.time_ns);
      task_state.step(o.sample.time_ns, o.step);
      publish(o);
    }
    task_state.publish_due(rt::now_ns(), params.model_name());
    while (scenes.try_pop(scene)) {
      take_applied();
      graph::fill(scene_msg, scene.snap, params.model_name_at(scene.tick_ns));
      scene_pub.publish(scene_msg);
    }
    take_applied();
    while (shown_queue.try_pop(levels)) {
      graph::fill(shown_msg, rows, cols, levels.level, frame_seq);
      shown_msg.mutable_header()->set_stamp_ns(levels.time_ns);
      shown_pub.publish(shown_msg);
    }
    while (summaries.try_pop(summary)) {
      graph::fill(status_msg, args.name, summary, felt.device_faults + felt.sim_faults, "");
      cuts.fill(status_msg);
      graph::fill_verdict(status_msg, sched.rate_hz, summary.ticks, summary.overruns, cuts);
      graph::add_counters(status_msg, out, &params.subscriber());
      status_pub.publish(status_msg);
    }
  };
  graph::say(args.name, "the loop " + wait.why);
  graph::report_ready();
  while (!rt_done.load()) {
    drain();
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  rt_thread.join();
  drain();

  std::printf("%s: %s\n", args.name.c_str(), report.summary().c_str());
  std::printf("%s: %s\n", args.name.c_str(), rt::format(rt::summarize(stats, sched.rate_hz)).c_str());
  const double n = static_cast<double>(std::max<std::uint64_t>(felt.ticks, 1));
  std::printf("%s: the hand felt: mean |F| %.3f N, peak |F| %.3f N, mean pins up %.2f, on the top %.1f %% of ticks, "
              "%llu tactile frames, falls %d, progress %.2f%s; device faults on %llu ticks, model faults %llu, queue drops %llu; %s\n",
              args.name.c_str(), felt.force_sum_n / n, felt.force_max_n, felt.pins_sum / n, 100.0 * static_cast<double>(felt.on_top) / n,
              static_cast<unsigned long long>(felt.frames), felt.falls, felt.progress, felt.completed ? " (completed)" : "",
              static_cast<unsigned long long>(felt.device_faults), static_cast<unsigned long long>(felt.sim_faults),
              static_cast<unsigned long long>(dropped.load()), cuts.summary().c_str());
  const rt::LoopSummary whole = rt::summarize(stats, sched.rate_hz);
  std::printf("%s: verdict: %s\n", args.name.c_str(), graph::rate_verdict(sched.rate_hz, whole.ticks, whole.overruns, cuts).c_str());
  std::fflush(stdout);
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return enact::graph::node_main("enact-rt", run, argc, argv); }
