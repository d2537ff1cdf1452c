#include "core/graph/graph_dir.h"

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include "core/bus/endpoints.h"
#include "core/config/env.h"
#include "core/graph/topics.h"

namespace enact::graph {

std::vector<std::string> nodes_not_announced(const msgs::GraphInfo& info) {
  std::vector<std::string> out;
  for (const std::string& node : info.param_nodes()) {
    const std::string board = kParamValues + node;
    if (std::none_of(info.topics().begin(), info.topics().end(), [&](const auto& t) { return t.name() == board; })) out.push_back(node);
  }
  return out;
}

std::string graph_dir() {
  const char* dir = std::getenv(env::kGraphDir);
  std::string out = dir && *dir ? dir : "/tmp/enact-" + std::to_string(getuid());
  std::error_code ec;
  std::filesystem::create_directories(out, ec);
  return out;
}

std::string node_endpoint(const std::string& name) { return bus::ipc_endpoint(graph_dir(), name); }

}  // namespace enact::graph
