// enact topic list | echo TOPIC | hz TOPIC: look at a running graph through its attach point.
#include <google/protobuf/descriptor.h>
#include <google/protobuf/message.h>

#include <cstdio>
#include <map>
#include <memory>

#include "core/bus/attach.h"
#include "core/bus/bytes.h"
#include "core/graph/logger.h"
#include "core/graph/node.h"
#include "core/rt/clock.h"
#include "msgs/common.pb.h"
#include "msgs/graph.pb.h"
#include "core/config/suggest.h"
#include "nodes/enact/attach_target.h"
#include "nodes/enact/commands.h"

namespace enact::cli {
namespace {

constexpr const char* kHelp = R"(usage: enact topic list [--graph NAME | --attach ENDPOINT]
       enact topic echo TOPIC [--count N | --once] [--graph NAME | --attach ENDPOINT]
       enact topic hz TOPIC [--duration S] [--graph NAME | --attach ENDPOINT]
       enact topic info TOPIC | bw TOPIC [--duration S] [--graph NAME | --attach ENDPOINT]

Attach to a running graph (like `ros2 topic`), at any time, without disturbing it:
  list   the graph's topics, their message types and publishers (from graph/topics)
  echo   print each message of TOPIC (Protobuf text), N of them (--once: one) or until
         Ctrl-C; a state topic (task/state) gives its current message at once; at the end,
         on stderr, how many arrived and how many were lost (sequence gaps)
  hz     the rate of TOPIC every second, with messages lost (sequence gaps)
  info   TOPIC's message type, publishers and rate (measured over 1 s)
  bw     the bandwidth of TOPIC every second (bytes of payload), until --duration or Ctrl-C
TOPIC may start with '/' (ROS 2 style): /ffd/state is ffd/state.
options:
)";

}  // namespace

msgs::GraphInfo graph_info(const std::string& endpoint, const bus::ClientKeys& keys) {
  bus::ByteSubscriber sub;
  bus::attach_connect(sub.socket(), endpoint, keys);
  sub.subscribe(std::string(bus::kGraphTopic));
  msgs::GraphInfo info;
  const std::int64_t give_up = rt::now_ns() + 3'000'000'000;
  while (rt::now_ns() < give_up && !graph::stop_requested()) {
    const auto raw = sub.receive(200);
    if (raw && info.ParseFromArray(raw->payload(), static_cast<int>(raw->payload_size()))) return info;
  }
  throw UsageError("no graph answers at " + endpoint + " (is it still running?)");
}

std::string type_of(const msgs::GraphInfo& info, const std::string& topic) {
  for (const auto& t : info.topics()) {
    if (t.name() == topic) return t.type();
  }
  std::string names;
  std::vector<std::string> known;
  for (const auto& t : info.topics()) names += (names.empty() ? "" : ", ") + t.name(), known.push_back(t.name());
  throw UsageError("the graph has no topic '" + topic + "'" + config::did_you_mean(topic, known) + " (topics: " + names + ")");
}

