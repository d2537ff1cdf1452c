// enact param set / list / get / dump / load: the parameters of a running graph, through its
// attach point. Every node publishes its declared parameters with the values in force on
// param/values/<node> (core/params/param_board.h); changes go on param/set, answered on
// param/ack.
#include <cstdio>
#include <map>

#include "core/bus/attach.h"
#include "core/bus/typed.h"
#include "core/config/suggest.h"
#include "core/config/yaml.h"
#include "core/graph/graph_dir.h"
#include "core/graph/stop.h"
#include "core/params/param_bus.h"
#include "core/graph/topics.h"
#include "core/rt/clock.h"
#include "msgs/graph.pb.h"
#include "msgs/param_update.pb.h"
#include "nodes/enact/attach_target.h"
#include "nodes/enact/commands.h"

namespace enact::cli {
namespace {

constexpr const char* kParamHelp = R"(usage: enact param set NAME VALUE     change a parameter of a running graph
       enact param list [NODE]          every parameter: value, unit, range, live or not
       enact param get NAME             the value in force of one parameter
       enact param dump [NODE]          the values in force as YAML
       enact param load FILE [--node NODE]   send the values of a YAML file
  (each with [--graph NAME | --attach ENDPOINT] [--key FILE.key --server-key FILE.pub])

Every node of the graph (simulator, drivers, container and its components, logger,
Foxglove bridge) publishes the parameters it declares with the values in force; NAME is
NODE.PARAM, or COMPONENT.PARAM for a container's component (sim.model in both shipped
launch files). `enact-sim --help` (and each node's) lists them with their defaults.

set: sends the change on param/set and waits for the node's answer on param/ack: prints
"applied from ffd/state seq N" (the state whose step first used it; exit 0) or "refused:
REASON" (exit 1); no answer within 5 s exits 1 too. VALUE is sent as a number when it is
one, as a flag for true / false, else as text. The live parameters of the simulator (SIM):
  SIM.model               CM0 CM1 CM2 CM3 P T PT, or a computer model YAML file
  SIM.threshold_m         penetration before force is felt, m (>= 0)
  SIM.stiffness_n_per_m   contact stiffness of the body, N/m   } checked against the
  SIM.damping_n_s_per_m   contact damping of the body, N s/m   } stability analysis
  SIM.change_ramp_s       the blend time of the next live changes, s (0..10)
  SIM.reset               (any VALUE) model, pins and task back to the start: a new trial
  SIM.reposition          (any VALUE) the subject is put back at the start
  SIM.trial               start | stop

dump NODE writes NODE's start parameters under the names its param_file takes (a launch
file's param_file: accepts it); dump without NODE writes every value under its full name.
load FILE sends each value of a live parameter that differs from the one in force, as set
does, and reports each line: applied, refused (with the reason), unchanged; a parameter
that cannot change while the graph runs is refused when its value differs. With --node
NODE the names are NODE's own (as dump NODE writes them). Exit 1 when a line was refused.
options:
)";

// how long the nodes' parameters may take to arrive
constexpr int kBoardsWait_ms = 5000;

// the graph this command talks to
struct Target {
  std::string endpoint;
  bus::ClientKeys keys;
};

// every node's ParamValues: the topics GraphInfo lists under param/values/, each node's
// last message (the attach point keeps it). A graph still starting lists some of them: the
// wait goes on until every node of its launch file that publishes its parameters is listed.
std::vector<msgs::ParamValues> read_boards(const Target& t) {
  bus::ByteSubscriber bytes;
  bus::Subscriber<msgs::GraphInfo> graph(bytes, std::string(bus::kGraphTopic));
  bus::attach_connect(bytes.socket(), t.endpoint, t.keys);
  const std::int64_t deadline = rt::now_ns() + std::int64_t{kBoardsWait_ms} * 1'000'000;
  msgs::GraphInfo info;
  std::vector<std::string> topics, missing;
  while ((topics.empty() || !missing.empty()) && rt::now_ns() < deadline && !graph::stop_requested()) {
    if (!graph.receive(info, 100)) continue;
    topics.clear();
    for (const auto& topic : info.topics()) {
      if (topic.name().starts_with(graph::kParamValues)) topics.push_back(topic.name());
    }
    missing = graph::nodes_not_announced(info);
  }
  if (topics.empty()) throw config::Error("no node of the graph at " + t.endpoint + " publishes its parameters\n  fix: is it an enact graph of this version? (enact topic list)");
  for (const std::string& node : missing) {
    std::fprintf(stderr, "enact param: node %s has not published its parameters within %d s (still starting, or stopped: enact node list)\n", node.c_str(), kBoardsWait_ms / 1000);
  }
  bus::ByteSubscriber values_bytes;
  for (const std::string& topic : topics) values_bytes.subscribe(topic);
  bus::attach_connect(values_bytes.socket(), t.endpoint, t.keys);
  std::map<std::string, msgs::ParamValues> by_topic;
  bus::RawMessage raw;
  msgs::ParamValues v;
  while (by_topic.size() < topics.size() && rt::now_ns() < deadline && !graph::stop_requested()) {
    if (!values_bytes.receive(raw, 100)) continue;
    if (v.ParseFromArray(raw.payload(), static_cast<int>(raw.payload_size()))) by_topic[std::string(raw.topic())] = v;
  }
  std::vector<msgs::ParamValues> out;
  for (const std::string& topic : topics) {
    if (by_topic.count(topic)) out.push_back(by_topic[topic]);
    else std::fprintf(stderr, "enact param: no parameters from %s within %d s\n", topic.c_str(), kBoardsWait_ms / 1000);
  }
  return out;
}

