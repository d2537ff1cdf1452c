#include "core/launch/realtime.h"

#include <cstdio>
#include <ostream>

#include "core/config/env.h"
#include "core/rt/probe.h"

namespace enact::launch {

std::unique_ptr<rt::LauncherProfile> apply_realtime(LaunchDescription& graph, std::ostream& log) {
  // simulated time: every node takes the graph clock from its environment; the loop ticks
  // back to back and has no deadline to hold, so the profile is off (a SCHED_FIFO thread
  // that never sleeps would starve the observers on its CPU)
  if (graph.clock == rt::GraphClock::simulated) {
    for (NodeSpec& n : graph.nodes) n.env.push_back({env::kClock, rt::to_string(graph.clock), graph.clock_source});
    graph.realtime.enabled = false;
    log << "enact launch: clock simulated (" << graph.clock_source << "): the loop ticks as fast as the machine goes; no real-time profile\n";
  }
  // the loop's I/O threads carry the loop only when its hop is forced onto ZeroMQ
  for (const NodeSpec& n : graph.nodes) {
    for (const Param& p : n.params) graph.realtime.io_with_loop |= p.name == "loop_transport" && p.value == "zeromq";
  }
  // the machine's figures the loops wait by: measured once per boot, before the profile
  // confines the launcher to its CPUs (the probe measures across every CPU)
  if (graph.realtime.enabled) {
    const rt::MachineProbe probe = rt::cached_probe();
    char line[256];
    std::snprintf(line, sizeof line, "this machine wakes a sleeping thread %.1f us late (p99), a pipe round trip on one CPU takes %.1f us (p50): enact doctor explains it",
                  static_cast<double>(probe.sleep_late.p99_ns) * 1e-3, static_cast<double>(probe.pipe_same_cpu.p50_ns) * 1e-3);
    log << "enact launch: " << line << "\n";
  }
  auto profile = std::make_unique<rt::LauncherProfile>(graph.realtime);
  for (NodeSpec& n : graph.nodes) {
    if (profile->in_loop(n.name)) n.env.push_back({env::kRtProfile, profile->node(n.name).to_env(), "the launch file's realtime: entry"});
  }
  log << "enact launch: " << profile->summary() << "\n";
  return profile;
}

}  // namespace enact::launch
