#include "nodes/enact/attach_target.h"

#include <cstdio>
#include <iostream>

#include "core/graph/node.h"

namespace enact::cli {

graph::GraphEntry attach_target(const Args& a, const std::string& tool) {
  if (a.has("graph") && a.has("attach")) throw UsageError("give --graph NAME or --attach ENDPOINT, not both");
  graph::AttachChoice choice;
  choice.graph = a.get("graph");
  choice.endpoint = a.get("attach");
  choice.wait_s = a.has("wait") ? a.number("wait", 0.0) : -1.0;
  if (a.has("wait") && choice.wait_s < 0.0) throw UsageError("--wait must be >= 0");
  try {
    const graph::GraphEntry e = graph::find_graph(choice, std::cerr, [] { return graph::stop_requested(); });
    std::fprintf(stderr, "enact %s: %s\n", tool.c_str(), graph::attached_line(e).c_str());
    return e;
  } catch (const graph::AmbiguousGraph& e) {
    throw UsageError(e.what());
  }
}

bus::ClientKeys attach_keys(const Args& a) { return bus::client_keys(a.get("key"), a.get("server-key")); }

}  // namespace enact::cli
