// enact topic list | echo TOPIC | hz TOPIC | pub TOPIC YAML: look at a running graph through
// its attach point, and send on its inbound topics.
#include <google/protobuf/descriptor.h>
#include <google/protobuf/message.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <memory>

#include "core/bus/attach.h"
#include "core/bus/bytes.h"
#include "core/record/logger.h"
#include "core/params/param_bus.h"
#include "core/graph/topics.h"
#include "core/graph/graph_dir.h"
#include "core/graph/stop.h"
#include "core/rt/clock.h"
#include "msgs/common.pb.h"
#include "msgs/graph.pb.h"
#include "msgs/param_update.pb.h"
#include "core/config/suggest.h"
#include "nodes/enact/attach_target.h"
#include "nodes/enact/commands.h"
#include "nodes/enact/reflect.h"

namespace enact::cli {
namespace {

constexpr const char* kTopicHelp = R"(usage: enact topic list [--graph NAME | --attach ENDPOINT]
       enact topic echo TOPIC [--count N | --once] [--field PATH]... [--csv] [--graph NAME | --attach ENDPOINT]
       enact topic hz TOPIC [--duration S] [--graph NAME | --attach ENDPOINT]
       enact topic info TOPIC | bw TOPIC [--duration S] [--graph NAME | --attach ENDPOINT]
       enact topic pub TOPIC YAML [--once | --rate HZ [--count N]] [--graph NAME | --attach ENDPOINT]

Attach to a running graph (like `ros2 topic`), at any time, without disturbing it:
  list   the graph's topics, their message types and publishers (from graph/topics)
  echo   print each message of TOPIC (Protobuf text), N of them (--once: one) or until
         Ctrl-C; a state topic (task/state) gives its current message at once; at the end,
         on stderr, how many arrived and how many were lost (sequence gaps);
         --field PATH: only that field of each message (force.x, header.seq, pins, a list
         as [a, b], one element as pins[3]; a message, one column per field: position is
         position.x, position.y, position.z); several --field: one line each,
         tab-separated; --csv: a header line of the paths, then one CSV row per message
  hz     the rate of TOPIC every second, with messages lost (sequence gaps)
  info   TOPIC's message type, publishers and rate (measured over 1 s)
  bw     the bandwidth of TOPIC every second (bytes of payload), until --duration or Ctrl-C
  pub    send a message on one of the graph's inbound topics (param/set), written as YAML
         and mapped onto the message by field name, e.g.
           enact topic pub param/set '{name: sim.stiffness_n_per_m, number: 3000}'
         once (--once, the default), or --rate HZ until Ctrl-C or --count N; each message
         is a request the simulator answers (printed: applied from ffd/state seq N, the
         state whose step first used it, or refused; exit 1 when one is refused or
         unanswered). On a graph launched with --access it needs an operate key.
TOPIC may start with '/' (ROS 2 style): /ffd/state is ffd/state.
options:
)";

}  // namespace

