#pragma once
// What a graph's GraphInfo says of how it was started (and so what its recordings keep).
#include <string>

#include "core/launch/launch_file.h"
#include "msgs/graph.pb.h"

namespace enact::graph {

// how a graph was started, for GraphInfo (and so for recordings): the launch file, its
// text, every node's parameters, and the files they name (read now; at most 1 MiB each)
msgs::GraphInfo launch_info(const std::string& launch_path, const launch::LaunchDescription& graph);

}  // namespace enact::graph
