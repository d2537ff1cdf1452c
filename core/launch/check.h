#pragma once
// Checking a graph's nodes before anything starts: every node of this project (an enact-*
// executable, or `enact play`) is run once with --check, after substitution, exactly as it
// would be started: it checks each of its parameters as it would at start (unknown names,
// malformed or out-of-range values, missing files) and exits without binding anything.
#include <string>
#include <vector>

#include "core/launch/launch_file.h"

namespace enact::launch {

// true for a node that answers --check (enact-sim, enact-rt, enact-ffd, enact-tactile,
// enact-logger, enact-foxglove, enact play)
bool checkable(const NodeSpec& node);

// the problems found, each "FILE:LINE: node 'NAME': what it said" (the fix included);
// empty when every node accepts its parameters
std::vector<std::string> check_nodes(const LaunchDescription& graph);

}  // namespace enact::launch
