// enact-foxglove: the Foxglove bridge as a node of a launch file (enact foxglove is the same
// from the shell). It attaches through the graph's attach point ($ENACT_ATTACH, set by
// `enact launch`) and serves Foxglove over WebSocket until SIGINT / SIGTERM.
#include <cstdio>
#include <cstdlib>

#include "core/config/yaml.h"
#include "core/foxglove/bridge.h"
#include "core/graph/node.h"
#include "core/graph/params.h"

namespace {

using namespace enact;

constexpr const char* kHelp = R"(usage: enact-foxglove [--name NAME] --param NAME=VALUE...

Serves the graph to Foxglove (WebSocket, foxglove.websocket.v1): every topic with its
Protobuf schema, and foxglove/scene (foxglove.SceneUpdate) for the 3D panel.

parameters:
  port=8765          WebSocket port (0: any free port)
  host=127.0.0.1     where it listens (clients may publish param/set only on loopback)
  max_rate_hz=100    per client, on topics that run faster (the loop-rate ones)
  attach=            attach endpoint (default: $ENACT_ATTACH); keys: $ENACT_KEY and
                     $ENACT_SERVER_KEY (set by `enact launch --access`)
)";

int run(int argc, char** argv) {
  graph::NodeArgs args = graph::parse_node_args(argc, argv, "foxglove");
  if (args.help) {
    std::fputs(kHelp, stdout);
    return 0;
  }
  graph::Params& p = args.params;
  enact::foxglove::BridgeOptions o;
  o.port = static_cast<int>(p.number("port", o.port));
  o.host = p.text("host", o.host);
  o.max_rate_hz = p.number("max_rate_hz", o.max_rate_hz);
  const char* env = std::getenv("ENACT_ATTACH");
  o.attach = p.text("attach", env ? env : "");
  o.keys = enact::bus::client_keys("", "");
  p.refuse_unread({"port", "host", "max_rate_hz", "attach"});
  if (o.attach.empty()) throw config::Error(args.name + ": no attach endpoint\n  fix: run it from `enact launch`, or give attach=ENDPOINT");
  if (o.port < 0 || o.port > 65535 || o.max_rate_hz <= 0.0) throw config::Error(args.name + ": port must be 0-65535 and max_rate_hz > 0\n  fix: e.g. port=8765 max_rate_hz=100");

  graph::install_stop_handlers();
  enact::foxglove::Bridge bridge(o);
  graph::report_ready();
  graph::say(args.name, enact::foxglove::describe(bridge, o));
  bridge.run([] { return graph::stop_requested(); });
  graph::say(args.name, enact::foxglove::format(bridge.stats()));
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return enact::graph::node_main("enact-foxglove", run, argc, argv); }
