#pragma once
// The Foxglove bridge: a Foxglove WebSocket server (subprotocol foxglove.websocket.v1, spec:
// https://github.com/foxglove/ws-protocol/blob/main/docs/spec.md) attached to a graph as an
// observer. Every topic of the graph (from graph/topics) is advertised with encoding
// protobuf and its schema (the graph's FileDescriptorSet, base64), and one more,
// foxglove/scene: the scene as foxglove.SceneUpdate for the 3D panel (core/foxglove/scene.h).
// Clients get what they subscribe to, stamped with the wall clock (the messages' own headers
// keep the monotonic stamps); a topic faster than max_rate_hz (the loop-rate ones) reaches
// each client at most at that rate from its first message (a topic's rate is not known until
// it was measured over a full window: until then the limit holds; once measured faster, it
// stays limited), and a client whose
// connection backs up loses messages. The graph never waits: the attach point drops for a
// slow observer, and the observer thread (run()) never waits for the WebSocket thread.
// Clients publish (clientPublish, encodings json and protobuf) on the graph's inbound topics
// (param/set), and see and set the graph's parameters (parameters, parametersSubscribe): both
// go the way `enact param set` sends (core/params/param_bus.h): the same refusal of a
// parameter that is not live, the same role at the attach point, the node's ParamAck.
#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "core/bus/attach.h"
#include "core/bus/bytes.h"
#include "core/bus/client.h"
#include "core/foxglove/scene.h"
#include "core/net/ws_server.h"
#include "msgs/graph.pb.h"
#include "msgs/param_update.pb.h"

namespace enact::graph {
class ParamClient;
}

namespace enact::foxglove {

inline constexpr const char* kSubprotocol = "foxglove.websocket.v1";

struct BridgeOptions {
  std::string attach;                          // the graph's attach endpoint
  bus::ClientKeys keys;                        // for a graph with an access file (none: plain)
  std::string host = "127.0.0.1";              // where the WebSocket server listens
  int port = 8765;                             // 0: any free port
  double max_rate_hz = 100.0;                  // per client, on topics that run faster
  std::size_t max_backlog_bytes = 4u << 20;    // per client: past this, its messages drop
  // the graph's name when it was found by name: when it stops (no graph/topics for 3 s), the
  // bridge waits for a graph of that name and follows it; "": the bridge ends
  std::string graph_name;
};

struct BridgeStats {
  std::uint64_t clients = 0;       // connected now
  std::uint64_t sent = 0;          // messages sent to clients
  std::uint64_t decimated = 0;     // left out by the rate limit
  std::uint64_t dropped = 0;       // left out because a client's connection backed up
  std::uint64_t published = 0;     // messages clients sent into the graph
};

class Bridge {
 public:
  // starts the WebSocket server and connects to the graph (nothing is received before
  // run()). Throws config::Error for a bad endpoint or a port that cannot be bound.
  explicit Bridge(BridgeOptions options);
  ~Bridge();
  Bridge(const Bridge&) = delete;
  Bridge& operator=(const Bridge&) = delete;

  // the WebSocket port bound
  int port() const;
  // clients may publish (param/set) and set parameters: only when the graph and the server
  // are loopback-only
  bool client_publish() const { return param_out_ != nullptr; }

  // observes the graph and feeds the clients until `stop` returns true (the observer thread):
  // true; false when the graph stopped and no graph_name is followed (said on stderr)
  bool run(const std::function<bool()>& stop);

  BridgeStats stats() const;

 private:
  struct Channel {
    std::uint32_t id = 0;
    std::string topic, type, schema_base64;
    // the rate limit applies until the topic was measured over a whole window since its
    // messages started to arrive, and for good once it ran faster than max_rate_hz in one (a
    // loop-rate topic whose loop paused stays limited when it resumes) (observer thread)
    bool measured = false, fast = false;
    std::uint64_t window = 0;        // messages in the current window (observer thread)
    std::int64_t since_ns = 0;       // when its messages started to arrive (subscribed)
  };
  struct Published {
    std::string topic, encoding;
  };
  struct Client {
    std::map<std::uint32_t, std::uint32_t> subscription_of;   // channel id -> subscription id
    std::map<std::uint32_t, std::int64_t> last_sent_ns;       // channel id -> when last sent
    std::map<std::uint32_t, Published> published;             // client channel id -> what
    // channels it advertised on topics the graph does not take (a panel's own, such as the
    // 3D panel's /clicked_point): accepted, as foxglove_bridge does, and what comes on them
    // dropped
    std::set<std::uint32_t> unrouted;
    std::set<std::string> param_updates;                      // parameters it follows
    bool all_param_updates = false;                           // it follows every parameter
  };
  // a change sent for a client (setParameters, or a message it published)
  struct Request {
    net::ClientId client = 0;
    std::string id;          // setParameters' id (answered with parameterValues)
    bool set_parameters = false;
  };

