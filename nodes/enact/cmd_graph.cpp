// enact graph list: the running graphs of this user, from the registry.
#include <cstdio>

#include "core/session/registry.h"
#include "nodes/enact/commands.h"

namespace enact::cli {
namespace {

constexpr const char* kGraphHelp = R"(usage: enact graph list

The graphs of this user running on this machine: enact launch, each enact experiment trial,
enact play. One line each: name, attach endpoint, pid, start time (UTC), launch file. Tools
attach to one with --graph NAME. Entries of graphs whose process is gone (kill -9) are
removed here, with their temporary folders. Registry: /tmp/enact-<uid>/graphs.
)";

}  // namespace

int graph_list(int argc, char** argv) {
  const Args a = parse(argc, argv, 2, {}, {});
  if (a.flag("help")) {
    std::fputs(kGraphHelp, stdout);
    return 0;
  }
  if (a.positional.size() != 1 || a.positional[0] != "list") throw UsageError("use: enact graph list");
  const std::vector<graph::GraphEntry> graphs = graph::list_graphs();
  if (graphs.empty()) {
    std::printf("no graph running (registry %s)\n", graph::registry_dir().c_str());
    return 0;
  }
  std::printf("%-28s %-24s %8s  %-20s  %s\n", "name", "attach endpoint", "pid", "started", "launch file");
  for (const graph::GraphEntry& g : graphs) {
    std::printf("%-28s %-24s %8lld  %-20s  %s\n", g.name.c_str(), g.endpoint.c_str(), static_cast<long long>(g.pid), g.started.c_str(), g.launch_file.c_str());
  }
  return 0;
}

}  // namespace enact::cli
