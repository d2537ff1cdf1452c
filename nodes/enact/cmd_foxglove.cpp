// enact foxglove: serve a running graph to Foxglove over WebSocket (core/foxglove/bridge.h).
#include <cstdio>

#include "core/foxglove/bridge.h"
#include "core/graph/stop.h"
#include "nodes/enact/attach_target.h"
#include "nodes/enact/commands.h"

namespace enact::cli {
namespace {

constexpr const char* kFoxgloveHelp = R"(usage: enact foxglove [--port 8765] [--host 127.0.0.1] [--max-rate HZ] [--graph NAME | --attach ENDPOINT]
                      [--key FILE.key --server-key FILE.pub]

Serve a running graph to Foxglove (https://foxglove.dev) over WebSocket (subprotocol
foxglove.websocket.v1), like foxglove_bridge does for ROS 2. Foxglove sees every topic of the
graph with its Protobuf schema, and foxglove/scene (foxglove.SceneUpdate) for its 3D panel:
the bridge as boxes, the floor, the body's 4 x 4 grid red where in contact, the force arrow.
Open: Foxglove > Open connection > Foxglove WebSocket > ws://127.0.0.1:8765, then
Layout > Import from file > docs/foxglove-layout.json.
  --port       WebSocket port (0: any free port; default 8765)
  --host       where it listens (default 127.0.0.1, this machine only)
  --max-rate   topics faster than this (the loop-rate ones) reach each client at most at
               this rate, Hz (default 100); a client that cannot keep up loses messages:
               the graph never waits for it
Foxglove's Parameters panel lists every parameter of the graph and sets the live ones, and its
Publish panel may send param/set (enact.msgs.ParamUpdate, in json or protobuf), both checked
and answered as enact param set is, only when the graph and this server are reachable from
this machine alone. Messages carry wall-clock times. Runs until Ctrl-C; when the graph stops,
it waits for a graph of the same name and follows it (attached by --attach to an endpoint no
graph here has: it ends, exit 1).
In a launch file: a node with exec: enact-foxglove (parameters: enact-foxglove --help).
)";

}  // namespace

int foxglove_bridge(int argc, char** argv) {
  const Args a = parse(argc, argv, 2, attach_options({"port", "host", "max-rate"}), {});
  Attached graph;
  if (const auto code = start_attached(a, "foxglove", kFoxgloveHelp, "", {}, a.positional.empty(), graph)) return *code;
  foxglove::BridgeOptions o;
  o.keys = graph.keys;
  o.attach = graph.endpoint;
  o.graph_name = graph.name;
  o.port = static_cast<int>(a.number("port", o.port));
  o.host = a.get("host", o.host);
  o.max_rate_hz = a.number("max-rate", o.max_rate_hz);
  if (o.port < 0 || o.port > 65535) throw UsageError("--port must be 0-65535");
  if (o.max_rate_hz <= 0.0) throw UsageError("--max-rate must be > 0");
  foxglove::Bridge bridge(o);
  std::fprintf(stderr, "enact foxglove: %s\n", foxglove::describe(bridge, o).c_str());
  const bool stopped = bridge.run([] { return graph::stop_requested(); });
  std::fprintf(stderr, "enact foxglove: %s\n", foxglove::format(bridge.stats()).c_str());
  return stopped ? 0 : 1;
}

}  // namespace enact::cli
