// enact launch FILE: run a graph of nodes from a YAML launch file.
#include <cstdio>
#include <iostream>

#include <filesystem>
#include <optional>

#include "core/session/registry.h"
#include "core/session/session.h"
#include "core/session/status_watch.h"
#include "core/params/node_params.h"
#include "core/launch/launch_file.h"
#include "core/launch/realtime.h"
#include "core/rt/profile.h"
#include "core/launch/supervisor.h"
#include "core/replay/replay.h"
#include "core/rt/clock.h"
#include "nodes/enact/commands.h"

namespace enact::cli {
namespace {

constexpr const char* kLaunchHelp = R"(usage: enact launch FILE [--arg NAME=VALUE]... [--name NAME] [--duration S] [--ready-timeout S]
                         [--clock real|simulated] [--check] [--attach ENDPOINT] [--access ACCESS.yaml [--allow-remote]]

Run a graph from a YAML launch file (format: docs/launch-files.md): start its nodes
and containers in order, each ready before the next, supervise them, and stop them in
reverse order on Ctrl-C / SIGTERM, after --duration, or when a required process exits.
The whole file is checked first (unknown keys, wrong types, missing executables: file:line
and the fix), then every node's parameters after substitution (each node of this project
is run once with --check: unknown names, malformed or out-of-range values, missing files,
named with the node's launch file line); nothing starts when something is wrong.
Exit status: 0 after a requested stop or when a required process finished with status 0
(e.g. `enact play` at the end of a recording); 1 when a required process failed or was
killed, or a process did not become ready; 2 for bad arguments.

options:
  --arg NAME=VALUE   set a launch argument (repeatable)
  --name NAME        the graph's name (default: the launch file's stem, numbered -2, -3, ...
                     when a graph of that name runs already); tools attach to it
                     with --graph NAME; `enact graph list` shows the running graphs
  --duration S       stop the graph cleanly after S seconds
  --ready-timeout S  how long each process may take to report ready (default 10)
  --clock CLOCK      the graph clock, over the launch file's clock: entry: real (the loop
                     ticks on the deadlines of rate_hz) or simulated (it ticks as soon as a
                     tick is done, as fast as the machine goes; simulated devices only)
  --check            load and print the plan, have every node check its parameters (as it
                     always does before anything starts), start nothing
  --attach ENDPOINT  where observers attach (default tcp://127.0.0.1:*: loopback, a free
                     port; printed, and kept in the graph's registry entry)
  --access FILE      who may attach (docs/remote-access.md; launch/access.example.yaml):
                     the attach point then takes only the listed keys, encrypted (CURVE),
                     and param/set only from operate keys, each at its rate limit
  --allow-remote     allow an --attach endpoint other machines can reach (needs --access)

A launch file's realtime: entry (every shipped graph has one) pins the loop's processes
together, holds the CPU latency request and orders SCHED_FIFO before anything starts; what
is refused is said once and the graph runs anyway (docs/concepts.md, "Real-time profile").
The nodes' sockets live in a fresh folder /tmp/enact-graph-XXXXXX ($ENACT_GRAPH_DIR),
removed at the end (or by the next launch, if this one was killed).
When the launcher dies (even by SIGKILL), every node gets SIGTERM and stops cleanly. A node
whose node/status stops for 3 s while the others report hangs: it is stopped, as for an exit.
)";

// --arg NAME=VALUE (it may repeat) taken out of argv into `launch_args`; the rest returned
std::vector<char*> take_launch_args(int argc, char** argv, std::map<std::string, std::string>& launch_args) {
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
  return rest;
}

// the graph as it will start: its arguments, and each node's command line
void print_graph(const launch::LaunchDescription& graph) {
  for (const auto& arg : graph.args) std::printf("arg   %s = %s%s%s\n", arg.name.c_str(), arg.value.c_str(), arg.description.empty() ? "" : "   # ", arg.description.c_str());
  for (const auto& n : graph.nodes) {
    std::string line;
    for (const auto& word : n.argv()) line += (line.empty() ? "" : " ") + word;
    std::printf("%-5s %s%s: %s\n", n.container ? "rt" : "node", n.name.c_str(), n.required ? " (required)" : n.respawn ? " (respawn)" : "", line.c_str());
  }
  std::fflush(stdout);
}