msgs::GraphInfo graph_info(const std::string& endpoint, const bus::ClientKeys& keys) {
  bus::ByteSubscriber sub;
  bus::attach_connect(sub.socket(), endpoint, keys);
  sub.subscribe(std::string(bus::kGraphTopic));
  // a graph still starting: the next GraphInfo, until every node declared its topics
  msgs::GraphInfo info;
  bool answered = false;
  const std::int64_t give_up = rt::now_ns() + 3'000'000'000;
  while (rt::now_ns() < give_up && !graph::stop_requested()) {
    const auto raw = sub.receive(200);
    if (!raw || !info.ParseFromArray(raw->payload(), static_cast<int>(raw->payload_size()))) continue;
    answered = true;
    if (graph::nodes_not_announced(info).empty()) return info;
  }
  if (answered) return info;
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

// the header, read through reflection (every stream message has header = 1; none: an empty one)
const msgs::Header& header_of(const google::protobuf::Message& m) {
  const auto* field = m.GetDescriptor()->FindFieldByName("header");
  if (!field) return msgs::Header::default_instance();
  return static_cast<const msgs::Header&>(m.GetReflection()->GetMessage(m, field));
}

// the messages lost in gaps by every publisher
std::uint64_t lost_in(const std::map<std::string, graph::SequenceCheck>& seqs) {
  std::uint64_t lost = 0;
  for (const auto& [source, check] : seqs) lost += check.gaps;
  return lost;
}

// what echo / hz do with each message
struct Watch {
  bool echo = false;
  long count = 0;           // stop after this many (0: no limit)
  double duration_s = 0.0;  // stop after this long (0: no limit)
  std::vector<std::string> fields;  // echo only these field paths
  bool csv = false;                 // ... as CSV rows under a header line
};

// one message as echo prints it: whole, or its fields (tab-separated, or a CSV row)
void print_echo(const std::string& topic, const google::protobuf::Message& msg, const std::vector<FieldPath>& paths, bool csv) {
  if (paths.empty()) {
    std::printf("--- %s\n%s", topic.c_str(), msg.DebugString().c_str());
  } else {
    std::string line;
    for (const FieldPath& p : paths) line += (line.empty() ? "" : csv ? "," : "\t") + (csv ? csv_cell(field_text(msg, p)) : field_text(msg, p));
    std::printf("%s\n", line.c_str());
  }
  std::fflush(stdout);
}

int echo_or_hz(const Attached& graph, const std::string& topic, const Watch& w) {
  const std::string type = type_of(graph_info(graph.endpoint, graph.keys), topic);
  auto msg = make(type);
  // the field paths, checked before anything arrives
  std::vector<FieldPath> paths;
  std::string header;
  for (const std::string& f : w.fields) {
    for (FieldPath& p : resolve_columns(*msg->GetDescriptor(), f)) {
      if (!header.empty()) header += ',';
      header += csv_cell(p.text);
      paths.push_back(std::move(p));
    }
  }
  if (w.csv) std::printf("%s\n", header.c_str());
  bus::ByteSubscriber sub;
  bus::attach_connect(sub.socket(), graph.endpoint, graph.keys);
  sub.subscribe(topic);
  std::map<std::string, graph::SequenceCheck> seqs;
  std::uint64_t received = 0, window = 0;
  const std::int64_t start = rt::now_ns();
  std::int64_t next_report = start + 1'000'000'000;
  const std::int64_t end = w.duration_s > 0.0 ? start + static_cast<std::int64_t>(w.duration_s * 1e9) : INT64_MAX;
  const bool echo = w.echo;
  const long count = w.count;
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
    const msgs::Header& h = header_of(*msg);
    graph::SequenceCheck& check = seqs[h.source()];
    if (check.repeats(h.seq(), h.stamp_ns())) continue;
    check.add(h.seq(), h.stamp_ns());
    ++received;
    ++window;
    if (echo) print_echo(topic, *msg, paths, w.csv);
  }
  // the summary: on stdout for hz, on stderr for echo (its stdout is the messages)
  std::fprintf(echo ? stderr : stdout, "%s: %llu messages in %.1f s, %llu lost in gaps\n", topic.c_str(), static_cast<unsigned long long>(received),
               static_cast<double>(rt::now_ns() - start) * 1e-9, static_cast<unsigned long long>(lost_in(seqs)));
  return 0;
}

// the message of enact topic pub TOPIC YAML, checked before anything attaches: TOPIC one
// of the graph's inbound topics, YAML mapped onto its message by field name
msgs::ParamUpdate pub_message(const std::string& topic, const std::string& yaml) {
  const auto inbound = std::find(std::begin(graph::kInboundTopics), std::end(graph::kInboundTopics), topic);
  if (inbound == std::end(graph::kInboundTopics)) {
    throw UsageError("'" + topic + "' is not an inbound topic: a graph takes messages from observers on param/set only (its own nodes publish the others)");
  }
  msgs::ParamUpdate update;
  try {
    fill_from_yaml(YAML::Load(yaml), update);
  } catch (const YAML::Exception& e) {
    throw UsageError("YAML '" + yaml + "': " + e.msg + " (write a mapping: '{name: sim.model, text: CM2}')");
  }
  return update;
}

