#pragma once
// The attach point of a graph: the one endpoint observers (logger, viewer, a Python script,
// another machine) connect to, at any time, to see any topic of the graph.
//
// Nodes talk to each other directly (the FFD driver's publisher to the simulator's
// subscriber), so the loop's hot path has no extra hop. The attach point connects an XSUB
// socket to every node's publisher and forwards, on its own thread, data to the observers
// and the observers' subscriptions to the publishers: a topic nobody observes is not even
// sent to it. It publishes the graph's topics and their schemas on "graph/topics"
// (msgs/graph.proto, GraphInfo) every second and as soon as an observer subscribes to it.
//
// Observers are lossy: a slow observer loses messages at the attach point (it sees gaps,
// and counts them by header.seq), and never slows the publishers. Except in simulated time
// (the launch info's clock): then the attach point waits for a full observer, as the nodes'
// publishers wait for it (bus::PublisherOptions::wait_when_full), and nobody loses anything,
// the graph's last messages included (closing, it delivers them for up to kFullLinger_ms). Each observer's queue
// holds at most kObserverQueue messages, and the nodes' messages in it at most
// observer_queue_bytes: the message limit is those bytes over an assumed mean message cost
// (kMeanCost_bytes, frames and their overhead; a 5 kHz graph's stream averages less), set
// once before any observer connects: ZeroMQ stalls a connected observer's stream when its
// limit changes (tests/bus/attach_test.cpp), so it is never adapted while running. The attach point's own GraphInfo (one a second, with the launch files:
// tens of kB) is not counted: a stopped observer's queue takes one a second beside the
// nodes' messages, until the queue is full. What a slow observer's queue held goes back to
// the system once it drained or left.
// Wire format and a Python client: core/bus/README.md.
//
// Observers may also publish, on the few inbound topics the graph accepts (param/set): they
// send bus messages upstream on the same connection (an XSUB socket: AttachSender), and the
// attach point republishes them on its inbound publisher, which the graph's nodes subscribe
// to like any other node's, and to the observers of that topic (a logger records them).
#include <atomic>
#include <cstdint>
#include <initializer_list>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include <zmq.hpp>

#include "core/bus/access.h"
#include "core/bus/client.h"
#include "core/bus/endpoints.h"
#include "core/bus/typed.h"
#include "msgs/graph.pb.h"

namespace enact::bus {

// the topic of GraphInfo messages
inline constexpr std::string_view kGraphTopic = "graph/topics";

// messages queued per observer (and from each publisher) at the attach point, at most
inline constexpr int kObserverQueue = 100000;

// the mean cost of a queued message assumed by the byte bound (64 MB: 100,000 messages)
inline constexpr std::size_t kMeanCost_bytes = 671;

// the messages an observer's queue may hold when a message costs cost_bytes (on average):
// as many as fit in queue_bytes, between 1 and kObserverQueue
int observer_queue_messages(std::size_t queue_bytes, std::size_t cost_bytes);

struct AttachOptions {
  // where observers connect; loopback only by default
  std::string bind_endpoint = kLoopbackAnyPort;
  // needed to bind an endpoint other machines can reach, together with `access`
  bool allow_remote = false;
  // who may attach (access.h): CURVE on the observers' socket, both directions, whatever its
  // endpoint; inbound messages pass only from operate keys, at their rate limit, stamped
  // with the key's name. None: no keys, loopback only.
  std::optional<Access> access{};
  // where refusals and drops of keyed clients are said (none: stderr)
  LogFn log{};
  // where an inbound ParamUpdate refused by its key's role is answered (ParamAck)
  std::string refused_ack_topic = "param/ack";
  // period of the GraphInfo messages, ms
  int graph_period_ms = 1000;
  // the most one observer's queue holds, bytes (counted as above)
  std::size_t observer_queue_bytes = std::size_t{64} << 20;
  // where the attach point republishes what observers send (empty: observers only listen)
  std::string inbound_endpoint{};
  // the topics observers may send on; anything else they send is dropped
  std::vector<std::string> inbound_topics{};
  // state topics: the last message of each is kept and sent at once to every observer that
  // subscribes to it (a late joiner sees the current state; the observers already
  // subscribed receive that copy again, with the same header.seq). An entry ending in '/'
  // names every topic under it, each kept on its own (param/values/<node>).
  std::vector<std::string> latched_topics{};
};

class AttachPoint {
 public:
  // binds the observers' endpoint and starts forwarding; `graph` names the graph in
  // GraphInfo. Throws config::Error for a malformed endpoint, one that cannot be bound, or
  // a non-local one without allow_remote and access.
  explicit AttachPoint(std::string graph, AttachOptions options = {});

  // stop()
  ~AttachPoint();

  AttachPoint(const AttachPoint&) = delete;
  AttachPoint& operator=(const AttachPoint&) = delete;

  // the endpoint actually bound (tcp port resolved): print it for observers
  const std::string& endpoint() const { return endpoint_; }

  // how many messages each observer's queue may hold now (observer_queue_bytes over the
  // cost of the largest message forwarded so far, at most kObserverQueue). Thread-safe.
  int observer_queue() const { return observer_queue_; }