using Entry = msgs::ParamValues::Param;

// the entries of NODE: a process's (its components' included), or a container component's;
// every entry without a node. Names as NODE's param_file takes them when `file_names`.
std::vector<std::pair<std::string, const Entry*>> entries(const std::vector<msgs::ParamValues>& boards, const std::string& node) {
  std::vector<std::pair<std::string, const Entry*>> out;
  for (const msgs::ParamValues& b : boards) {
    for (const Entry& e : b.params()) {
      if (node.empty()) out.emplace_back(e.name(), &e);
      else if (b.node() == node) out.emplace_back(e.file_name(), &e);
      else if (e.name().starts_with(node + ".")) out.emplace_back(e.name().substr(node.size() + 1), &e);
    }
  }
  if (!node.empty() && out.empty()) {
    std::vector<std::string> nodes;
    for (const msgs::ParamValues& b : boards) nodes.push_back(b.node());
    throw config::Error("no node or component '" + node + "' in the graph" + config::did_you_mean(node, nodes) + "\n  fix: enact param list shows them all");
  }
  return out;
}

// the entry named `name` (full name), or an error naming the closest ones
const Entry& find_entry(const std::vector<msgs::ParamValues>& boards, const std::string& name) {
  if (const Entry* e = graph::find_param(boards, name)) return *e;
  throw config::Error(graph::no_such_param(boards, name));
}

// a YAML scalar, always double-quoted (paths, lists and empty values read back as written)
std::string quoted(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) out += c == '"' || c == '\\' ? std::string("\\") + c : std::string(1, c);
  return out + "\"";
}

int list(const std::vector<msgs::ParamValues>& boards, const std::string& node) {
  std::printf("%-32s %-24s %-6s %-22s %s\n", "NAME", "VALUE", "UNIT", "RANGE", "LIVE");
  for (const auto& [name, e] : entries(boards, node)) {
    const std::string& value = e->value();
    const char* live = !e->live() ? "no" : e->at_start() ? "yes" : "yes (live only)";
    std::printf("%-32s %-24s %-6s %-22s %s\n", e->name().c_str(), value.c_str(), e->unit().c_str(), e->range().c_str(), live);
  }
  return 0;
}

int dump(const std::vector<msgs::ParamValues>& boards, const std::string& node) {
  std::printf("# enact param dump%s: the values in force%s\n", node.empty() ? "" : (" " + node).c_str(),
              node.empty() ? " (enact param load FILE)" : " (a param_file, or enact param load FILE --node NODE)");
  for (const auto& [name, e] : entries(boards, node)) {
    if (!node.empty() && !e->at_start()) continue;
    std::printf("%s: %s\n", name.c_str(), quoted(e->value()).c_str());
  }
  return 0;
}

// changes sent on param/set and their answers
class Changes {
 public:
  explicit Changes(const Target& t) : client_(t.endpoint, "enact-param", t.keys) {
    bus::attach_connect(acks_bytes_.socket(), t.endpoint, t.keys);
  }

  // sends NAME = VALUE (as typed); its answer is printed after `where` (a file line)
  void send(const std::string& name, const std::string& value, const std::string& where = "") {
    msgs::ParamUpdate update;
    update.set_name(name);
    graph::set_value(update, value);
    pending_[client_.send(update)] = where + name + " = " + value;
  }

  // waits for every answer, printing each; false when one was refused or none came
  bool answers() {
    bool all = true;
    msgs::ParamAck ack;
    while (!pending_.empty()) {
      if (acks_.receive(ack, 5)) {
        if (const auto answer = client_.take(ack)) {
          std::printf("%s: %s\n", pending_[answer->request_id].c_str(), graph::answer_text(*answer).c_str());
          all = all && answer->applied;
          pending_.erase(answer->request_id);
        }
      }
      for (const graph::ParamAnswer& lost : client_.tick(rt::now_ns())) {
        std::printf("%s: %s\n", pending_[lost.request_id].c_str(), graph::answer_text(lost).c_str());
        pending_.erase(lost.request_id);
        all = false;
      }
    }
    return all;
  }

