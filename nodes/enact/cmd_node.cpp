// enact node list | info NODE, and enact topic info | bw: the ROS 2 habits (`ros2 node`,
// `ros2 topic info`, `ros2 topic bw`) on a running graph, through its attach point.
#include <signal.h>

#include <cstdio>
#include <map>
#include <set>
#include <vector>

#include "core/bus/bytes.h"
#include "core/config/suggest.h"
#include "core/graph/topics.h"
#include "core/rt/clock.h"
#include "msgs/node_status.pb.h"
#include "nodes/enact/attach_target.h"
#include "nodes/enact/commands.h"

namespace enact::cli {
namespace {

constexpr const char* kNodeHelp = R"(usage: enact node list [--graph NAME | --attach ENDPOINT] [--key FILE.key --server-key FILE.pub]
       enact node info NODE [--graph NAME | --attach ENDPOINT] [--key FILE.key --server-key FILE.pub]

The nodes of a running graph (like `ros2 node`), through its attach point:
  list   every node: its state, rate and the topics it publishes (node/status, graph/topics)
  info   NODE's topics, parameters (as launched) and status: state, rate, loop latency,
         overruns, faults, and its per-topic counters. NODE may be a component of a
         co-located graph (sim, ffd, tactile of enact-rt): its parameters, and its node's
         topics and status
options:
)";

constexpr std::int64_t kSecond_ns = 1'000'000'000;

// messages and payload bytes of one topic over a time window
struct Traffic {
  std::uint64_t messages = 0, bytes = 0;
};

Traffic measure(bus::ByteSubscriber& sub, const std::string& topic, std::int64_t window_ns) {
  Traffic t;
  bus::RawMessage raw;
  const std::int64_t end = rt::now_ns() + window_ns;
  while (rt::now_ns() < end) {
    if (!sub.receive(raw, 50) || raw.topic() != topic) continue;
    ++t.messages;
    t.bytes += raw.payload_size();
  }
  return t;
}

// the newest NodeStatus of every node heard within `window_ns` (they come at 1 Hz)
std::map<std::string, msgs::NodeStatus> statuses(const std::string& endpoint, const bus::ClientKeys& keys, std::int64_t window_ns) {
  bus::ByteSubscriber sub;
  bus::attach_connect(sub.socket(), endpoint, keys);
  sub.subscribe(graph::kNodeStatus);
  std::map<std::string, msgs::NodeStatus> out;
  bus::RawMessage raw;
  msgs::NodeStatus s;
  const std::int64_t end = rt::now_ns() + window_ns;
  while (rt::now_ns() < end) {
    if (sub.receive(raw, 50) && raw.topic() == graph::kNodeStatus && s.ParseFromArray(raw.payload(), static_cast<int>(raw.payload_size()))) out[s.node()] = s;
  }
  return out;
}

// the graph's nodes: publishers of its topics, then nodes only heard on node/status
std::vector<std::string> node_names(const msgs::GraphInfo& info, const std::map<std::string, msgs::NodeStatus>& heard) {
  std::vector<std::string> names;
  std::set<std::string> seen;
  for (const auto& t : info.topics()) {
    if (seen.insert(t.publisher()).second) names.push_back(t.publisher());
  }
  for (const auto& [name, s] : heard) {
    if (seen.insert(name).second) names.push_back(name);
  }
  return names;
}

std::string published_by(const msgs::GraphInfo& info, const std::string& node) {
  std::string out;
  for (const auto& t : info.topics()) {
    if (t.publisher() == node) out += (out.empty() ? "" : " ") + t.name();
  }
  return out;
}

const char* state_name(const msgs::NodeStatus& s) { return s.node().empty() ? "-" : msgs::NodeStatus::State_Name(s.state()).c_str(); }

int list(const std::string& endpoint, const bus::ClientKeys& keys) {
  const msgs::GraphInfo info = graph_info(endpoint, keys);
  const auto heard = statuses(endpoint, keys, 1500'000'000);
  std::printf("%-14s %-12s %10s  %s\n", "node", "state", "rate (Hz)", "publishes");
  for (const std::string& n : node_names(info, heard)) {
    const auto it = heard.find(n);
    const msgs::NodeStatus s = it == heard.end() ? msgs::NodeStatus() : it->second;
    std::printf("%-14s %-12s %10.1f  %s\n", n.c_str(), state_name(s), s.rate_hz(), published_by(info, n).c_str());
  }
  return 0;
}

// the node a container's component runs in ("" when `name` is no component of one): its
// parameters are NODE.NAME.PARAM
std::string container_of(const msgs::GraphInfo& graph, const std::vector<std::string>& nodes, const std::string& name) {
  for (const std::string& n : nodes) {
    for (const auto& p : graph.params()) {
      if (p.name().starts_with(n + "." + name + ".")) return n;
    }
  }
  return "";
}

int info(const std::string& endpoint, const bus::ClientKeys& keys, const std::string& name) {
  const msgs::GraphInfo graph = graph_info(endpoint, keys);
  const auto heard = statuses(endpoint, keys, 2500'000'000);
  const std::vector<std::string> names = node_names(graph, heard);
  const bool is_node = std::find(names.begin(), names.end(), name) != names.end();
  // a co-located graph's components (sim, ffd, tactile of enact-rt) are shown in their node
  const std::string node = is_node ? name : container_of(graph, names, name);
  if (node.empty()) throw UsageError("the graph has no node or component '" + name + "'" + config::did_you_mean(name, names) + " (enact node list)");
  const std::string prefix = is_node ? node + "." : node + "." + name + ".";
  if (is_node) std::printf("node %s\n  publishes: %s\n  parameters:\n", node.c_str(), published_by(graph, node).c_str());
  else std::printf("component %s of node %s (in its one real-time thread)\n  publishes, through %s: %s\n  parameters:\n", name.c_str(), node.c_str(), node.c_str(), published_by(graph, node).c_str());
  for (const auto& p : graph.params()) {
    if (p.name().starts_with(prefix)) std::printf("    %s = %s\n", p.name().substr(prefix.size()).c_str(), p.value().c_str());
  }
  const auto it = heard.find(node);
  if (it == heard.end()) {
    std::printf("  status: none heard in 2.5 s (the node publishes node/status at 1 Hz when it runs)\n");
    return 0;
  }
  const msgs::NodeStatus& s = it->second;
  std::printf("  status: %s, %.1f Hz, loop latency p99 %.1f us (max %.1f us), %llu overruns, %llu faults%s%s\n", state_name(s), s.rate_hz(),
              static_cast<double>(s.latency_p99_ns()) * 1e-3, static_cast<double>(s.latency_max_ns()) * 1e-3, static_cast<unsigned long long>(s.overruns()),
              static_cast<unsigned long long>(s.faults()), s.last_fault().empty() ? "" : ", last: ", s.last_fault().c_str());
  for (const auto& t : s.topics()) {
    std::printf("    %-14s sent %llu, received %llu, dropped %llu, malformed %llu\n", t.topic().c_str(), static_cast<unsigned long long>(t.sent()),
                static_cast<unsigned long long>(t.received()), static_cast<unsigned long long>(t.dropped()), static_cast<unsigned long long>(t.malformed()));
  }
  return 0;
}

}  // namespace

