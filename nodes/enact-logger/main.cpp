// enact-logger: the logger as a node of a launch file. It attaches through the graph's
// attach point ($ENACT_ATTACH, set by `enact launch`) and records to an MCAP file until
// SIGINT / SIGTERM, then closes the file (complete and indexed). `enact record` is the same
// logger from the command line.
#include <cstdio>

#include "core/config/lists.h"
#include "core/config/yaml.h"
#include "core/graph/logger.h"
#include "core/graph/node.h"
#include "core/graph/params.h"

namespace {

using namespace enact;

constexpr const char* kHelp = R"(usage: enact-logger [--name NAME] --param NAME=VALUE...

Records the graph's traffic to an MCAP file (enact record is the same from the shell).

parameters:
  output=recording.mcap   file (with splitting: NAME_000.mcap, NAME_001.mcap, ...)
  topics=                 comma-separated topics to keep (empty: every topic)
  regex=  exclude=        only topics the regular expression matches / none it matches
  compression=zstd        zstd, lz4 or none
  chunk_duration_s=1      a chunk reaches the file at least this often (the most a kill -9 loses)
  split_size_mb=0  split_duration_s=0   start a new file past this size / after this long
  attach=                 attach endpoint (default: $ENACT_ATTACH)
                          keys: $ENACT_KEY and $ENACT_SERVER_KEY (set by `enact launch --access`)
  wait_s=10               how long to wait for the graph
To record a graph from its first tick, list the logger before the drivers in the launch
file and give the clock master `observers: 1` (README, "Recording and replay").
)";

int run(int argc, char** argv) {
  graph::NodeArgs args = graph::parse_node_args(argc, argv, "logger");
  if (args.help) {
    std::fputs(kHelp, stdout);
    return 0;
  }
  graph::Params& p = args.params;
  graph::LoggerOptions o;
  o.output = p.text("output", o.output);
  o.topics = config::split_commas(p.text("topics", ""));
  o.regex = p.text("regex", "");
  o.exclude = p.text("exclude", "");
  try {
    o.writer.compression = record::parse_compression(p.text("compression", "zstd"));
  } catch (const std::invalid_argument& e) {
    throw config::Error(args.name + ": " + e.what() + "\n  fix: compression=zstd");
  }
  o.writer.chunk_duration_ns = static_cast<std::int64_t>(p.number("chunk_duration_s", 1.0) * 1e9);
  o.split_size_mb = p.number("split_size_mb", 0.0);
  o.split_duration_s = p.number("split_duration_s", 0.0);
  o.attach = p.text("attach", "");
  o.keys = bus::client_keys("", "");
  o.wait_s = p.number("wait_s", 10.0);
  p.refuse_unread({"output", "topics", "regex", "exclude", "compression", "chunk_duration_s", "split_size_mb", "split_duration_s", "attach", "wait_s"});
  if (o.writer.chunk_duration_ns <= 0 || o.split_size_mb < 0.0 || o.split_duration_s < 0.0) {
    throw config::Error(args.name + ": chunk_duration_s must be > 0, split_size_mb and split_duration_s >= 0\n  fix: e.g. chunk_duration_s=1");
  }
  if (args.check) return 0;

  graph::install_stop_handlers();
  graph::Logger logger(o);
  logger.attach();
  graph::report_ready();
  graph::say(args.name, "recording " + std::string(o.topics.empty() ? "every topic" : p.text("topics", "")) + " to " + o.output);
  logger.run([] { return graph::stop_requested(); });
  logger.close();
  graph::say(args.name, "closed " + logger.files().back() + "\n" + graph::format(logger.report()));
  if (!logger.write_failure().empty()) graph::say(args.name, graph::format_write_failure(logger));
  return logger.write_failure().empty() ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) { return enact::graph::node_main("enact-logger", run, argc, argv); }
