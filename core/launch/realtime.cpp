#include "core/launch/realtime.h"

#include <ostream>

namespace enact::launch {

std::unique_ptr<rt::LauncherProfile> apply_realtime(LaunchDescription& graph, std::ostream& log) {
  auto profile = std::make_unique<rt::LauncherProfile>(graph.realtime);
  for (NodeSpec& n : graph.nodes) {
    if (profile->in_loop(n.name)) n.env.push_back({rt::kProfileEnv, profile->node(n.name).to_env()});
  }
  log << "enact launch: " << profile->summary() << "\n";
  return profile;
}

}  // namespace enact::launch