  // WebSocket thread
  void on_open(net::ClientId c);
  void on_close(net::ClientId c);
  void on_text(net::ClientId c, const std::string& text);
  void on_binary(net::ClientId c, const std::string& data);
  void advertise_from(net::ClientId c, Client& client, const nlohmann::json& channels);
  void get_parameters(net::ClientId c, const nlohmann::json& msg);
  void set_parameters(net::ClientId c, const nlohmann::json& msg);
  void follow_parameters(Client& client, const nlohmann::json& names, bool follow);
  // sends `update` into the graph for a client (refused here when its parameter is not live)
  void send_update(msgs::ParamUpdate update, Request request);
  // observer thread
  void take_graph(const msgs::GraphInfo& info, const std::string& payload, std::int64_t now_ns);
  void forward(const std::string& topic, const std::string& payload, std::int64_t now_ns);
  void update_subscriptions();
  void measure_rates(std::int64_t now_ns);
  // (re)connects to the graph at `endpoint`, the old one's channels unadvertised
  void connect(const std::string& endpoint);
  // false when the graph stopped and the bridge ends; follows graph_name to its new endpoint
  bool follow_graph(std::int64_t now_ns);
  void take_params(const msgs::ParamValues& values);
  void take_ack(const msgs::ParamAck& ack);
  void resend_or_give_up(std::int64_t now_ns);
  void answer(const Request& r, const std::string& name, const nlohmann::json& parameter, int level, const std::string& text);

  std::string advertise_json(const std::vector<const Channel*>& channels) const;
  const Channel* channel_of(const std::string& topic) const;

  BridgeOptions options_;
  std::unique_ptr<net::WsServer> server_;
  std::unique_ptr<graph::ParamClient> param_out_;  // only when clients may publish
  std::unique_ptr<bus::ByteSubscriber> sub_;   // observer thread, but for its making
  std::int64_t graph_seen_ns_ = 0;             // observer thread: the last graph/topics
  std::int64_t next_look_ns_ = 0;              // when to look for the graph again
  bool waiting_ = false;                       // for a graph of graph_name to start again
  static constexpr std::int64_t kGraphSilence_ns = 3'000'000'000;  // 3 GraphInfo periods
  std::optional<SceneConverter> scene_;        // observer thread
  std::optional<graph::NamedScene> scene_in_use_;  // observer thread
  mutable std::mutex mutex_;                   // guards channels_, clients_, stats_
  std::vector<Channel> channels_;
  std::uint32_t last_channel_id_ = 0;
  std::map<net::ClientId, Client> clients_;
  BridgeStats stats_;
  std::vector<msgs::ParamValues> boards_;      // each node's parameters in force
  std::map<std::uint64_t, Request> requests_;  // by request id, until answered
  std::atomic<bool> subscriptions_changed_ = false;
  std::set<std::string> zmq_topics_;           // observer thread: what sub_ receives
  std::int64_t rate_window_start_ns_ = 0;
};

// RFC 4648 base64 of `bytes`, with padding
std::string base64(const std::string& bytes);

}  // namespace enact::foxglove

namespace enact::foxglove {

// "ws://HOST:PORT" of a running bridge
std::string url(const BridgeOptions& options, int port);

// how to open it, for the log: the URL, the graph, whether clients may publish
std::string describe(const Bridge& bridge, const BridgeOptions& options);

// "N clients, N sent, N left out by the rate limit, N dropped (slow clients), N published"
std::string format(const BridgeStats& stats);

}  // namespace enact::foxglove
