#include "core/node/tactile.h"

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
#include "core/graph/topics.h"
#include "core/graph/watchdog_log.h"
#include "core/rt/clock.h"

namespace enact::node {

const NodeKind kTactile{.executable = "enact-tactile", .default_name = "tactile", .help = R"(usage: enact-tactile [--name NAME] --param NAME=VALUE...

The tactile display driver of a distributed graph: applies tactile/frame, publishes
tactile/shown at shown_rate_hz and node/status at 1 Hz; lowers every pin on stop, and
while no frame came for longer than watchdog_s (each episode said and counted). In
simulated time its clock is the frames' stamps: tactile/shown follows each frame.

parameters (--param NAME=VALUE):
)"};

Tactile::Tactile(Host& host)
    : host_(host),
      device_(graph::make_tactile_device(host.params())),
      driver_(*device_),
      config_(graph::tactile_node_bindings().read(host.params())) {}

Tactile::~Tactile() = default;

// the node's sockets and messages, and what it has applied
struct Tactile::Io {
  explicit Io(Tactile& t)
      : out(t.host_.out()), shown_pub(out, graph::kTactileShown), frames(in, graph::kTactileFrame),
        watchdog(t.host_.name(), "no tactile/frame: pins lowered") {}
  bus::BytePublisher& out;
  bus::Publisher<msgs::TactileShown> shown_pub;
  bus::ByteSubscriber in;
  bus::Subscriber<msgs::TactileFrame> frames;
  graph::WatchdogLog watchdog;
  msgs::TactileFrame frame;
  PinsShown pins;
  msgs::TactileShown shown;
  msgs::NodeStatus status;
};

// the frame just received, on the pins at `now`
void Tactile::apply(std::int64_t now) {
  const msgs::TactileFrame& frame = io_->frame;
  driver_.apply(now, pins_up(frame.level().data(), frame.level_size(), driver_.pins()), frame.header().seq());
}

// what the pins show at `now`, published
void Tactile::publish_shown(std::int64_t now) {
  Io& io = *io_;
  driver_.show(now, io.pins);
  graph::fill(io.shown, driver_.rows(), driver_.cols(), io.pins.level, io.pins.frame_seq, io.pins.moves ? &io.pins.motion : nullptr);
  io.shown.mutable_header()->set_stamp_ns(now);
  io.shown_pub.publish(io.shown);
}

void Tactile::publish_status(std::int64_t now) {
  Io& io = *io_;
  graph::fill(io.status, host_.name(), rt::LoopSummary{.rate_hz = config_.shown_rate_hz}, 0, "");
  io.watchdog.update(io.watchdog.tripped(), now);
  io.watchdog.fill(io.status);
  host_.publish_status(io.status, io.in.all_counters());
}

// real time: frames applied as they come, the pins shown at shown_rate_hz, every pin down
// while frames stop for longer than watchdog_s
void Tactile::run_real() {
  Io& io = *io_;
  const std::int64_t period = static_cast<std::int64_t>(1e9 / config_.shown_rate_hz);
  const std::int64_t watchdog_ns = static_cast<std::int64_t>(config_.watchdog_s * 1e9);
  std::int64_t next_shown = rt::now_ns(), next_status = next_shown + 1'000'000'000, last_frame_ns = -1;
  while (!graph::stop_requested()) {
    if (graph::wait_readable(io.in.socket(), next_shown) && io.frames.receive(io.frame, 0)) {
      last_frame_ns = rt::now_ns();
      io.watchdog.update(false, last_frame_ns);
      apply(last_frame_ns);
    }
    const std::int64_t now = rt::now_ns();
    // frames stopped (after the first): every pin down until the next one
    if (last_frame_ns >= 0 && !io.watchdog.tripped() && now - last_frame_ns > watchdog_ns) {
      io.watchdog.update(true, now);
      driver_.lower(now);
    }
    if (now < next_shown) continue;
    next_shown += period;
    publish_shown(now);
    if (now >= next_status) {
      next_status += 1'000'000'000;
      publish_status(now);
    }
  }
}

// simulated time: the model's time is the frames' stamps (the samples they came from); what
// the pins show is published after each frame, which the clock master waits for
void Tactile::run_simulated() {
  Io& io = *io_;
  // the clock master, started after this node, listens before the first frame comes
  graph::await_subscribers(io.out, graph::kTactileShown, 1, rt::now_ns() + 2'000'000'000);
  std::int64_t next_status = rt::now_ns() + 1'000'000'000;
  while (!graph::stop_requested()) {
    if (io.frames.receive(io.frame, 100)) {
      const std::int64_t t = io.frame.header().stamp_ns();
      apply(t);
      publish_shown(t);
    }
    if (rt::now_ns() >= next_status) {
      next_status += 1'000'000'000;
      publish_status(io.frame.header().stamp_ns());
    }
  }
  // stopped: the frames already here are the model's as much as those before (the clock
  // master, when it feels no pins, runs ahead of this node): every one is applied
  while (io.frames.receive(io.frame, 0)) {
    apply(io.frame.header().stamp_ns());
    publish_shown(io.frame.header().stamp_ns());
  }
}

void Tactile::open_ports() { io_ = std::make_unique<Io>(*this); }

void Tactile::activate() {
  io_->in.connect(graph::node_endpoint(config_.sim_node));
  driver_.activate();
}

void Tactile::run() {
  if (graph::graph_clock() == rt::GraphClock::simulated) {
    run_simulated();
  } else {
    run_real();
  }
}

int Tactile::deactivate() {
  driver_.deactivate();  // every pin down
  graph::say(host_.name(), driver_.summary("frames lost (seq gaps): " + std::to_string(io_->frames.counters().lost) + "; " + io_->watchdog.summary() + "; "));
  return 0;
}

}  // namespace enact::node
