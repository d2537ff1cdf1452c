#include "core/node/ffd.h"

#include <algorithm>
#include <cstdlib>
#include <utility>

#include "core/bus/loop_link.h"
#include "core/bus/typed.h"
#include "core/config/env.h"
#include "core/devices/hand.h"
#include "core/node/components.h"
#include "core/params/node_params.h"
#include "core/params/param_binding.h"
#include "core/graph/messages.h"
#include "core/graph/graph_dir.h"
#include "core/graph/process.h"
#include "core/graph/sockets.h"
#include "core/graph/stop.h"
#include "core/graph/topics.h"
#include "core/graph/watchdog_log.h"
#include "core/rt/clock.h"
#include "core/rt/loop_stats.h"
#include "core/rt/probe.h"
#include "core/rt/profile.h"
#include "core/rt/round_trip.h"

namespace enact::node {

const NodeKind kFfd{.executable = "enact-ffd", .default_name = "ffd", .help = R"(usage: enact-ffd [--name NAME] --param NAME=VALUE...

The force-feedback device driver and clock master of a distributed graph: publishes
ffd/state at rate_hz, applies the ffd/force answering each sample, publishes node/status
at 1 Hz (sample-to-force latency percentiles, jitter, drops).

Stops on SIGINT/SIGTERM: zero force first.

parameters (--param NAME=VALUE):
)", .loop = true};

namespace {

// simulated time: how long the driver waits for the pins of a frame the simulator sent
constexpr std::int64_t kShownWait_ns = 2'000'000'000;

}  // namespace

struct Ffd::Io {
  Io(Ffd& f)
      : out(f.host_.out()),
        state_pub(out, graph::kDeviceState),
        commands(in, graph::kForceCommand),
        shown(conflated(shown_in), graph::kTactileShown),
        hand(f.driver_->feeling_hand()),
        feels_pins(hand != nullptr) {}
  static bus::ByteSubscriber& conflated(bus::ByteSubscriber& s) {
    s.set_conflate(true);
    return s;
  }
  bus::BytePublisher& out;
  bus::Publisher<msgs::DeviceState> state_pub;
  bus::ByteSubscriber in;
  bus::Subscriber<msgs::ForceCommand> commands;
  // the hop to the simulator: the same-host link (the bus still carries every state to the
  // observers), or the bus itself
  bus::LoopLink link;
  char answer[bus::LoopLink::kMaxMessage];
  msgs::ForceCommand command;
  // a virtual subject's fingertip: the latest pins the tactile driver shows
  bus::ByteSubscriber shown_in;
  bus::Subscriber<msgs::TactileShown> shown;
  msgs::TactileShown shown_msg;
  devices::HandSource* hand;
  const bool feels_pins;
  float levels[32] = {};
  devices::PinMotion motion;  // the pins' motion from the last tactile/shown, if it said
  bool moves = false;
  std::int64_t shown_offset_ns = 0;  // the tactile driver's clock less this loop's
  std::int64_t last_tick_ns = -1;
  std::uint64_t pins_felt = 0;
  std::uint64_t frame_due = 0;  // simulated time: the tactile frame whose pins come before the next tick
  std::uint64_t pins_missed = 0;  // simulated time: frames whose pins did not come in kShownWait_ns
  std::unique_ptr<rt::PeriodicScheduler> scheduler;
  rt::LoopStats stats;
  devices::ForceSample sample;
  msgs::DeviceState state;
  msgs::NodeStatus status;
  // each sample and the answer that carries its seq: unanswered samples, late (stale) answers
  rt::RoundTrip answers;
  std::int64_t next_status = 0;
};

Ffd::Ffd(Host& host)
    : host_(host),
      config_(graph::ffd_node_bindings().read(host.params())),
      local_hop_(config_.loop_transport != "zeromq"),
      simulated_(graph::graph_clock() == rt::GraphClock::simulated) {
  sched_.rate_hz = config_.loop.rate_hz;
  sched_.simulated = simulated_;
  sched_.validate();
  rtp_.lock_memory = config_.loop.lock_memory;
  rtp_.fifo_priority = config_.loop.fifo_priority;
  driver_ = std::make_unique<ForceDriver>(graph::make_force_device(host.params()), host.name(),
                                          "force path cut (no force answer, or a device error): force ramped to zero");
}

Ffd::~Ffd() = default;

// the hop to the simulator, and its peers: wait until the simulator (and the observers asked
// for) listen: ZeroMQ drops what it sends before that
void Ffd::open_hop() {
  Io& io = *io_;
  const std::string& name = host_.name();
  if (local_hop_) {
    io.link = bus::LoopLink::listen(bus::loop_link_path(graph::graph_dir(), name));
    io.state_pub.also_over(&io.link);
  } else {
    io.in.connect(graph::node_endpoint(config_.sim_node));
  }
  if (io.feels_pins) io.shown_in.connect(graph::node_endpoint(config_.tactile_node));
  // the simulator subscribes to the states on the bus on either hop (on the local one until
  // the first state reaches it over the link): it counts with the observers asked for. It
  // takes the link once its own observers listen
  const int subscribers = local_hop_ && config_.observers == 0 ? 0 : 1 + config_.observers;
  graph::wait_for_subscribers(io.out, graph::kDeviceState, subscribers, name, "subscriber (the simulator, then observers)");
  if (local_hop_) graph::wait_for_loop_peer(io.link, name, config_.sim_node);
  graph::say(name, local_hop_ ? "loop hop to " + config_.sim_node + ": local (Unix link " + io.link.path() + ", read by the loop thread)"
                              : "loop hop to " + config_.sim_node + ": ZeroMQ (loop_transport=zeromq)");
}

// how to wait, from this machine's probe: the spin window covers its wake-up lateness; a
// period shorter than twice the lateness is spun whole on the loop's CPU, under normal
// scheduling (the simulator, woken by each state, still gets the CPU it needs)
void Ffd::plan_wait() {
  if (simulated_) {
    // lock-step: the next tick as soon as this one's answer (and the pins it drove) are in
    graph::say(host_.name(), "the loop ticks back to back: the graph's clock is simulated (a tick's time is its index over rate_hz)");
    io_->scheduler = std::make_unique<rt::PeriodicScheduler>(sched_);
    return;
  }
  const rt::RtReport report = rt::apply_rt_setup(rtp_);
  // under the graph's real-time profile (said above) a node that asks for nothing more has nothing to add
  if (!report.notes.empty() || !std::getenv(env::kRtProfile)) graph::say(host_.name(), report.summary());
  const bool fifo = rt::running_fifo();
  const rt::WaitPlan wait = rt::loop_wait(config_.loop.spin_us, rt::PeriodicScheduler(sched_).period_ns(), fifo, false, graph::loop_cpu_own());
  if (fifo && !wait.fifo) rt::system_calls().set_fifo(0);
  host_.board().set(host_.name() + ".fifo_priority", std::to_string(rt::fifo_priority_now()));  // what the loop runs at
  sched_.spin_ns = wait.spin_ns;
  sched_.sleep_every_tick = !wait.spin_whole_period;
  sched_.wake_fd = local_hop_ && sched_.sleep_every_tick;  // the answer awaited on the link until its timer
  graph::say(host_.name(), "the loop " + wait.why);
  io_->scheduler = std::make_unique<rt::PeriodicScheduler>(sched_);
}

// the next answer from the simulator until deadline_ns, into io.command: false when none came
bool Ffd::next_answer(std::int64_t deadline_ns) {
  Io& io = *io_;
  if (!local_hop_) {
    while (graph::wait_readable(io.in.socket(), deadline_ns)) {
      if (io.commands.receive(io.command, 0)) return true;
    }
    return false;
  }
  // until the scheduler's timer where it is armed for deadline_ns (no timer of this wait's own)
  const rt::PeriodicScheduler::ReplyWait wait = io.scheduler->reply_wait(deadline_ns);
  for (long n; (n = io.link.receive(io.answer, sizeof io.answer, wait.until, wait.stop_fd)) > 0;) {
    if (io.commands.accept_payload(io.answer, static_cast<std::size_t>(n), io.command)) return true;
  }
  return false;
}

// the answer to the sample just sent: in real time until `answer_by` (just before the next
// tick), in simulated time until it comes (or a stop)
bool Ffd::await_answer(std::int64_t answer_by) {
  while (!next_answer(simulated_ ? rt::now_ns() + 100'000'000 : answer_by)) {
    if (!simulated_ || graph::stop_requested()) return false;
  }
  return true;
}

// simulated time: the pins of frame `due` (0: no frame since the last tick), waited for
bool Ffd::await_shown(std::uint64_t due) {
  Io& io = *io_;
  const std::int64_t give_up = rt::now_ns() + kShownWait_ns;
  while (due > 0 && !(io.shown.receive(io.shown_msg, 100) && io.shown_msg.frame_seq() >= due)) {
    if (graph::stop_requested() || rt::now_ns() > give_up) {
      if (io.pins_missed++ == 0) graph::say(host_.name(), "tactile/shown for frame " + std::to_string(due) + " did not come within 2 s: the subject feels the pins it had (said once, counted)");
      return false;
    }
  }
  return due > 0;
}

// a virtual subject's fingertip, before each read: the pins as they were at the tick before
// (the co-located loop's order: pins written at a tick are felt from the next read on), from
// the motion the tactile driver last sent (the pins rising tick by tick, as on the co-located
// graph), else its last levels, held. In simulated time the pins of each frame the last
// answer said was sent are waited for (lock-step: the same pins at the same tick every run)
void Ffd::feel_pins(std::int64_t last_tick) {
  Io& io = *io_;
  if (!io.feels_pins) return;
  if (simulated_ ? await_shown(std::exchange(io.frame_due, 0)) : io.shown.receive(io.shown_msg, 0)) {
    ++io.pins_felt;
    io.moves = graph::get(io.shown_msg, io.motion);
    // the driver's clock: in simulated time the frames' stamps, this loop's ticks; in real
    // time its stamps, mapped onto this clock at receipt (within the hop's latency)
    io.shown_offset_ns = simulated_ ? 0 : io.shown_msg.header().stamp_ns() - rt::now_ns();
    const int n = std::min(io.shown_msg.level_size(), 32);
    for (int i = 0; i < n; ++i) io.levels[i] = io.shown_msg.level(i);
  } else if (!io.moves) {
    return;  // the pins the subject felt last, held
  }
  const int rows = static_cast<int>(io.shown_msg.rows()), cols = static_cast<int>(io.shown_msg.cols());
  if (io.moves) {
    for (int i = 0; i < std::min(rows * cols, 32); ++i) io.levels[i] = static_cast<float>(io.motion.level(i, last_tick + io.shown_offset_ns));
  }
  io.hand->feel_pins(io.levels, rows, cols);
}

// the answer in io.command, if it answers the open sample: its force written (at `now`, the
// tick's time, in simulated time; at once in real time)
bool Ffd::apply_answer(std::int64_t now) {
  Io& io = *io_;
  if (!io.answers.reply(io.command.answered_seq(), rt::now_ns())) return false;
  // in simulated time at the model's time, as every tick's read: the loop reads no wall clock
  driver_->device().write(simulated_ ? now : rt::now_ns(), io.command.zero() ? math::Vec3{} : graph::get(io.command.force()));
  if (simulated_) {
    io.frame_due = io.command.tactile_frame_seq();
    run_over_ = io.command.run_over();
  } else {
    io.stats.latency.record(rt::now_ns() - io.sample.time_ns);
  }
  return true;
}

// one tick: the answer to the last sample if it came while the loop spun to this tick (the
// simulator, above the driver's priority on the shared CPU, answers then too), the sample
// out, its answer in until the loop spins to the next tick (an answer to an older sample is
// too late to apply: counted stale), the force written
void Ffd::tick(std::int64_t now) {
  Io& io = *io_;
  while (!simulated_ && next_answer(0) && !apply_answer(now)) {
  }
  feel_pins(io.last_tick_ns < 0 ? now : io.last_tick_ns);
  io.last_tick_ns = now;
  driver_->device().read(now, io.sample);
  driver_->path(io.sample.faults, now);
  io.state.mutable_header()->set_stamp_ns(0);
  graph::fill(io.state, io.sample);
  if (local_hop_ && !io.link.connected()) io.link.accept_peer();  // a respawned simulator
  io.state_pub.publish(io.state);
  io.answers.sent(io.state.header().seq(), now);
  const std::int64_t answer_by = io.scheduler->next_deadline_ns() - io.scheduler->spin_ns();
  while (await_answer(answer_by) && !apply_answer(now)) {
  }
  io.state_pub.send_held();  // the observers' copy, once the force is written
  // still open: the next tick takes the answer that came by then (sent() closes it)
  if (now >= io.next_status) publish_status();
}

void Ffd::publish_status() {
  Io& io = *io_;
  io.next_status += 1'000'000'000;
  rt::take_timing(*io.scheduler, io.stats);
  graph::fill(io.status, host_.name(), rt::summarize(io.stats, sched_.rate_hz), io.answers.unanswered(),
              io.answers.unanswered() ? "samples without a force answer in time" : "");
  driver_->cuts().fill(io.status);
  // every deadline: a sample taken and answered in time, or not (a skipped tick is missed)
  graph::fill_verdict(io.status, sched_.rate_hz, io.answers.requests() + io.scheduler->skipped(),
                      io.answers.unanswered() + io.scheduler->skipped(), driver_->cuts());
  io.status.mutable_header()->set_stamp_ns(0);
  host_.publish_status(io.status, io.in.all_counters());
}

void Ffd::say_summary() {
  Io& io = *io_;
  const std::string& name = host_.name();
  rt::take_timing(*io.scheduler, io.stats);
  graph::say(name, rt::format(rt::summarize(io.stats, sched_.rate_hz)) + " Samples without an answer in time: " +
                       std::to_string(io.answers.unanswered()) + " of " + std::to_string(io.answers.requests()) +
                       ", late answers: " + std::to_string(io.answers.stale()) +
                       ", lost answers (seq gaps): " + std::to_string(io.commands.counters().lost) + ".");
  graph::say(name, driver_->summary());
  graph::say(name, "verdict: " + (simulated_ ? graph::simulated_verdict(sched_.rate_hz, io.answers.requests(), rt::now_ns() - started_ns_)
                                             : graph::rate_verdict(sched_.rate_hz, io.answers.requests() + io.scheduler->skipped(),
                                                                   io.answers.unanswered() + io.scheduler->skipped(), driver_->cuts())));
  if (io.feels_pins) {
    graph::say(name, "the virtual subject felt " + std::to_string(io.pins_felt) + " pin states from " + config_.tactile_node + " (tactile/shown)" +
                         (simulated_ ? "; frames whose pins did not come in time: " + std::to_string(io.pins_missed) + "." : "."));
  }
}

void Ffd::open_ports() { io_ = std::make_unique<Io>(*this); }

void Ffd::activate() {
  open_hop();
  plan_wait();
  driver_->device().activate();
  const std::int64_t start = rt::now_ns() + 1'000'000;
  end_ns_ = config_.loop.end_ns(start);
  io_->next_status = start + 1'000'000'000;
  io_->scheduler->start(start);
  started_ns_ = rt::now_ns();
}

void Ffd::run() {
  while (!graph::stop_requested() && !run_over_) {
    const std::int64_t now = io_->scheduler->wait();
    if (now >= end_ns_) break;
    tick(now);
  }
  if (run_over_) graph::say(host_.name(), graph::kRunOverLine);
}

int Ffd::deactivate() {
  io_->answers.close();
  driver_->device().deactivate();  // zero force first
  say_summary();
  return 0;
}

}  // namespace enact::node
