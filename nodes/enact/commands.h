#pragma once
// The subcommands of the `enact` command line; each returns the process exit code.
#include <string>

#include "core/bus/client.h"
#include "core/replay/replay.h"
#include "msgs/graph.pb.h"
#include "nodes/enact/args.h"

namespace enact::cli {

// what `enact --version` prints and a sweep's manifest records (version.cpp): "enact 0.1.0",
// and the git commit this enact was built from (its hex digits, "-dirty" after them when
// tracked files differed from it; "unknown" when built outside git, e.g. from a tarball)
const char* version();
const char* git_commit();

int check(int argc, char** argv);
int simulate(int argc, char** argv);
int path(int argc, char** argv);
int bench(int argc, char** argv);  // in enact-bench
int run_bench(int argc, char** argv);  // enact bench: runs enact-bench
int bench_loop(int argc, char** argv);
int bench_record(int argc, char** argv);
int launch(int argc, char** argv);
int topic(int argc, char** argv);
int record(int argc, char** argv);
int info(int argc, char** argv);
int export_csv(int argc, char** argv);
int recover(int argc, char** argv);
int play(int argc, char** argv);
int resim(int argc, char** argv);
int devices(int argc, char** argv);
int param(int argc, char** argv);
int graph_list(int argc, char** argv);
int foxglove_bridge(int argc, char** argv);
int doctor(int argc, char** argv);
int node(int argc, char** argv);
int keys(int argc, char** argv);

// how enact resim and enact metrics replay a recording: the recorded scene and model, the
// recorded loop's stages made again (their libraries: --library PATH, taken from argv, first;
// else as recorded)
graph::ResimOptions replay_options(int& argc, char** argv);

// the GraphInfo of the graph at `endpoint`, attached with `keys` (UsageError when none answers within 3 s)
msgs::GraphInfo graph_info(const std::string& endpoint, const bus::ClientKeys& keys);
// the message type of `topic` in `info` (UsageError naming the topics, and the closest, if absent)
std::string type_of(const msgs::GraphInfo& info, const std::string& topic);
// a topic as the graph names it: a leading '/' (ROS 2 habit) removed
std::string topic_name(const std::string& given);
// enact topic info TOPIC (type, publishers, rate) or bw TOPIC (bytes per second)
int topic_info_or_bw(const std::string& endpoint, const bus::ClientKeys& keys, const std::string& topic, bool bw, double duration_s);
// enact export FILE --foxglove OUT.mcap (from export_csv)
int export_foxglove(const Args& a);
int experiment_run(int argc, char** argv);
int sweep_run(int argc, char** argv);
int metrics(int argc, char** argv);
int share(int argc, char** argv);

}  // namespace enact::cli
