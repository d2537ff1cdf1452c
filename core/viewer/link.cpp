#include "core/viewer/link.h"

#include <optional>

#include "core/graph/topics.h"

namespace enact::viewer {
namespace {

// how often the registry is read
constexpr std::int64_t kLook_ns = 500'000'000;

// the running graph that fits `choice` (graph::pick_graph: the one in use while it runs and
// fits), nullopt when none does, or when several do and none is named
std::optional<graph::GraphEntry> pick(const graph::AttachChoice& choice, const std::string& current) {
  try {
    return graph::pick_graph(choice, graph::list_graphs(), current);
  } catch (const graph::AmbiguousGraph&) {
    return std::nullopt;
  }
}

}  // namespace

// the sockets of one endpoint
struct GraphLink::Connection {
  bus::ByteSubscriber bytes;
  bus::Subscriber<msgs::SceneState> scene{bytes, graph::kSceneState};
  bus::Subscriber<msgs::TaskEvent> events{bytes, graph::kTaskEvent};
  bus::Subscriber<msgs::NodeStatus> status{bytes, graph::kNodeStatus};
  bus::Subscriber<msgs::TactileShown> shown{bytes, graph::kTactileShown};
  bus::Subscriber<msgs::ParamAck> acks{bytes, graph::kParamAck};
  bus::Subscriber<msgs::GraphInfo> graph{bytes, std::string(bus::kGraphTopic)};
  bus::Subscriber<msgs::TaskState> task{bytes, graph::kTaskState};
  graph::ParamClient params;
  bus::RawMessage raw;
  msgs::SceneState scene_msg;
  msgs::TaskEvent event_msg;
  msgs::NodeStatus status_msg;
  msgs::TactileShown shown_msg;
  msgs::ParamAck ack_msg;
  msgs::GraphInfo graph_msg;
  msgs::TaskState task_msg;

  Connection(const std::string& endpoint, const std::string& source, const bus::ClientKeys& keys) : params(endpoint, source, keys) {
    bus::attach_connect(bytes.socket(), endpoint, keys);
  }
};

GraphLink::GraphLink(graph::AttachChoice choice, std::string source, bus::ClientKeys keys)
    : choice_(std::move(choice)), source_(std::move(source)), keys_(std::move(keys)) {
  if (!choice_.endpoint.empty()) connect(choice_.endpoint);
}

GraphLink::~GraphLink() = default;

void GraphLink::connect(const std::string& endpoint) {
  connection_.reset();
  endpoint_ = endpoint;
  if (!endpoint.empty()) connection_ = std::make_unique<Connection>(endpoint, source_, keys_);
}

bool GraphLink::follow(std::int64_t now_ns) {
  if (!choice_.endpoint.empty() || now_ns < next_look_ns_) return false;
  next_look_ns_ = now_ns + kLook_ns;
  const std::optional<graph::GraphEntry> g = pick(choice_, endpoint_);
  const std::string endpoint = g ? g->endpoint : "";
  name_ = g ? g->name : "";
  if (endpoint == endpoint_) return false;
  connect(endpoint);
  return true;
}

std::vector<graph::ParamAnswer> GraphLink::receive(ViewModel& model, std::int64_t now_ns, int max_messages) {
  std::vector<graph::ParamAnswer> answers;
  if (!connection_) return answers;
  Connection& c = *connection_;
  for (int i = 0; i < max_messages && c.bytes.receive(c.raw, 0); ++i) {
    if (c.scene.accept(c.raw, c.scene_msg)) model.on_scene(c.scene_msg);
    else if (c.events.accept(c.raw, c.event_msg)) model.on_event(c.event_msg);
    else if (c.status.accept(c.raw, c.status_msg)) model.on_status(c.status_msg, now_ns);
    else if (c.shown.accept(c.raw, c.shown_msg)) model.on_shown(c.shown_msg);
    else if (c.graph.accept(c.raw, c.graph_msg)) model.on_graph(c.graph_msg, now_ns);
    else if (c.task.accept(c.raw, c.task_msg)) model.on_task_state(c.task_msg);
    else if (c.acks.accept(c.raw, c.ack_msg)) {
      if (auto a = c.params.take(c.ack_msg)) answers.push_back(*a);
    }
  }
  for (graph::ParamAnswer& lost : c.params.tick(now_ns)) answers.push_back(std::move(lost));
  return answers;
}

std::uint64_t GraphLink::send(const msgs::ParamUpdate& update) { return connection_ ? connection_->params.send(update) : 0; }

std::string GraphLink::describe() const {
  if (!endpoint_.empty()) return name_.empty() ? endpoint_ : "graph " + name_ + " at " + endpoint_;
  if (!choice_.graph.empty()) return "graph " + choice_.graph;
  if (!choice_.prefix.empty()) return "the trials of " + choice_.prefix;
  return "the graph launched next here";
}

}  // namespace enact::viewer
