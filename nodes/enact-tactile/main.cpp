// enact-tactile: the tactile display driver of a distributed graph. It applies each
// TactileFrame to the pins and publishes what they physically show (after the cells' rise
// time) on tactile/shown. On stop it lowers every pin, and when frames stop coming for
// longer than watchdog_s (the simulator hangs or died) too, until they come again.
#include <cstdio>

#include "core/bus/typed.h"
#include "core/config/yaml.h"
#include "core/graph/components.h"
#include "core/graph/messages.h"
#include "core/graph/node.h"
#include "core/graph/node_params.h"
#include "core/graph/param_board.h"
#include "core/graph/topics.h"
#include "core/graph/watchdog_log.h"
#include "core/rt/clock.h"

namespace {

using namespace enact;

constexpr const char* kHelp = R"(usage: enact-tactile [--name NAME] --param NAME=VALUE...

The tactile display driver of a distributed graph: applies tactile/frame, publishes
tactile/shown at shown_rate_hz and node/status at 1 Hz; lowers every pin on stop, and
while no frame came for longer than watchdog_s (each episode said and counted).

parameters (--param NAME=VALUE):
)";

int run(int argc, char** argv) {
  graph::NodeArgs args = graph::parse_node_args(argc, argv, "tactile");
  if (args.help) {
    std::fputs((kHelp + graph::help_lines(*graph::node_table("enact-tactile"))).c_str(), stdout);
    return 0;
  }
  graph::Params& p = args.params;
  p.declare(*graph::node_table("enact-tactile"));
  p.refuse_unknown();
  auto device = graph::make_tactile_device(p);
  const std::string sim_node = p.text("sim_node");
  const double shown_rate_hz = p.number("shown_rate_hz");
  const double watchdog_s = p.number("watchdog_s");
  if (args.check) return 0;

  graph::install_stop_handlers();
  bus::BytePublisher out(graph::node_endpoint(args.name), {.node = args.name, .send_hwm = 1000});
  bus::Publisher<msgs::TactileShown> shown_pub(out, graph::kTactileShown);
  bus::Publisher<msgs::NodeStatus> status_pub(out, graph::kNodeStatus);
  graph::announce_topics(out);
  graph::ParamBoard board(args.name);
  board.add(p, args.name);
  board.start();
  bus::ByteSubscriber in;
  bus::Subscriber<msgs::TactileFrame> frames(in, graph::kTactileFrame);
  in.connect(graph::node_endpoint(sim_node));

  const int pins = device->rows() * device->cols();
  float levels[32] = {};
  msgs::TactileFrame frame;
  msgs::TactileShown shown;
  msgs::NodeStatus status;
  std::uint64_t frame_seq = 0, applied = 0;
  const std::int64_t period = static_cast<std::int64_t>(1e9 / shown_rate_hz);
  const std::int64_t watchdog_ns = static_cast<std::int64_t>(watchdog_s * 1e9);
  graph::WatchdogLog watchdog(args.name, "no tactile/frame: pins lowered");
  device->activate();
  std::int64_t next_shown = rt::now_ns(), next_status = next_shown + 1'000'000'000, last_frame_ns = -1;
  graph::report_ready();
  while (!graph::stop_requested()) {
    if (graph::wait_readable(in.socket(), next_shown) && frames.receive(frame, 0)) {
      std::uint32_t bits = 0;
      for (int i = 0; i < std::min(pins, frame.level_size()); ++i) bits |= frame.level(i) > 0.5f ? 1u << i : 0u;
      last_frame_ns = rt::now_ns();
      watchdog.update(false, last_frame_ns);
      device->write(last_frame_ns, bits);
      frame_seq = frame.header().seq();
      ++applied;
    }
    const std::int64_t now = rt::now_ns();
    // frames stopped (after the first): every pin down until the next one
    if (last_frame_ns >= 0 && !watchdog.tripped() && now - last_frame_ns > watchdog_ns) {
      watchdog.update(true, now);
      device->write(now, 0u);
    }
    if (now < next_shown) continue;
    next_shown += period;
    device->shown(now, levels, pins);
    graph::fill(shown, device->rows(), device->cols(), levels, frame_seq);
    shown.mutable_header()->set_stamp_ns(now);
    shown_pub.publish(shown);
    if (now >= next_status) {
      next_status += 1'000'000'000;
      graph::fill(status, args.name, rt::LoopSummary{.rate_hz = shown_rate_hz}, 0, "");
      graph::add_counters(status, out, &in);
      watchdog.update(watchdog.tripped(), now);
      watchdog.fill(status);
      status_pub.publish(status);
    }
  }
  device->deactivate();  // every pin down
  graph::say(args.name, std::to_string(applied) + " frames applied; frames lost (seq gaps): " + std::to_string(frames.counters().lost) +
                            "; " + watchdog.summary() + "; pins lowered.");
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return enact::graph::node_main("enact-tactile", run, argc, argv); }