namespace {

int list(const std::string& endpoint, const bus::ClientKeys& keys) {
  const msgs::GraphInfo info = graph_info(endpoint, keys);
  std::printf("graph %s at %s\n", info.graph().c_str(), endpoint.c_str());
  for (const auto& t : info.topics()) std::printf("  %-16s %-28s %s\n", t.name().c_str(), t.type().c_str(), t.publisher().c_str());
  return 0;
}

// a message of a type named on the bus, from the linked-in contract
std::unique_ptr<google::protobuf::Message> make(const std::string& type) {
  const auto* d = google::protobuf::DescriptorPool::generated_pool()->FindMessageTypeByName(type);
  if (!d) throw UsageError("unknown message type '" + type + "'");
  return std::unique_ptr<google::protobuf::Message>(google::protobuf::MessageFactory::generated_factory()->GetPrototype(d)->New());
}

// the header's seq and source, read through reflection (every stream message has header = 1)
std::pair<std::string, std::uint64_t> header_of(const google::protobuf::Message& m) {
  const auto* field = m.GetDescriptor()->FindFieldByName("header");
  if (!field) return {"", 0};
  const auto& h = static_cast<const msgs::Header&>(m.GetReflection()->GetMessage(m, field));
  return {h.source(), h.seq()};
}

// the messages lost in gaps by every publisher
std::uint64_t lost_in(const std::map<std::string, graph::SequenceCheck>& seqs) {
  std::uint64_t lost = 0;
  for (const auto& [source, check] : seqs) lost += check.gaps;
  return lost;
}

int echo_or_hz(const std::string& endpoint, const bus::ClientKeys& keys, const std::string& topic, bool echo, long count, double duration_s) {
  const std::string type = type_of(graph_info(endpoint, keys), topic);
  auto msg = make(type);
  bus::ByteSubscriber sub;
  bus::attach_connect(sub.socket(), endpoint, keys);
  sub.subscribe(topic);
  std::map<std::string, graph::SequenceCheck> seqs;
  std::uint64_t received = 0, window = 0;
  const std::int64_t start = rt::now_ns();
  std::int64_t next_report = start + 1'000'000'000;
  const std::int64_t end = duration_s > 0.0 ? start + static_cast<std::int64_t>(duration_s * 1e9) : INT64_MAX;
  while (!graph::stop_requested() && rt::now_ns() < end && (count <= 0 || static_cast<long>(received) < count)) {
    const auto raw = sub.receive(100);
    const std::int64_t now = rt::now_ns();
    if (!echo && now >= next_report) {
      std::printf("%s: %.1f Hz (%llu messages, %llu lost in gaps so far)\n", topic.c_str(), static_cast<double>(window) * 1e9 / static_cast<double>(now - next_report + 1'000'000'000),
                  static_cast<unsigned long long>(received), static_cast<unsigned long long>(lost_in(seqs)));
      std::fflush(stdout);
      window = 0;
      next_report = now + 1'000'000'000;
    }
    if (!raw || raw->topic() != topic || !msg->ParseFromArray(raw->payload(), static_cast<int>(raw->payload_size()))) continue;
    // per publisher: a state topic's last message may come again (an observer joined)
    const auto [source, seq] = header_of(*msg);
    graph::SequenceCheck& check = seqs[source];
    if (check.repeats(seq)) continue;
    check.add(seq);
    ++received;
    ++window;
    if (echo) {
      std::printf("--- %s\n%s", topic.c_str(), msg->DebugString().c_str());
      std::fflush(stdout);
    }
  }
  // the summary: on stdout for hz, on stderr for echo (its stdout is the messages)
  std::fprintf(echo ? stderr : stdout, "%s: %llu messages in %.1f s, %llu lost in gaps\n", topic.c_str(), static_cast<unsigned long long>(received),
               static_cast<double>(rt::now_ns() - start) * 1e-9, static_cast<unsigned long long>(lost_in(seqs)));
  return 0;
}

}  // namespace

int topic(int argc, char** argv) {
  const Args a = parse(argc, argv, 2, {"graph", "attach", "wait", "count", "duration", "key", "server-key"}, {"once"});
  if (a.flag("help") || a.positional.empty()) {
    std::fputs(kHelp, a.flag("help") ? stdout : stderr);
    std::fputs(kAttachOptionsHelp, a.flag("help") ? stdout : stderr);
    return a.flag("help") ? 0 : 2;
  }
  const std::string& verb = a.positional[0];
  const bool listing = verb == "list" && a.positional.size() == 1;
  const bool watching = (verb == "echo" || verb == "hz" || verb == "info" || verb == "bw") && a.positional.size() == 2;
  if (!listing && !watching) throw UsageError("use: enact topic list | echo TOPIC | hz TOPIC | info TOPIC | bw TOPIC");
  if (a.flag("once") && (verb != "echo" || a.has("count"))) throw UsageError("--once is for echo, instead of --count");
  graph::install_stop_handlers();
  const bus::ClientKeys keys = attach_keys(a);
  const std::string endpoint = attach_target(a, "topic").endpoint;
  if (listing) return list(endpoint, keys);
  const std::string topic = topic_name(a.positional[1]);
  if (verb == "info" || verb == "bw") return topic_info_or_bw(endpoint, keys, topic, verb == "bw", a.number("duration", 0.0));
  const long count = a.flag("once") ? 1 : static_cast<long>(a.number("count", 0.0));
  return echo_or_hz(endpoint, keys, topic, verb == "echo", count, a.number("duration", 0.0));
}

}  // namespace enact::cli
