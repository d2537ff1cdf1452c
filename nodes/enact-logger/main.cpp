// enact-logger: the logger as a node of a launch file. It attaches through the graph's
// attach point ($ENACT_ATTACH, set by `enact launch`) and records to an MCAP file until
// SIGINT / SIGTERM, then closes the file (complete and indexed). `enact record` is the same
// logger from the command line.
#include <cstdio>

#include "core/config/lists.h"
#include "core/config/yaml.h"
#include "core/graph/logger.h"
#include "core/graph/node.h"
#include "core/graph/node_params.h"
#include "core/graph/param_board.h"
#include "core/graph/params.h"

namespace {

using namespace enact;

constexpr const char* kHelp = R"(usage: enact-logger [--name NAME] --param NAME=VALUE...

Records the graph's traffic to an MCAP file (enact record is the same from the shell).

To record a graph from its first tick, list the logger before the drivers in the launch
file and give the clock master `observers: 1` (docs/recording-and-replay.md).

parameters (--param NAME=VALUE):
)";

int run(int argc, char** argv) {
  graph::NodeArgs args = graph::parse_node_args(argc, argv, "logger");
  if (args.help) {
    std::fputs((kHelp + graph::help_lines(*graph::node_table("enact-logger"))).c_str(), stdout);
    return 0;
  }
  graph::Params& p = args.params;
  p.declare(*graph::node_table("enact-logger"));
  p.refuse_unknown();
  graph::LoggerOptions o;
  o.output = p.text("output");
  o.topics = config::split_commas(p.text("topics"));
  o.regex = p.text("regex");
  o.exclude = p.text("exclude");
  o.writer.compression = record::parse_compression(p.text("compression"));
  o.writer.chunk_duration_ns = static_cast<std::int64_t>(p.number("chunk_duration_s") * 1e9);
  o.split_size_mb = p.number("split_size_mb");
  o.split_duration_s = p.number("split_duration_s");
  o.attach = p.text("attach");
  o.keys = bus::client_keys("", "");
  o.wait_s = p.number("wait_s");
  if (args.check) return 0;

  graph::install_stop_handlers();
  graph::ParamBoard board(args.name);
  board.add(p, args.name);
  board.start();
  graph::Logger logger(o);
  logger.attach();
  graph::report_ready();
  graph::say(args.name, "recording " + std::string(o.topics.empty() ? "every topic" : p.text("topics")) + " to " + o.output);
  logger.run([] { return graph::stop_requested(); });
  logger.close();
  graph::say(args.name, "closed " + logger.files().back() + "\n" + graph::format(logger.report()));
  if (!logger.write_failure().empty()) graph::say(args.name, graph::format_write_failure(logger));
  return logger.write_failure().empty() ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) { return enact::graph::node_main("enact-logger", run, argc, argv); }
