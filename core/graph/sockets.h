#pragma once
// Waiting on a graph's sockets: a socket readable before a deadline (ns), the subscribers a
// node waits for, the loop link's peer; and the sockets' counters in a NodeStatus.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <zmq.hpp>

#include "core/bus/bytes.h"
#include "core/bus/loop_link.h"
#include "msgs/node_status.pb.h"

namespace enact::graph {

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
void add_counters(msgs::NodeStatus& status, const bus::BytePublisher& out, const std::vector<std::pair<std::string, bus::TopicCounters>>& received);

}  // namespace enact::graph
