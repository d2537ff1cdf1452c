#pragma once
// A running graph's session (DESIGN.md, "The graph as one mechanism"): what `enact launch`,
// every `enact experiment` trial and `enact play` set up the same way. It owns
//   - the graph's temporary folder (/tmp/enact-graph-XXXXXX: the nodes' ipc sockets, and a
//     "launcher" file naming this process, so that a later session removes it if this one
//     is killed with -9),
//   - the attach point, with its inbound path (param/set from observers to the nodes) and
//     the latched state topics (graph/topics, task/state),
//   - the graph's entry in the per-user registry (registry.h), under its name,
//   - the environment of its processes ($ENACT_GRAPH_DIR, $ENACT_ATTACH, $ENACT_GRAPH; with
//     an access file, $ENACT_KEY and $ENACT_SERVER_KEY: the key of the graph's own observers),
//   - a supervisor run that a stop() from any thread ends in order.
// The topics come from the nodes themselves: each declares what it publishes on its ready
// pipe (graph::announce_topics, core/graph/launcher_pipe.h), and the session lists them in GraphInfo.
#include <atomic>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "core/bus/access.h"
#include "core/bus/attach.h"
#include "core/bus/client.h"
#include "core/session/registry.h"
#include "core/graph/temp_folder.h"
#include "core/launch/launch_file.h"
#include "core/launch/supervisor.h"

namespace enact::graph {

struct SessionOptions {
  // where observers attach (loopback, a free port, by default)
  std::string bind_endpoint = bus::kLoopbackAnyPort;
  bool allow_remote = false;
  // who may attach (bus::load_access; enact launch --access); none: anyone who reaches the
  // endpoint. The graph's own observers (enact-logger in the launch file, the launcher) get
  // a key of their own, role observe, in the graph's folder
  std::optional<bus::Access> access;
  // a running graph has the name already: take NAME-2, NAME-3, ... (a default name) rather
  // than refuse (a name the user gave)
  bool numbered = false;
  // the session will run a supervisor (block its signals first: enact launch, trials); a
  // player keeps its own stop handlers
  bool supervised = true;
  // the CPUs the graph's real-time loop is pinned to, for the registry ("": none): the next
  // graph places its loop elsewhere (rt::GraphProfile::other_loops)
  std::string loop_cpus;
};

class GraphSession {
 public:
  // sets everything up and registers graph `name` (from `launch_file`, shown in the
  // registry). Throws config::Error for a name already running or a bad attach endpoint.
  GraphSession(const std::string& name, const std::string& launch_file, const SessionOptions& options = {});
  ~GraphSession();
  GraphSession(const GraphSession&) = delete;
  GraphSession& operator=(const GraphSession&) = delete;

  const std::string& name() const { return registration_.entry().name; }
  const std::string& folder() const { return folder_.path(); }
  const std::string& endpoint() const { return attach_.endpoint(); }
  bus::AttachPoint& attach() { return attach_; }

  // where node `node` of this graph publishes (ipc in the graph's folder)
  std::string node_endpoint(const std::string& node) const;
  // the environment of the graph's processes
  std::vector<launch::Param> environment() const;
  // the keys of the graph's own observers (none without an access file)
  bus::ClientKeys own_keys() const;

  // runs `graph` under the supervisor (launch::supervise: its exit code) until it ends, a
  // stop signal, or stop(); the nodes' publishers are connected to the attach point and the
  // topics they declare listed. options.env gets environment() first.
  int run(const launch::LaunchDescription& graph, const std::string& launch_path, launch::SupervisorOptions options, std::ostream& log);

  // ends run() in order, from any thread
  void stop() { stop_.store(true); }

 private:
  TempFolder folder_;
  bus::OwnClientFiles own_;  // the own observers' key files; empty without an access file
  bus::AttachPoint attach_;
  Registration registration_;
  std::atomic<bool> stop_{false};
};

}  // namespace enact::graph
