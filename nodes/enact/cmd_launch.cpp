// enact launch FILE: run a graph of nodes from a YAML launch file.
#include <cstdio>
#include <iostream>

#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <optional>

#include "core/bus/attach.h"
#include "core/graph/logger.h"
#include "core/graph/node.h"
#include "core/graph/temp_folder.h"
#include "core/graph/topics.h"
#include "core/launch/launch_file.h"
#include "core/launch/supervisor.h"
#include "msgs/param_update.pb.h"
#include "nodes/enact/commands.h"

namespace enact::cli {
namespace {

constexpr const char* kHelp = R"(usage: enact launch FILE [--arg NAME=VALUE]... [--duration S] [--ready-timeout S] [--check]
                         [--attach ENDPOINT] [--access ACCESS.yaml [--allow-remote]]

Run a graph from a YAML launch file (format: README.md, "Launch files"): start its nodes
and containers in order, each ready before the next, supervise them, and stop them in
reverse order on Ctrl-C / SIGTERM, after --duration, or when a required process exits.
The whole file is checked first (unknown keys, wrong types, missing executables: file:line
and the fix); nothing starts when it is wrong.
Exit status: 0 after a requested stop or when a required process finished with status 0
(e.g. `enact play` at the end of a recording); 1 when a required process failed or was
killed, or a process did not become ready; 2 for bad arguments.

options:
  --arg NAME=VALUE   set a launch argument (repeatable)
  --duration S       stop the graph cleanly after S seconds
  --ready-timeout S  how long each process may take to report ready (default 10)
  --check            load and print the plan, start nothing
  --attach ENDPOINT  where observers attach (default tcp://127.0.0.1:*: loopback, a free
                     port; printed, and kept in /tmp/enact-<uid>/attach for `enact topic`)
  --access FILE      who may attach (README, "Remote access"; launch/access.example.yaml):
                     the attach point then takes only the listed keys, encrypted (CURVE),
                     and param/set only from operate keys, each at its rate limit
  --allow-remote     allow an --attach endpoint other machines can reach (needs --access)

The nodes' sockets live in a fresh folder /tmp/enact-graph-XXXXXX ($ENACT_GRAPH_DIR),
removed at the end.
)";

}  // namespace

int launch(int argc, char** argv) {
  // --arg may repeat: collect them before the generic parser
  std::map<std::string, std::string> launch_args;
  std::vector<char*> rest;
  for (int i = 0; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--arg" || a.rfind("--arg=", 0) == 0) {
      const std::string kv = a == "--arg" ? (i + 1 < argc ? argv[++i] : "") : a.substr(6);
      const std::size_t eq = kv.find('=');
      if (eq == std::string::npos || eq == 0) throw UsageError("--arg needs NAME=VALUE, got '" + kv + "'");
      launch_args[kv.substr(0, eq)] = kv.substr(eq + 1);
      continue;
    }
    rest.push_back(argv[i]);
  }
  const Args a = parse(static_cast<int>(rest.size()), rest.data(), 2, {"duration", "ready-timeout", "attach", "access"}, {"check", "allow-remote"});
  if (a.flag("help")) {
    std::fputs(kHelp, stdout);
    return 0;
  }
  if (a.positional.size() != 1) throw UsageError("give exactly one launch file");
  if (a.flag("allow-remote") && !a.has("access")) throw UsageError("--allow-remote needs --access ACCESS.yaml: without keys anyone who reaches the port could change the forces on a hand");
  std::optional<bus::Access> access;
  if (a.has("access")) access = bus::load_access(a.get("access"));
  launch::SupervisorOptions options;
  options.duration_s = a.number("duration", 0.0);
  options.ready_timeout_s = a.number("ready-timeout", options.ready_timeout_s);
  if (options.duration_s < 0.0 || options.ready_timeout_s <= 0.0) throw UsageError("--duration must be >= 0 and --ready-timeout > 0");
  const launch::LaunchDescription graph = launch::load_launch(a.positional[0], launch_args);
  for (const auto& arg : graph.args) std::printf("arg   %s = %s%s%s\n", arg.name.c_str(), arg.value.c_str(), arg.description.empty() ? "" : "   # ", arg.description.c_str());
  for (const auto& n : graph.nodes) {
    std::string line;
    for (const auto& word : n.argv()) line += (line.empty() ? "" : " ") + word;
    std::printf("%-5s %s%s: %s\n", n.container ? "rt" : "node", n.name.c_str(), n.required ? " (required)" : n.respawn ? " (respawn)" : "", line.c_str());
  }
  std::fflush(stdout);
  if (a.flag("check")) return 0;

  // the graph's folder and its attach point (observers: viewers, loggers, enact topic); the
  // attach point's thread must not receive the signals the supervisor waits for
  launch::block_supervisor_signals();
  const graph::TempFolder graph_dir("/tmp/enact-graph-");  // the graph's ipc sockets, removed at the end
  const std::string& dir = graph_dir.path();
  options.env.push_back({"ENACT_GRAPH_DIR", dir});
  bus::AttachOptions attach_options;
  attach_options.bind_endpoint = a.get("attach", attach_options.bind_endpoint);
  attach_options.allow_remote = a.flag("allow-remote");
  // with keys, the graph's own observers (enact-logger) get one too, in the private folder
  if (access) {
    const bus::OwnClientFiles own = bus::add_own_client(*access, dir, "graph:observer");
    options.env.push_back({bus::kKeyEnv, own.key});
    options.env.push_back({bus::kServerKeyEnv, own.server_key});
    std::cerr << "enact launch: access from " << access->file << ": " << access->clients.size() - 1 << " client keys; graph key " << access->server_public_z85 << "\n";
  }
  attach_options.access = std::move(access);
  // observers may send parameter changes; the nodes find them at the inbound publisher
  attach_options.inbound_endpoint = bus::ipc_endpoint(dir, graph::kInboundNode);
  attach_options.inbound_topics = {graph::kParamSet};
  bus::AttachPoint attach(std::filesystem::path(a.positional[0]).stem().string(), attach_options);
  attach.declare_topic<msgs::ParamUpdate>(graph::kParamSet, "attach");
  for (const auto& n : graph.nodes) {
    const std::string exec = std::filesystem::path(n.path).filename().string();
    const auto topics = graph::topics_of(exec);
    if (topics.empty()) continue;
    attach.add_publisher(n.name, bus::ipc_endpoint(dir, n.name));
    for (const auto& t : topics) attach.declare_topic(t.name, t.type, n.name);
  }
  attach.set_launch_info(graph::launch_info(a.positional[0], graph));
  options.env.push_back({"ENACT_ATTACH", attach.endpoint()});
  // observers can find the graph from now on (a node may wait for them before it is ready)
  std::error_code ec;
  std::filesystem::create_directories(std::filesystem::path(graph::attach_file()).parent_path(), ec);
  std::ofstream(graph::attach_file()) << attach.endpoint() << "\n";
  options.on_ready = [&] { std::cerr << "enact launch: observers attach at " << attach.endpoint() << "\n"; };
  const int code = launch::supervise(graph, options, std::cerr);
  attach.stop();
  return code;
}

}  // namespace enact::cli
