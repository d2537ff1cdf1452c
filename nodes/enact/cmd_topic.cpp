// enact topic list | echo TOPIC | hz TOPIC: look at a running graph through its attach point.
#include <google/protobuf/descriptor.h>
#include <google/protobuf/message.h>
#include <signal.h>

#include <atomic>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>

#include "core/bus/attach.h"
#include "core/bus/bytes.h"
#include "core/graph/topics.h"
#include "core/rt/clock.h"
#include "msgs/common.pb.h"
#include "msgs/graph.pb.h"
#include "nodes/enact/commands.h"

namespace enact::cli {
namespace {

constexpr const char* kHelp = R"(usage: enact topic list [--attach ENDPOINT]
       enact topic echo TOPIC [--count N] [--attach ENDPOINT]
       enact topic hz TOPIC [--duration S] [--attach ENDPOINT]

Attach to a running graph (like `ros2 topic`), at any time, without disturbing it:
  list   the graph's topics, their message types and publishers (from graph/topics)
  echo   print each message of TOPIC (Protobuf text), N of them or until Ctrl-C
  hz     the rate of TOPIC every second, with messages lost (sequence gaps)
--attach: the graph's attach endpoint (printed by `enact launch`); default: the last graph
launched on this machine (/tmp/enact-<uid>/attach).
)";

std::atomic<bool> g_stop{false};
void on_stop(int) { g_stop.store(true); }

// the graph's topics, from its attach point
msgs::GraphInfo graph_info(const std::string& endpoint, const bus::ClientKeys& keys) {
  bus::ByteSubscriber sub;
  bus::attach_connect(sub.socket(), endpoint, keys);
  sub.subscribe(std::string(bus::kGraphTopic));
  msgs::GraphInfo info;
  const std::int64_t give_up = rt::now_ns() + 3'000'000'000;
  while (rt::now_ns() < give_up && !g_stop.load()) {
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
  for (const auto& t : info.topics()) names += (names.empty() ? "" : ", ") + t.name();
  throw UsageError("the graph has no topic '" + topic + "' (topics: " + names + ")");
}

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

int echo_or_hz(const std::string& endpoint, const bus::ClientKeys& keys, const std::string& topic, bool echo, long count, double duration_s) {
  const std::string type = type_of(graph_info(endpoint, keys), topic);
  auto msg = make(type);
  bus::ByteSubscriber sub;
  bus::attach_connect(sub.socket(), endpoint, keys);
  sub.subscribe(topic);
  std::map<std::string, std::uint64_t> last_seq;
  std::uint64_t received = 0, lost = 0, window = 0;
  const std::int64_t start = rt::now_ns();
  std::int64_t next_report = start + 1'000'000'000;
  const std::int64_t end = duration_s > 0.0 ? start + static_cast<std::int64_t>(duration_s * 1e9) : INT64_MAX;
  while (!g_stop.load() && rt::now_ns() < end && (count <= 0 || static_cast<long>(received) < count)) {
    const auto raw = sub.receive(100);
    const std::int64_t now = rt::now_ns();
    if (!echo && now >= next_report) {
      std::printf("%s: %.1f Hz (%llu messages, %llu lost in gaps so far)\n", topic.c_str(), static_cast<double>(window) * 1e9 / static_cast<double>(now - next_report + 1'000'000'000),
                  static_cast<unsigned long long>(received), static_cast<unsigned long long>(lost));
      std::fflush(stdout);
      window = 0;
      next_report = now + 1'000'000'000;
    }
    if (!raw || raw->topic() != topic || !msg->ParseFromArray(raw->payload(), static_cast<int>(raw->payload_size()))) continue;
    ++received;
    ++window;
    const auto [source, seq] = header_of(*msg);
    auto& last = last_seq[source];
    if (last != 0 && seq > last + 1) lost += seq - last - 1;
    last = seq;
    if (echo) {
      std::printf("--- %s\n%s", topic.c_str(), msg->DebugString().c_str());
      std::fflush(stdout);
    }
  }
  if (!echo) std::printf("%s: %llu messages in %.1f s, %llu lost in gaps\n", topic.c_str(), static_cast<unsigned long long>(received),
                         static_cast<double>(rt::now_ns() - start) * 1e-9, static_cast<unsigned long long>(lost));
  return 0;
}

}  // namespace

std::string attach_endpoint(const Args& a) {
  if (a.has("attach")) return a.get("attach");
  std::ifstream in(graph::attach_file());
  std::string endpoint;
  if (!(in >> endpoint)) throw UsageError("no running graph found (" + graph::attach_file() + "): start one with `enact launch`, or give --attach ENDPOINT");
  return endpoint;
}

bus::ClientKeys attach_keys(const Args& a) { return bus::client_keys(a.get("key"), a.get("server-key")); }

int topic(int argc, char** argv) {
  const Args a = parse(argc, argv, 2, {"attach", "count", "duration", "key", "server-key"}, {});
  if (a.flag("help") || a.positional.empty()) {
    std::fputs(kHelp, a.flag("help") ? stdout : stderr);
    std::fputs(kKeyHelp, a.flag("help") ? stdout : stderr);
    return a.flag("help") ? 0 : 2;
  }
  signal(SIGINT, on_stop);
  signal(SIGTERM, on_stop);
  const std::string& verb = a.positional[0];
  const std::string endpoint = attach_endpoint(a);
  const bus::ClientKeys keys = attach_keys(a);
  if (verb == "list" && a.positional.size() == 1) return list(endpoint, keys);
  if ((verb == "echo" || verb == "hz") && a.positional.size() == 2) {
    return echo_or_hz(endpoint, keys, a.positional[1], verb == "echo", static_cast<long>(a.number("count", 0.0)), a.number("duration", 0.0));
  }
  throw UsageError("use: enact topic list | echo TOPIC | hz TOPIC");
}

}  // namespace enact::cli