  // forwards the topics published at `endpoint` (a BytePublisher::endpoint() of node
  // `node`) to observers; the publisher may start later. Throws config::Error for a
  // malformed endpoint. Thread-safe.
  void add_publisher(const std::string& node, const std::string& endpoint);

  // lists topic `name` of message type `type` (full name, e.g. "enact.msgs.DeviceState"),
  // published by node `publisher`, in GraphInfo (once: declaring it again changes nothing);
  // sends an updated GraphInfo at once. Thread-safe.
  void declare_topic(const std::string& name, const std::string& type, const std::string& publisher);

  // the same, with the type name taken from Msg
  template <class Msg>
  void declare_topic(const std::string& name, const std::string& publisher) {
    declare_topic(name, Msg::descriptor()->full_name(), publisher);
  }

  // the graph's name in GraphInfo from now on (the registry may number it: bridge-2); sends
  // an updated GraphInfo at once. Thread-safe.
  void set_graph_name(const std::string& graph);

  // how the graph was started, sent in every GraphInfo (launch_file, launch_text, params,
  // files; its header, graph, topics and descriptor_set are ignored). Thread-safe.
  void set_launch_info(const msgs::GraphInfo& launch);

  // stops forwarding and joins the thread; observers stay connected but receive nothing.
  // Safe to call twice.
  void stop();

 private:
  struct Topic {
    std::string name;
    std::string type;
    std::string publisher;
  };

  // sends a command to the forwarding thread and waits for its answer ("" when done)
  void request(std::initializer_list<std::string_view> frames);
  void run();
  bool handle_command();
  void forward_data();
  bool forward_from_observers();
  void relay_inbound(zmq::message_t& first);
  void refuse_inbound(const std::vector<zmq::message_t>& frames, const std::string& reason);
  void publish_graph();
  void send_latched(std::string_view prefix);
  // a state topic (latched_topics names it, or a folder of it)
  bool latched(std::string_view topic) const;
  // a message of the attach point's own to the observers (dropped when none subscribed)
  void publish_own(std::string_view topic, const std::string& type, const std::string& payload);

  std::string graph_;         // owned by the forwarding thread
  std::string endpoint_;
  int graph_period_ms_;
  zmq::socket_t xpub_;        // observers connect here
  zmq::socket_t xsub_;        // connects to every node's publisher
  zmq::socket_t control_;     // forwarding thread's end of the command pair
  zmq::socket_t requester_;   // callers' end, used under request_mutex_
  zmq::socket_t inbound_;     // republishes what observers send (bound only with an endpoint)
  std::vector<std::string> inbound_topics_;
  std::vector<std::string> latched_topics_;
  std::map<std::string, std::vector<std::string>, std::less<>> latched_;  // topic -> frames of its last message (forwarding thread)
  std::optional<Access> access_;
  std::unique_ptr<CurveServer> curve_;   // the observers' socket's keys, while it lives
  std::unique_ptr<InboundGate> gate_;    // inbound policy (with access only)
  std::string refused_ack_topic_;
  std::uint64_t refused_seq_ = 0;
  std::mutex request_mutex_;
  std::atomic<bool> failed_ = false;
  std::string failure_;       // why the thread stopped, set before failed_
  // owned by the forwarding thread
  std::vector<Topic> topics_;
  std::mutex launch_mutex_;
  msgs::GraphInfo launch_;    // launch details, under launch_mutex_
  // simulated time (launch_.clock()): observers lose nothing, the graph waits for them
  std::atomic<bool> lossless_{false};
  bool nodrop_ = false;       // the forwarding thread's: ZMQ_XPUB_NODROP set on xpub_
  std::string descriptor_set_;
  std::uint64_t graph_seq_ = 0;
  std::vector<zmq::message_t> frames_;  // the message being forwarded
  int observer_queue_ = kObserverQueue;
  std::thread thread_;
};

// an observer's way to send on a graph's inbound topics (param/set): an XSUB socket
// connected to the attach point, sending bus messages upstream. Nothing tells the sender
// whether a message arrived (it is dropped while the connection is not up yet, and when the
// topic is not inbound): senders expect an answer and repeat the message until it comes.
// Used by one thread at a time.
class AttachSender {
 public:
  // connects to `endpoint` (an AttachPoint::endpoint()) with `keys` (attach_connect);
  // `source` goes into header.source. Throws config::Error for a malformed endpoint or a
  // failed handshake.
  AttachSender(const std::string& endpoint, std::string source, const ClientKeys& keys = {});

  // fills msg.header (seq +1 per call, stamp_ns now, source) and sends it on `topic`
  // without blocking; false when it could not be queued
  template <class Msg>
  bool send(const std::string& topic, Msg& msg) {
    msgs::Header& h = *msg.mutable_header();
    h.set_seq(++seq_);
    h.set_stamp_ns(rt::now_ns());
    h.set_source(source_);
    return send_bytes(topic, Msg::descriptor()->full_name(), msg.SerializeAsString());
  }

 private:
  bool send_bytes(std::string_view topic, std::string_view type, const std::string& payload);

  zmq::socket_t socket_;
  std::string source_;
  std::uint64_t seq_ = 0;
};

}  // namespace enact::bus
