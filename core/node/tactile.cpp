#include "core/node/tactile.h"

#include <algorithm>

#include "core/bus/typed.h"
#include "core/graph/components.h"
#include "core/graph/messages.h"
#include "core/graph/node.h"
#include "core/graph/topics.h"
#include "core/graph/watchdog_log.h"
#include "core/rt/clock.h"

namespace enact::node {

const NodeKind kTactile{.executable = "enact-tactile", .default_name = "tactile", .help = R"(usage: enact-tactile [--name NAME] --param NAME=VALUE...

The tactile display driver of a distributed graph: applies tactile/frame, publishes
tactile/shown at shown_rate_hz and node/status at 1 Hz; lowers every pin on stop, and
while no frame came for longer than watchdog_s (each episode said and counted).

parameters (--param NAME=VALUE):
)"};

Tactile::Tactile(Host& host)
    : host_(host),
      device_(graph::make_tactile_device(host.params())),
      sim_node_(host.params().text("sim_node")),
      shown_rate_hz_(host.params().number("shown_rate_hz")),
      watchdog_s_(host.params().number("watchdog_s")) {}

int Tactile::run() {
  host_.open(1000);
  const std::string& name = host_.name();
  bus::BytePublisher& out = host_.out();
  bus::Publisher<msgs::TactileShown> shown_pub(out, graph::kTactileShown);
  bus::Publisher<msgs::NodeStatus> status_pub(out, graph::kNodeStatus);
  host_.announce();
  bus::ByteSubscriber in;
  bus::Subscriber<msgs::TactileFrame> frames(in, graph::kTactileFrame);
  in.connect(graph::node_endpoint(sim_node_));

  const int pins = device_->rows() * device_->cols();
  float levels[32] = {};
  msgs::TactileFrame frame;
  msgs::TactileShown shown;
  msgs::NodeStatus status;
  std::uint64_t frame_seq = 0, applied = 0;
  const std::int64_t period = static_cast<std::int64_t>(1e9 / shown_rate_hz_);
  const std::int64_t watchdog_ns = static_cast<std::int64_t>(watchdog_s_ * 1e9);
  graph::WatchdogLog watchdog(name, "no tactile/frame: pins lowered");
  device_->activate();
  std::int64_t next_shown = rt::now_ns(), next_status = next_shown + 1'000'000'000, last_frame_ns = -1;
  graph::report_ready();
  while (!graph::stop_requested()) {
    if (graph::wait_readable(in.socket(), next_shown) && frames.receive(frame, 0)) {
      std::uint32_t bits = 0;
      for (int i = 0; i < std::min(pins, frame.level_size()); ++i) bits |= frame.level(i) > 0.5f ? 1u << i : 0u;
      last_frame_ns = rt::now_ns();
      watchdog.update(false, last_frame_ns);
      device_->write(last_frame_ns, bits);
      frame_seq = frame.header().seq();
      ++applied;
    }
    const std::int64_t now = rt::now_ns();
    // frames stopped (after the first): every pin down until the next one
    if (last_frame_ns >= 0 && !watchdog.tripped() && now - last_frame_ns > watchdog_ns) {
      watchdog.update(true, now);
      device_->write(now, 0u);
    }
    if (now < next_shown) continue;
    next_shown += period;
    device_->shown(now, levels, pins);
    graph::fill(shown, device_->rows(), device_->cols(), levels, frame_seq);
    shown.mutable_header()->set_stamp_ns(now);
    shown_pub.publish(shown);
    if (now >= next_status) {
      next_status += 1'000'000'000;
      graph::fill(status, name, rt::LoopSummary{.rate_hz = shown_rate_hz_}, 0, "");
      graph::add_counters(status, out, &in);
      watchdog.update(watchdog.tripped(), now);
      watchdog.fill(status);
      status_pub.publish(status);
    }
  }
  device_->deactivate();  // every pin down
  graph::say(name, std::to_string(applied) + " frames applied; frames lost (seq gaps): " + std::to_string(frames.counters().lost) + "; " +
                       watchdog.summary() + "; pins lowered.");
  return 0;
}

}  // namespace enact::node
