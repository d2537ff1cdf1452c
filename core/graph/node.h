#pragma once
// What every node process shares: where the graph's sockets live, stopping on SIGINT /
// SIGTERM, waiting on a socket with a sub-millisecond deadline, and its NodeStatus.
#include <cstdint>
#include <string>
#include <vector>

#include "core/rt/clock.h"

#include <zmq.hpp>

#include "core/bus/bytes.h"
#include "core/bus/loop_link.h"
#include "msgs/graph.pb.h"
#include "msgs/node_status.pb.h"

namespace enact::graph {

// the graph's folder: $ENACT_GRAPH_DIR (set by `enact launch`), else /tmp/enact-<uid>
std::string graph_dir();
// where node `name` publishes: ipc://<graph_dir>/<name>.pub
std::string node_endpoint(const std::string& name);
// the nodes of the graph's launch file that publish their parameters (GraphInfo.param_nodes)
// and have not declared their topics yet (each declares all of its own at once, its
// param/values/<node> among them): a graph still starting lists only some of its topics
std::vector<std::string> nodes_not_announced(const msgs::GraphInfo& info);

// seconds a node may take to stop after the first SIGINT/SIGTERM before it is killed
// (SIGALRM): a node stuck in its shutdown never outlives its launcher for long
inline constexpr unsigned kStopGrace_s = 5;

// SIGINT and SIGTERM set a flag instead of killing the process, and arm the grace period
void install_stop_handlers();
bool stop_requested();

// wait until `socket` has a message or the monotonic clock reaches deadline_ns (ns
// resolution, unlike zmq_poll's milliseconds); true when readable
bool wait_readable(zmq::socket_t& socket, std::int64_t deadline_ns);

// how long a node waits for the observers it was asked to wait for (launch parameter
// observers=N) before it runs anyway
inline constexpr double kObserversWait_s = 60.0;

// waits up to kObserversWait_s (or a stop request) until `count` subscribers listen to
// `topic` on `out`, saying so on stderr with the graph's attach endpoint, and (before the
// node said "ready": `before_ready`) telling the launcher to wait that long more for it;
// says so again, naming `who`, when they do not come (the node then runs anyway)
void wait_for_subscribers(bus::BytePublisher& out, const char* topic, int count, const std::string& node, const std::string& who,
                          bool before_ready = true);
// waits quietly until `count` subscribers listen to `topic` on `out`, until deadline_ns or a
// stop request: whether they do
bool await_subscribers(bus::BytePublisher& out, const char* topic, int count, std::int64_t deadline_ns);
// the clock master: waits up to kObserversWait_s (or a stop request) until the peer of the
// loop's same-host link (node `peer`) connects, saying so when it takes longer than a moment;
// false when it did not come (the node then runs anyway, every sample unanswered)
bool wait_for_loop_peer(bus::LoopLink& link, const std::string& node, const std::string& peer);

// per-topic counters of a node's sockets into its NodeStatus
void add_counters(msgs::NodeStatus& status, const bus::BytePublisher& out, const bus::ByteSubscriber* in);

// a loop process of the graph (launch file `realtime:`): applies the profile the launcher
// put in ENACT_RT_PROFILE to this thread and to the I/O threads of the bus, and says what
// it applied. Call it first, before any socket. Nothing when the variable is not set.
void apply_rt_profile(const std::string& node);

// whether apply_rt_profile pinned this process to CPUs of its own: the graph's other
// processes run elsewhere, and no other loop process shares them (the distributed graph's
// simulator, pinned beside the FFD driver, does: the driver's loop must then sleep every tick)
bool loop_cpu_own();

// the graph clock the launcher gave this node (ENACT_CLOCK; unset: real time); throws
// config::Error for a value that names no clock
rt::GraphClock graph_clock();

// print "<node>: <text>" on stderr, flushed (nodes' lines interleave under the launcher)
void say(const std::string& node, const std::string& text);

}  // namespace enact::graph
