#pragma once
// What every node process shares: where the graph's sockets live, stopping on SIGINT /
// SIGTERM, waiting on a socket with a sub-millisecond deadline, and its NodeStatus.
#include <cstdint>
#include <string>

#include <zmq.hpp>

#include "core/bus/bytes.h"
#include "msgs/node_status.pb.h"

namespace enact::graph {

// the graph's folder: $ENACT_GRAPH_DIR (set by `enact launch`), else /tmp/enact-<uid>
std::string graph_dir();
// where node `name` publishes: ipc://<graph_dir>/<name>.pub
std::string node_endpoint(const std::string& name);

// seconds a node may take to stop after the first SIGINT/SIGTERM before it is killed
// (SIGALRM): a node stuck in its shutdown never outlives its launcher for long
inline constexpr unsigned kStopGrace_s = 5;

// SIGINT and SIGTERM set a flag instead of killing the process, and arm the grace period
void install_stop_handlers();
bool stop_requested();

// wait until `socket` has a message or the monotonic clock reaches deadline_ns (ns
// resolution, unlike zmq_poll's milliseconds); true when readable
bool wait_readable(zmq::socket_t& socket, std::int64_t deadline_ns);

// waits up to 10 s (or a stop request) until `count` subscribers listen to `topic` on `out`;
// says so on stderr, naming `who`, when they do not come (the node then runs anyway)
void wait_for_subscribers(bus::BytePublisher& out, const char* topic, int count, const std::string& node, const std::string& who);
// per-topic counters of a node's sockets into its NodeStatus
void add_counters(msgs::NodeStatus& status, const bus::BytePublisher& out, const bus::ByteSubscriber* in);

// a node's main: runs `run`, and reports an exception as "<program>: error: ..." with exit 1
int node_main(const char* program, int (*run)(int, char**), int argc, char** argv);

// print "<node>: <text>" on stderr, flushed (nodes' lines interleave under the launcher)
void say(const std::string& node, const std::string& text);

}  // namespace enact::graph