// every node checks its parameters, as it would at start, before anything starts: the
// problems said (with the --arg a value came from); true when there is none
// a problem's text, and where a value it names came from when it does not say so itself (a
// node's own check, a file a launch argument names, does not know)
std::string with_sources(const std::string& problem, const std::map<std::string, std::string>& launch_args) {
  std::string out = problem;
  for (const auto& [arg, value] : problem.find("--arg ") != std::string::npos ? std::map<std::string, std::string>{} : launch_args) {
    if (!value.empty() && problem.find(value) != std::string::npos) out += "\n  (the value comes from --arg " + arg + "=" + value + ")";
  }
  return out;
}

bool graph_accepted(const launch::LaunchDescription& graph, const std::map<std::string, std::string>& launch_args) {
  const std::vector<std::string> problems = graph::check_graph(graph);
  for (const std::string& p : problems) std::fprintf(stderr, "enact launch: %s\n", with_sources(p, launch_args).c_str());
  if (problems.empty()) return true;
  std::fprintf(stderr, "enact launch: nothing started (%zu parameter problem%s)\n", problems.size(), problems.size() == 1 ? "" : "s");
  return false;
}

}  // namespace

int launch(int argc, char** argv) {
  // --arg may repeat: collect them before the generic parser
  std::map<std::string, std::string> launch_args;
  std::vector<char*> rest = take_launch_args(argc, argv, launch_args);
  const Args a = parse(static_cast<int>(rest.size()), rest.data(), 2, {"duration", "ready-timeout", "attach", "name", "access", "clock"}, {"check", "allow-remote"});
  if (a.flag("help")) {
    std::fputs(kLaunchHelp, stdout);
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
  const std::string file = find_file(a.positional[0]);
  const std::string name = a.get("name", std::filesystem::path(file).stem().string());
  if (name.empty()) throw UsageError("--name needs a name");
  // $(recorded ARG NAME): the recorded simulator's files, copied into a folder kept while the
  // graph runs (this process outlives its nodes)
  launch::set_recorded_lookup([](const std::string& recording, const std::string& param) {
    static graph::TempFolder files;
    return graph::recorded_sim_param(find_file(recording), param, files);
  });
  launch::LaunchDescription graph;
  try {
    graph = launch::load_launch(file, launch_args);
  } catch (const config::Error& e) {
    // a launch argument's value the file could not take (a recording that is not there): a
    // parameter problem, said as the nodes' own are; the file's own errors go on as they are
    const std::string said = with_sources(e.what(), launch_args);
    if (said == e.what()) throw;
    std::fprintf(stderr, "enact launch: error: %s\nenact launch: nothing started (1 parameter problem)\n", said.c_str());
    return 1;
  }
  if (const auto clock = clock_option(a)) launch::choose_clock(graph, *clock);
  print_graph(graph);
  if (!graph_accepted(graph, launch_args)) return 1;
  if (a.flag("check")) {
    std::printf("check: every node accepts its parameters\n");
    return 0;
  }

  // the real-time profile, before the launcher starts any thread or process (they inherit it);
  // its loop on a CPU no running graph's loop holds
  graph.realtime.other_loops = graph::running_loops();
  const auto realtime = launch::apply_realtime(graph, std::cerr);

  // the graph's session: its folder, attach point and registry entry; observers can find
  // it from now on (a node may wait for them before it is ready)
  graph::SessionOptions session_options;
  session_options.bind_endpoint = a.get("attach", session_options.bind_endpoint);
  session_options.allow_remote = a.flag("allow-remote");
  session_options.numbered = !a.has("name");
  session_options.access = std::move(access);
  session_options.loop_cpus = rt::cpu_list(realtime->loop_cpus());
  if (session_options.access) {
    const bus::Access& acc = *session_options.access;
    std::cerr << "enact launch: access from " << acc.file << ": " << acc.clients.size() << " client keys; graph key " << acc.server_public_z85 << "\n";
  }
  graph::GraphSession session(name, file, session_options);
  std::cerr << "enact launch: graph " << session.name() << ": observers attach at " << session.endpoint() << std::endl;
  // a node whose node/status stops is handled as if it had exited
  graph::StatusWatch statuses(session.endpoint(), session.own_keys());
  options.hung_nodes = [&] { return statuses.hung(rt::now_ns()); };
  options.on_ready = [&] { std::cerr << "enact launch: graph " << session.name() << " ready; observers attach at " << session.endpoint() << std::endl; };
  return session.run(graph, file, options, std::cerr);
}

}  // namespace enact::cli