// enact topic pub: `count` requests (0: until Ctrl-C), `rate_hz` apart, each answered by
// the simulator on param/ack; 0 when every one was applied
int pub(const Attached& graph, const msgs::ParamUpdate& update, long count, double rate_hz) {
  // the answers come on param/ack, through the same attach point
  bus::ByteSubscriber acks_bytes;
  bus::Subscriber<msgs::ParamAck> acks(acks_bytes, graph::kParamAck);
  bus::attach_connect(acks_bytes.socket(), graph.endpoint, graph.keys);
  graph::ParamClient client(graph.endpoint, "enact-topic-pub", graph.keys);
  const std::int64_t period_ns = rate_hz > 0.0 ? static_cast<std::int64_t>(1e9 / rate_hz) : 0;
  long sent = 0, answered = 0, applied = 0;
  std::int64_t next_send = rt::now_ns();
  msgs::ParamAck ack;
  // send on time, until every request sent is answered (or given up)
  while (!graph::stop_requested() && ((count <= 0 || sent < count) || answered < sent)) {
    const std::int64_t now = rt::now_ns();
    if ((count <= 0 || sent < count) && now >= next_send) {
      std::printf("publishing #%ld: %s\n", ++sent, update.ShortDebugString().c_str());
      client.send(update);
      next_send = now + period_ns;
    }
    std::vector<graph::ParamAnswer> answers = client.tick(now);
    if (acks.receive(ack, 10)) {
      if (auto a = client.take(ack)) answers.push_back(*a);
    }
    for (const graph::ParamAnswer& a : answers) {
      std::printf("%s: %s\n", a.name.c_str(), graph::answer_text(a).c_str());
      std::fflush(stdout);
      ++answered;
      applied += a.applied ? 1 : 0;
    }
  }
  return sent > 0 && applied == sent ? 0 : 1;
}

}  // namespace

int topic(int argc, char** argv) {
  const std::vector<std::string> fields = take_repeated(argc, argv, "--field");
  const Args a = parse(argc, argv, 2, attach_options({"count", "duration", "rate"}), {"once", "csv"});
  const std::size_t n = a.positional.size();
  const std::string verb = n ? a.positional[0] : "";
  const bool listing = verb == "list" && n == 1;
  const bool watching = (verb == "echo" || verb == "hz" || verb == "info" || verb == "bw") && n == 2;
  const bool publishing = verb == "pub" && n == 3;
  if (a.flag("once") && !(verb == "echo" || verb == "pub")) throw UsageError("--once is for echo and pub");
  if (a.flag("once") && (a.has("count") || a.has("rate"))) throw UsageError("give --once or --count / --rate, not both");
  if ((!fields.empty() || a.flag("csv")) && verb != "echo") throw UsageError("--field and --csv are for echo");
  if (a.flag("csv") && fields.empty()) throw UsageError("--csv needs the columns: --field PATH (one or more)");
  if (a.has("rate") && verb != "pub") throw UsageError("--rate is for pub (hz measures a rate)");
  if (verb == "pub" && a.has("count") && !a.has("rate")) throw UsageError("pub --count N needs --rate HZ (without it: --once)");
  // what pub sends, checked before attaching
  const bool sending = publishing && !a.flag("help");
  const std::optional<msgs::ParamUpdate> message = sending ? std::optional(pub_message(topic_name(a.positional[1]), a.positional[2])) : std::nullopt;
  const double rate_hz = a.number("rate", 0.0);
  if (a.has("rate") && rate_hz <= 0.0) throw UsageError("--rate must be > 0 Hz");
  Attached graph;
  if (const auto code = start_attached(a, "topic", kTopicHelp, "list | echo TOPIC | hz TOPIC | info TOPIC | bw TOPIC | pub TOPIC YAML",
                                       {"list", "echo", "hz", "info", "bw", "pub"}, listing || watching || publishing, graph)) {
    return *code;
  }
  if (listing) return list(graph.endpoint, graph.keys);
  const std::string topic = topic_name(a.positional[1]);
  if (publishing) {
    const long count = a.has("rate") ? static_cast<long>(a.number("count", 0.0)) : 1;
    return pub(graph, *message, count, rate_hz);
  }
  if (verb == "info" || verb == "bw") return topic_info_or_bw(graph.endpoint, graph.keys, topic, verb == "bw", a.number("duration", 0.0));
  Watch w{.echo = verb == "echo", .count = a.flag("once") ? 1 : static_cast<long>(a.number("count", 0.0)), .duration_s = a.number("duration", 0.0),
          .fields = fields, .csv = a.flag("csv")};
  return echo_or_hz(graph, topic, w);
}

}  // namespace enact::cli
