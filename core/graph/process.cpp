#include "core/graph/process.h"

#include <cstdio>
#include <cstdlib>

#include "core/bus/context.h"
#include "core/config/env.h"
#include "core/config/yaml.h"
#include "core/rt/profile.h"

namespace enact::graph {
namespace {

bool g_loop_cpu_own = false;

}  // namespace

void apply_rt_profile(const std::string& node) {
  const char* text = std::getenv(env::kRtProfile);
  if (!text) return;
  const rt::NodeProfile profile = rt::NodeProfile::from_env(text);
  const rt::NodeProfileReport report = rt::apply_node_profile(profile);
  g_loop_cpu_own = report.pinned && profile.sharing == 1;
  bus::set_io_threads({report.io_cpus, report.io_fifo_priority});
  say(node, report.summary());
}

bool loop_cpu_own() { return g_loop_cpu_own; }

rt::GraphClock graph_clock() {
  const char* text = std::getenv(env::kClock);
  if (!text) return rt::GraphClock::real;
  const auto clock = rt::parse_clock(text);
  if (!clock) throw config::Error(std::string(env::kClock) + "='" + text + "' names no clock\n  fix: real or simulated (the launcher sets it from the launch file's clock: entry or --clock)");
  return *clock;
}

void say(const std::string& node, const std::string& text) {
  std::fprintf(stderr, "%s: %s\n", node.c_str(), text.c_str());
  std::fflush(stderr);
}

}  // namespace enact::graph
