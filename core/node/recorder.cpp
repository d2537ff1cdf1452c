#include "core/node/recorder.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <iostream>
#include <utility>

#include "core/config/lists.h"
#include "core/config/yaml.h"
#include "core/foxglove/bridge.h"
#include "core/graph/process.h"
#include "core/params/device_config.h"
#include "core/params/node_params.h"
#include "core/params/param_binding.h"
#include "core/graph/stop.h"
#include "core/record/logger.h"
#include "core/session/registry.h"

namespace enact::node {

const NodeKind kLogger{.executable = "enact-logger", .default_name = "logger", .help = R"(usage: enact-logger [--name NAME] --param NAME=VALUE...

Records the graph's traffic to an MCAP file (enact record is the same from the shell).

To record a graph from its first tick, list the logger before the drivers in the launch
file and give the clock master `observers: 1` (docs/recording-and-replay.md), or make it a
component of the co-located container (plugin logger: the container waits for it).

parameters (--param NAME=VALUE):
)", .send_hwm = 0};

const NodeKind kFoxglove{.executable = "enact-foxglove", .default_name = "foxglove", .help = R"(usage: enact-foxglove [--name NAME] --param NAME=VALUE...

Serves the graph to Foxglove (WebSocket, foxglove.websocket.v1): every topic with its
Protobuf schema, and foxglove/scene (foxglove.SceneUpdate) for the 3D panel.

parameters (--param NAME=VALUE):
)", .send_hwm = 0};

namespace {

// how long an observer node waits for its graph when its parameters say nothing of it
constexpr double kGraphWait_s = 10.0;

// where an observer attaches: its attach parameter, else the graph the one rule finds
// (graph::pick_graph: the graph whose launcher started it, else the only one running),
// waited for up to wait_s
std::string attach_point(const std::string& given, double wait_s) {
  graph::AttachChoice choice;
  choice.endpoint = given;
  choice.wait_s = wait_s;
  return graph::find_graph(choice, std::cerr, [] { return graph::stop_requested(); }).endpoint;
}

class LoggerObserver : public Observer {
 public:
  explicit LoggerObserver(graph::Params& p) {
    const graph::LoggerConfig c = graph::logger_bindings().read(p);
    o_.output = c.output;
    o_.topics = config::split_commas(c.topics);
    topics_ = o_.topics.empty() ? "every topic" : c.topics;
    o_.regex = c.regex;
    o_.exclude = c.exclude;
    o_.writer.compression = record::parse_compression(c.compression);
    o_.writer.chunk_duration_ns = std::llround(c.chunk_duration_s * 1e9);
    o_.split_size_mb = c.split_size_mb;
    o_.split_duration_s = c.split_duration_s;
    o_.attach = c.attach;
    o_.keys = bus::client_keys("", "");
    o_.wait_s = c.wait_s;
    filter_ = graph::TopicFilter(o_);  // a bad pattern is refused here, before anything moves
  }
  std::string activate() override {
    o_.attach = attach_point(o_.attach, o_.wait_s);
    logger_ = std::make_unique<graph::Logger>(o_);
    logger_->attach();
    return "recording " + topics_ + " to " + o_.output;
  }
  bool records(const std::string& topic) const override { return filter_.wants(topic); }
  bool run(const std::function<bool()>& stop) override {
    try {
      logger_->run(stop);
    } catch (...) {
      logger_->close();  // whatever stopped it, what was recorded is closed whole
      throw;
    }
    return true;
  }
  Ending deactivate() override {
    if (!logger_) return {};
    logger_->close();
    Ending e{"closed " + logger_->files().back() + "\n" + graph::format(logger_->report()), logger_->write_failure().empty()};
    if (!e.ok) e.said += "\n" + graph::format_write_failure(*logger_);
    return e;
  }

 private:
  graph::LoggerOptions o_;
  graph::TopicFilter filter_;
  std::string topics_;
  std::unique_ptr<graph::Logger> logger_;
};

class FoxgloveObserver : public Observer {
 public:
  explicit FoxgloveObserver(graph::Params& p) {
    const graph::FoxgloveConfig c = graph::foxglove_bindings().read(p);
    attach_ = c.attach;
    o_.port = c.port;
    o_.host = c.host;
    o_.max_rate_hz = c.max_rate_hz;
    o_.keys = bus::client_keys("", "");
  }
  std::string activate() override {
    o_.attach = attach_point(attach_, kGraphWait_s);
    bridge_ = std::make_unique<foxglove::Bridge>(o_);
    return foxglove::describe(*bridge_, o_);
  }
  bool run(const std::function<bool()>& stop) override { return bridge_->run(stop); }
  Ending deactivate() override { return {bridge_ ? foxglove::format(bridge_->stats()) : "", true}; }

 private:
  std::string attach_;
  foxglove::BridgeOptions o_;
  std::unique_ptr<foxglove::Bridge> bridge_;
};

}  // namespace

std::unique_ptr<Observer> make_observer(const std::string& plugin, graph::Params& p) {
  if (plugin == "logger") return std::make_unique<LoggerObserver>(p);
  if (plugin == "foxglove") return std::make_unique<FoxgloveObserver>(p);
  return nullptr;
}

ObserverGroup::~ObserverGroup() {
  stop_.store(true);
  for (Member& m : members_) {
    if (m.thread.joinable()) m.thread.join();
    try {
      if (m.observer) (void)m.observer->deactivate();
    } catch (const std::exception&) {
      // already stopping for another error: that one is said
    }
  }
}

void ObserverGroup::add(const std::string& name, const std::string& plugin, graph::Params& p) {
  Member m;
  m.name = name;
  m.recorder = plugin == "logger";
  m.observer = make_observer(plugin, p);
  if (!m.observer) throw config::Error("component '" + name + "': plugin '" + plugin + "' is not an observer\n  fix: use logger or foxglove");
  members_.push_back(std::move(m));
}

int ObserverGroup::recorders(const std::string& topic) const {
  int n = 0;
  for (const Member& m : members_) n += m.observer && m.observer->records(topic);
  return n;
}

void ObserverGroup::start(bool recorders) {
  for (Member& m : members_) {
    if (m.recorder != recorders) continue;
    graph::say(node_, m.name + ": " + m.observer->activate());
    m.thread = std::thread([this, &m] {
      try {
        m.ran = m.observer->run([this] { return stop_.load(); });
      } catch (const std::exception& e) {
        m.ran = false;
        m.error = e.what();
      }
    });
  }
}

bool ObserverGroup::stop_all() {
  stop_.store(true);
  bool ok = true;
  for (Member& m : members_) {
    if (!m.thread.joinable()) continue;
    m.thread.join();
    const Observer::Ending end = m.observer->deactivate();
    m.observer.reset();
    if (!end.said.empty()) graph::say(node_, m.name + ": " + end.said);
    if (!m.error.empty()) graph::say(node_, m.name + ": error: " + m.error);
    ok = ok && m.ran && end.ok;
  }
  return ok;
}

ObserverNode::ObserverNode(Host& host, const char* plugin) : host_(host), observer_(make_observer(plugin, host.params())) {}

void ObserverNode::activate() { doing_ = observer_->activate(); }

void ObserverNode::run() {
  graph::say(host_.name(), doing_);
  ran_ = observer_->run([] { return graph::stop_requested(); });
}

int ObserverNode::deactivate() {
  const Observer::Ending end = observer_->deactivate();
  if (!end.said.empty()) graph::say(host_.name(), end.said);
  return ran_ && end.ok ? 0 : 1;
}

}  // namespace enact::node
