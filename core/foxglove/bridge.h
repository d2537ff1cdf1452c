#pragma once
// The Foxglove bridge: a Foxglove WebSocket server (subprotocol foxglove.websocket.v1, spec:
// https://github.com/foxglove/ws-protocol/blob/main/docs/spec.md) attached to a graph as an
// observer. Every topic of the graph (from graph/topics) is advertised with encoding
// protobuf and its schema (the graph's FileDescriptorSet, base64), and one more,
// foxglove/scene: the scene as foxglove.SceneUpdate for the 3D panel (core/foxglove/scene.h).
// Clients get what they subscribe to; a topic faster than max_rate_hz (the loop-rate ones)
// reaches each client at most at that rate, and a client whose connection backs up loses
// messages. The graph never waits: the attach point drops for a slow observer, and the
// observer thread (run()) never waits for the WebSocket thread.
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

#include "core/bus/attach.h"
#include "core/bus/bytes.h"
#include "core/bus/client.h"
#include "core/foxglove/scene.h"
#include "core/foxglove/ws_server.h"
#include "msgs/graph.pb.h"

namespace enact::foxglove {

inline constexpr const char* kSubprotocol = "foxglove.websocket.v1";

struct BridgeOptions {
  std::string attach;                          // the graph's attach endpoint
  bus::ClientKeys keys;                        // for a graph with an access file (none: plain)
  std::string host = "127.0.0.1";              // where the WebSocket server listens
  int port = 8765;                             // 0: any free port
  double max_rate_hz = 100.0;                  // per client, on topics that run faster
  std::size_t max_backlog_bytes = 4u << 20;    // per client: past this, its messages drop
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
  // clients may publish (param/set): only when the graph and the server are loopback-only
  bool client_publish() const { return sender_ != nullptr; }

  // observes the graph and feeds the clients until `stop` returns true (the observer thread)
  void run(const std::function<bool()>& stop);

  BridgeStats stats() const;

 private:
  struct Channel {
    std::uint32_t id = 0;
    std::string topic, type, schema_base64;
    double rate_hz = 0.0;            // measured over the last second (observer thread)
    std::uint64_t window = 0;        // messages in the current second (observer thread)
  };
  struct Client {
    std::map<std::uint32_t, std::uint32_t> subscription_of;   // channel id -> subscription id
    std::map<std::uint32_t, std::int64_t> last_sent_ns;       // channel id -> when last sent
    std::map<std::uint32_t, std::string> published_topic;     // client channel id -> topic
  };

  // WebSocket thread
  void on_open(ClientId c);
  void on_close(ClientId c);
  void on_text(ClientId c, const std::string& text);
  void on_binary(ClientId c, const std::string& data);
  // observer thread
  void take_graph(const msgs::GraphInfo& info, const std::string& payload, std::int64_t now_ns);
  void forward(const std::string& topic, const std::string& payload, std::int64_t now_ns);
  void update_subscriptions();
  void measure_rates(std::int64_t now_ns);

  std::string advertise_json(const std::vector<const Channel*>& channels) const;
  const Channel* channel_of(const std::string& topic) const;

  BridgeOptions options_;
  std::unique_ptr<WsServer> server_;
  std::unique_ptr<bus::AttachSender> sender_;  // only when clients may publish
  bus::ByteSubscriber sub_;
  std::optional<SceneConverter> scene_;        // observer thread
  std::string scene_text_;                     // observer thread
  mutable std::mutex mutex_;                   // guards channels_, clients_, stats_
  std::vector<Channel> channels_;
  std::map<ClientId, Client> clients_;
  BridgeStats stats_;
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
