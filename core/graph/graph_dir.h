#pragma once
// Where a graph's sockets live: its folder and each node's publisher endpoint, and which
// nodes of a starting graph have not declared their topics yet.
#include <string>
#include <vector>

#include "msgs/graph.pb.h"

namespace enact::graph {

// the graph's folder: $ENACT_GRAPH_DIR (set by `enact launch`), else /tmp/enact-<uid>
std::string graph_dir();
// where node `name` publishes: ipc://<graph_dir>/<name>.pub
std::string node_endpoint(const std::string& name);
// the nodes of the graph's launch file that publish their parameters (GraphInfo.param_nodes)
// and have not declared their topics yet (each declares all of its own at once, its
// param/values/<node> among them): a graph still starting lists only some of its topics
std::vector<std::string> nodes_not_announced(const msgs::GraphInfo& info);

}  // namespace enact::graph