std::string topic_name(const std::string& given) { return given.starts_with('/') ? given.substr(1) : given; }

int topic_info_or_bw(const std::string& endpoint, const bus::ClientKeys& keys, const std::string& topic, bool bw, double duration_s) {
  const msgs::GraphInfo graph = graph_info(endpoint, keys);
  const std::string type = type_of(graph, topic);
  bus::ByteSubscriber sub;
  bus::attach_connect(sub.socket(), endpoint, keys);
  sub.subscribe(topic);
  if (!bw) {
    std::string publishers;
    for (const auto& t : graph.topics()) {
      if (t.name() == topic) publishers += (publishers.empty() ? "" : ", ") + t.publisher();
    }
    const Traffic t = measure(sub, topic, kSecond_ns);
    std::printf("topic: %s\ntype: %s\npublishers: %s\nrate: %llu Hz (measured over 1 s)\n", topic.c_str(), type.c_str(), publishers.c_str(),
                static_cast<unsigned long long>(t.messages));
    return 0;
  }
  // one line a second until --duration, or Ctrl-C (the default action: nothing to close)
  signal(SIGINT, SIG_DFL);
  const int seconds = duration_s > 0.0 ? static_cast<int>(duration_s + 0.5) : -1;
  for (int i = 0; seconds < 0 || i < seconds; ++i) {
    const Traffic t = measure(sub, topic, kSecond_ns);
    std::printf("%s: %.1f kB/s, %llu messages/s, mean %.0f B\n", topic.c_str(), static_cast<double>(t.bytes) * 1e-3, static_cast<unsigned long long>(t.messages),
                t.messages ? static_cast<double>(t.bytes) / static_cast<double>(t.messages) : 0.0);
    std::fflush(stdout);
  }
  return 0;
}

int node(int argc, char** argv) {
  const Args a = parse(argc, argv, 2, attach_options(), {});
  const std::size_t n = a.positional.size();
  const bool listing = n == 1 && a.positional[0] == "list";
  Attached graph;
  if (const auto code = start_attached(a, "node", kNodeHelp, "list | info NODE", {"list", "info"}, listing || (n == 2 && a.positional[0] == "info"), graph)) return *code;
  return listing ? list(graph.endpoint, graph.keys) : info(graph.endpoint, graph.keys, a.positional[1]);
}

}  // namespace enact::cli
