// Inbound param/set on any payload: bytes published on the graph's inbound publisher reach
// the simulator's ParamPort, which refuses what it must (acked), plans the rest; the
// simulator applies every accepted change between steps and keeps stepping with finite forces.
#include <cmath>
#include <cstdlib>
#include <string>

#include "core/bus/bytes.h"
#include "core/bus/typed.h"
#include "core/graph/graph_dir.h"
#include "core/params/param_bus.h"
#include "core/graph/topics.h"
#include "core/sim/simulator.h"
#include "tests/fuzz/fuzz.h"
#include "tests/support/test_util.h"

namespace {

using namespace enact;

// a graph folder of this process, set before any endpoint is made
std::string graph_dir() {
  static const test::TempDir dir;
  setenv("ENACT_GRAPH_DIR", dir.path().c_str(), 1);
  return dir.path();
}

struct Graph {
  std::string dir = graph_dir();
  sim::Simulator simulator;
  bus::BytePublisher inbound{graph::node_endpoint(graph::kInboundNode), {.node = graph::kInboundNode}};
  bus::BytePublisher out{graph::node_endpoint("sim"), {.node = "sim"}};
  bus::Publisher<msgs::TaskEvent> events{out, "task/event"};
  std::unique_ptr<graph::ParamPort> port;
  std::int64_t time_ns = 0;

  Graph() {
    sim::SimParams p;
    p.scene = test::source_path("launch/scenes/bridge.yaml");
    simulator.configure(p);
    simulator.activate(0);
    port = std::make_unique<graph::ParamPort>(simulator, "sim", out, events);
    while (!inbound.has_subscribers("param/set")) usleep(1000);
  }

  std::uint64_t seen() const {
    const bus::TopicCounters c = port->subscriber().counters("param/set");
    return c.received + c.malformed;
  }

  // steps while the request travels; applies what the port passes on
  void deliver(const std::uint8_t* data, std::size_t size) {
    const std::uint64_t before = seen();
    inbound.send("param/set", msgs::ParamUpdate::descriptor()->full_name(), data, size);
    for (int waited = 0; seen() == before && waited < 2000; ++waited) {
      step();
      usleep(500);
    }
    // every request on param/set is counted, received or refused
    if (seen() == before) __builtin_trap();
    for (int i = 0; i < 20; ++i) step();
  }

  std::uint64_t state_seq = 0;

  void step() {
    while (const auto change = port->next()) port->applied(simulator.apply(*change, time_ns));
    time_ns += 200'000;
    const sim::StepOutput& o = simulator.step(time_ns, {0.0, 0.0, 0.02});
    port->stepped(simulator.steps(), ++state_seq, time_ns);
    if (!std::isfinite(o.force_n.x) || !std::isfinite(o.force_n.y) || !std::isfinite(o.force_n.z)) __builtin_trap();
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static Graph graph_;
  graph_.deliver(data, size);
  return 0;
}
