// enact-foxglove: the Foxglove bridge as a node of a launch file (enact foxglove is the same
// from the shell). It attaches through the graph's attach point ($ENACT_ATTACH, set by
// `enact launch`) and serves Foxglove over WebSocket until SIGINT / SIGTERM.
#include <cstdio>
#include <cstdlib>

#include "core/config/yaml.h"
#include "core/foxglove/bridge.h"
#include "core/graph/node.h"
#include "core/graph/node_params.h"
#include "core/graph/param_board.h"
#include "core/graph/params.h"

namespace {

using namespace enact;

constexpr const char* kHelp = R"(usage: enact-foxglove [--name NAME] --param NAME=VALUE...

Serves the graph to Foxglove (WebSocket, foxglove.websocket.v1): every topic with its
Protobuf schema, and foxglove/scene (foxglove.SceneUpdate) for the 3D panel.

parameters (--param NAME=VALUE):
)";

int run(int argc, char** argv) {
  graph::NodeArgs args = graph::parse_node_args(argc, argv, "foxglove");
  if (args.help) {
    std::fputs((kHelp + graph::help_lines(*graph::node_table("enact-foxglove"))).c_str(), stdout);
    return 0;
  }
  graph::Params& p = args.params;
  p.declare(*graph::node_table("enact-foxglove"));
  p.refuse_unknown();
  enact::foxglove::BridgeOptions o;
  o.port = p.integer("port");
  o.host = p.text("host");
  o.max_rate_hz = p.number("max_rate_hz");
  const char* env = std::getenv("ENACT_ATTACH");
  o.attach = p.has("attach") ? p.text("attach") : env ? env : "";
  o.keys = enact::bus::client_keys("", "");
  if (args.check) return 0;
  if (o.attach.empty()) throw config::Error(args.name + ": no attach endpoint\n  fix: run it from `enact launch`, or give attach=ENDPOINT");

  graph::install_stop_handlers();
  graph::ParamBoard board(args.name);
  board.add(p, args.name);
  board.start();
  enact::foxglove::Bridge bridge(o);
  graph::report_ready();
  graph::say(args.name, enact::foxglove::describe(bridge, o));
  bridge.run([] { return graph::stop_requested(); });
  graph::say(args.name, enact::foxglove::format(bridge.stats()));
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return enact::graph::node_main("enact-foxglove", run, argc, argv); }