 private:
  bus::ByteSubscriber acks_bytes_;
  bus::Subscriber<msgs::ParamAck> acks_{acks_bytes_, graph::kParamAck};
  graph::ParamClient client_;
  std::map<std::uint64_t, std::string> pending_;  // by request id: "[where]NAME = VALUE"
};

int load(const Target& t, const std::vector<msgs::ParamValues>& boards, const std::string& file, const std::string& node) {
  const YAML::Node root = config::load_file(file);
  if (!root.IsMap()) throw config::Error(file + ": not a YAML map of name: value lines\n  fix: write it with enact param dump");
  const auto known = entries(boards, node);
  Changes changes(t);
  bool ok = true;
  for (const auto& kv : root) {
    const std::string name = config::scalar(file, kv.first, "a parameter name"), value = config::scalar(file, kv.second, "parameter " + name);
    const std::string where = file + ":" + std::to_string(kv.first.Mark().line + 1) + ": ";
    const std::string at = where + name + " = " + value + ": ";
    const Entry* e = nullptr;
    std::vector<std::string> names;
    for (const auto& [n, entry] : known) {
      if (n == name) e = entry;
      names.push_back(n);
    }
    if (!e) std::printf("%srefused: no such parameter%s\n  fix: enact param list%s shows them\n", at.c_str(), config::did_you_mean(name, names).c_str(), node.empty() ? "" : (" " + node).c_str());
    else if (e->value() == value) std::printf("%sunchanged\n", at.c_str());
    else if (!e->live()) std::printf("%srefused: %s\n", at.c_str(), graph::fixed_refusal(boards, e->name()).c_str());
    else changes.send(e->name(), value, where);
    ok = ok && e && (e->value() == value || e->live());
  }
  return changes.answers() && ok ? 0 : 1;
}

}  // namespace

int param(int argc, char** argv) {
  const Args a = parse(argc, argv, 2, {"graph", "attach", "wait", "key", "server-key", "node"}, {});
  if (a.flag("help") || a.positional.empty()) {
    std::fputs(kParamHelp, a.flag("help") ? stdout : stderr);
    std::fputs(kAttachOptionsHelp, a.flag("help") ? stdout : stderr);
    std::fputs("  --node NODE        load: the names of FILE are NODE's own (as dump NODE writes them)\n", a.flag("help") ? stdout : stderr);
    return a.flag("help") ? 0 : 2;
  }
  const std::string& verb = a.positional[0];
  const std::size_t n = a.positional.size();
  if (verb == "set" && n != 3) throw UsageError("use: enact param set NAME VALUE");
  if (verb == "get" && n != 2) throw UsageError("use: enact param get NAME");
  if (verb == "load" && n != 2) throw UsageError("use: enact param load FILE [--node NODE]");
  if ((verb == "list" || verb == "dump") && n > 2) throw UsageError("use: enact param " + verb + " [NODE]");
  if (verb != "set" && verb != "get" && verb != "load" && verb != "list" && verb != "dump") {
    throw UsageError("unknown verb '" + verb + "'" + config::did_you_mean(verb, {"set", "list", "get", "dump", "load"}) + ": use set, list, get, dump or load");
  }
  if (a.has("node") && verb != "load") throw UsageError("--node is for load");
  graph::install_stop_handlers();
  const Target t{attach_target(a, "param").endpoint, attach_keys(a)};
  if (verb == "set") {
    // a parameter its node declares fixed is refused here; the node decides on the others
    std::vector<msgs::ParamValues> boards;
    try {
      boards = read_boards(t);
    } catch (const config::Error&) {
      // a graph whose nodes publish no parameters: the node alone decides
    }
    const std::string refused = graph::fixed_refusal(boards, a.positional[1]);
    if (!refused.empty()) {
      std::printf("%s = %s: refused: %s\n", a.positional[1].c_str(), a.positional[2].c_str(), refused.c_str());
      return 1;
    }
    Changes changes(t);
    changes.send(a.positional[1], a.positional[2]);
    return changes.answers() ? 0 : 1;
  }
  const std::vector<msgs::ParamValues> boards = read_boards(t);
  if (verb == "get") {
    std::printf("%s\n", find_entry(boards, a.positional[1]).value().c_str());
    return 0;
  }
  const std::string node = n > 1 ? a.positional[1] : "";
  if (verb == "list") return list(boards, node);
  if (verb == "dump") return dump(boards, node);
  return load(t, boards, a.positional[1], a.get("node"));
}

}  // namespace enact::cli
