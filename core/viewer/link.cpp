#include "core/viewer/link.h"

#include <fstream>

#include "core/graph/topics.h"

namespace enact::viewer {
namespace {

// how often the attach file is read
constexpr std::int64_t kLook_ns = 500'000'000;

std::string read_attach_file() {
  std::ifstream in(graph::attach_file());
  std::string endpoint;
  in >> endpoint;
  return endpoint;
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
  graph::ParamClient params;
  bus::RawMessage raw;
  msgs::SceneState scene_msg;
  msgs::TaskEvent event_msg;
  msgs::NodeStatus status_msg;
  msgs::TactileShown shown_msg;
  msgs::ParamAck ack_msg;
  msgs::GraphInfo graph_msg;

  Connection(const std::string& endpoint, const std::string& source, const bus::ClientKeys& keys) : params(endpoint, source, keys) {
    bus::attach_connect(bytes.socket(), endpoint, keys);
  }
};

GraphLink::GraphLink(std::string endpoint, std::string source, bus::ClientKeys keys)
    : follow_file_(endpoint.empty()), source_(std::move(source)), keys_(std::move(keys)) {
  if (!follow_file_) connect(endpoint);
}

GraphLink::~GraphLink() = default;

void GraphLink::connect(const std::string& endpoint) {
  connection_.reset();
  endpoint_ = endpoint;
  if (!endpoint.empty()) connection_ = std::make_unique<Connection>(endpoint, source_, keys_);
}

bool GraphLink::follow(std::int64_t now_ns) {
  if (!follow_file_ || now_ns < next_look_ns_) return false;
  next_look_ns_ = now_ns + kLook_ns;
  const std::string endpoint = read_attach_file();
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
    else if (c.acks.accept(c.raw, c.ack_msg)) {
      if (auto a = c.params.take(c.ack_msg)) answers.push_back(*a);
    }
  }
  for (graph::ParamAnswer& lost : c.params.tick(now_ns)) answers.push_back(std::move(lost));
  return answers;
}

std::uint64_t GraphLink::send(const msgs::ParamUpdate& update) { return connection_ ? connection_->params.send(update) : 0; }

std::string GraphLink::describe() const {
  if (!endpoint_.empty()) return endpoint_;
  return "the next graph launched here (" + graph::attach_file() + ")";
}

}  // namespace enact::viewer
