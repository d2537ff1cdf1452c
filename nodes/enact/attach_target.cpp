#include "nodes/enact/attach_target.h"

#include <algorithm>
#include <cstdio>
#include <iostream>

#include "core/config/suggest.h"
#include "core/graph/stop.h"

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

std::set<std::string> attach_options(std::initializer_list<std::string> own) {
  std::set<std::string> names{"graph", "attach", "wait", "key", "server-key"};
  names.insert(own);
  return names;
}

std::optional<int> start_attached(const Args& a, const std::string& tool, const char* help, const std::string& verbs,
                                  const std::vector<std::string>& known_verbs, bool well_formed, Attached& out) {
  // help asked (stdout, exit 0) or no verb given (stderr, exit 2)
  const bool asked = a.flag("help");
  if (asked || (!verbs.empty() && a.positional.empty())) {
    std::fputs(help, asked ? stdout : stderr);
    std::fputs(kAttachOptionsHelp, asked ? stdout : stderr);
    return asked ? 0 : 2;
  }
  if (!well_formed) {
    const std::string& verb = a.positional.empty() ? "" : a.positional[0];
    const bool known = std::find(known_verbs.begin(), known_verbs.end(), verb) != known_verbs.end();
    if (verbs.empty()) throw UsageError("unexpected argument '" + verb + "'");
    if (!known && !verb.empty()) throw UsageError("unknown verb '" + verb + "'" + config::did_you_mean(verb, known_verbs) + "; use: enact " + tool + " " + verbs);
    throw UsageError("use: enact " + tool + " " + verbs);
  }
  graph::install_stop_handlers();
  out.keys = attach_keys(a);
  const graph::GraphEntry entry = attach_target(a, tool);
  out.endpoint = entry.endpoint;
  out.name = entry.pid != 0 ? entry.name : "";  // a registered graph (pid 0: an endpoint alone)
  return std::nullopt;
}

bus::ClientKeys attach_keys(const Args& a) { return bus::client_keys(a.get("key"), a.get("server-key")); }

}  // namespace enact::cli
