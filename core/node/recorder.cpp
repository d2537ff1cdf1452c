#include "core/node/recorder.h"

#include "core/config/lists.h"
#include "core/config/yaml.h"
#include "core/graph/node.h"

namespace enact::node {

const NodeKind kLogger{.executable = "enact-logger", .default_name = "logger", .help = R"(usage: enact-logger [--name NAME] --param NAME=VALUE...

Records the graph's traffic to an MCAP file (enact record is the same from the shell).

To record a graph from its first tick, list the logger before the drivers in the launch
file and give the clock master `observers: 1` (docs/recording-and-replay.md).

parameters (--param NAME=VALUE):
)"};

const NodeKind kFoxglove{.executable = "enact-foxglove", .default_name = "foxglove", .help = R"(usage: enact-foxglove [--name NAME] --param NAME=VALUE...

Serves the graph to Foxglove (WebSocket, foxglove.websocket.v1): every topic with its
Protobuf schema, and foxglove/scene (foxglove.SceneUpdate) for the 3D panel.

parameters (--param NAME=VALUE):
)"};

Logger::Logger(Host& host) : host_(host) {
  graph::Params& p = host.params();
  options_.output = p.text("output");
  options_.topics = config::split_commas(p.text("topics"));
  options_.regex = p.text("regex");
  options_.exclude = p.text("exclude");
  options_.writer.compression = record::parse_compression(p.text("compression"));
  options_.writer.chunk_duration_ns = static_cast<std::int64_t>(p.number("chunk_duration_s") * 1e9);
  options_.split_size_mb = p.number("split_size_mb");
  options_.split_duration_s = p.number("split_duration_s");
  options_.attach = p.text("attach");
  options_.keys = bus::client_keys("", "");
  options_.wait_s = p.number("wait_s");
}

int Logger::run() {
  host_.open(0);
  host_.announce();
  graph::Logger logger(options_);
  logger.attach();
  graph::report_ready();
  const std::string& name = host_.name();
  graph::say(name, "recording " + std::string(options_.topics.empty() ? "every topic" : host_.params().text("topics")) + " to " + options_.output);
  try {
    logger.run([] { return graph::stop_requested(); });
  } catch (...) {
    logger.close();  // whatever stopped it, what was recorded is closed whole
    throw;
  }
  logger.close();
  graph::say(name, "closed " + logger.files().back() + "\n" + graph::format(logger.report()));
  if (!logger.write_failure().empty()) graph::say(name, graph::format_write_failure(logger));
  return logger.write_failure().empty() ? 0 : 1;
}

Foxglove::Foxglove(Host& host) : host_(host) {
  graph::Params& p = host.params();
  options_.port = p.integer("port");
  options_.host = p.text("host");
  options_.max_rate_hz = p.number("max_rate_hz");
  options_.keys = bus::client_keys("", "");
}

int Foxglove::run() {
  options_.attach = graph::attach_endpoint(host_.params().has("attach") ? host_.params().text("attach") : "");
  host_.open(0);
  host_.announce();
  foxglove::Bridge bridge(options_);
  graph::report_ready();
  graph::say(host_.name(), foxglove::describe(bridge, options_));
  const bool stopped = bridge.run([] { return graph::stop_requested(); });
  graph::say(host_.name(), foxglove::format(bridge.stats()));
  return stopped ? 0 : 1;
}

}  // namespace enact::node
