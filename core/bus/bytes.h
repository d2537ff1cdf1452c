#pragma once
// The byte layer of the bus: publish and subscribe raw bus messages, three ZeroMQ frames
// [topic] [type] [payload] (wire format: core/bus/README.md), with per-topic counters.
// The typed layer (typed.h) serialises protobuf messages on top of it.
//
// Threads: a BytePublisher or ByteSubscriber is used by one thread at a time (ZeroMQ sockets
// are not thread-safe), counters included.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <zmq.hpp>

namespace enact::bus {

// traffic on one topic, cumulative. A publisher fills sent and dropped; a subscriber fills
// received, malformed, dropped (conflation), gaps and lost. A subscriber whose queue is full
// loses messages alone, without the publisher knowing: it counts them in gaps and lost.
struct TopicCounters {
  std::uint64_t sent = 0;       // messages the socket accepted
  std::uint64_t dropped = 0;    // publisher: refused by the socket (an error; never a full queue);
                                // subscriber: skipped by conflation (a newer one was waiting)
  std::uint64_t received = 0;   // well-formed messages handed to the caller
  std::uint64_t malformed = 0;  // messages refused: frame count, type name, or parse failure
  std::uint64_t gaps = 0;       // jumps in header.seq (typed layer)
  std::uint64_t lost = 0;       // messages missing in those jumps
};

struct PublisherOptions {
  std::string node;     // name of the publishing node: typed publishers write it in header.source
  int send_hwm = 1000;  // messages queued per subscriber; past it, that subscriber loses messages
  // flow control, for benchmarks and replay (enact play) only: send() refuses a message
  // (counted as dropped) while any subscriber's queue is full, so one stopped subscriber
  // stops every other (ZMQ_XPUB_NODROP). Never for a loop's nodes: an observer could stall
  // the loop.
  bool refuse_when_full = false;
  // simulated time (the graph clock): refuse_when_full, and send() waits while refused (at
  // most kFullWait_s, then drops), so the graph goes only as fast as its slowest subscriber
  // takes its messages and no observer loses one to the clock's speed
  bool wait_when_full = false;
};

// the longest a wait_when_full publisher waits for a full subscriber before it drops
inline constexpr double kFullWait_s = 2.0;
// how long a closing wait_when_full publisher still delivers what it queued, ms (others:
// kPublisherLinger_ms, context.h). A node in simulated time ends with its last messages still
// queued toward a slow observer; 100 ms dropped the end of a trial's recording on a loaded
// machine. A subscriber gone ends the wait at once
inline constexpr int kFullLinger_ms = 10000;

// sends one frame without blocking; while the socket refuses it (a full subscriber of an XPUB
// socket with ZMQ_XPUB_NODROP) and `wait` is set, tries again every 20 us for at most
// kFullWait_s. Whether it went; throws zmq::error_t as the socket does
bool send_frame(zmq::socket_t& socket, const void* data, std::size_t size, zmq::send_flags flags, bool wait);

// a publisher bound to one endpoint; any number of subscribers connect to it
class BytePublisher {
 public:
  // binds `endpoint` (ipc://, tcp://, inproc://; tcp port * picks a free one); throws
  // config::Error if the endpoint is malformed or cannot be bound
  BytePublisher(const std::string& endpoint, PublisherOptions options = {});
  BytePublisher(const BytePublisher&) = delete;
  BytePublisher& operator=(const BytePublisher&) = delete;

  // the endpoint actually bound (tcp port resolved): what subscribers connect to
  const std::string& endpoint() const { return endpoint_; }

  // the node name given in the options
  const std::string& node() const { return node_; }

  // sends one bus message without ever blocking. Each subscriber of `topic` gets it, except
  // one whose queue is full: that one alone loses it (and sees a gap in header.seq), so a
  // stopped subscriber never holds back the others (see README, "Delivery"). false when the
  // socket refuses it, or with refuse_when_full a queue is full (counted as dropped). With no subscriber the message is discarded
  // and still counts as sent. The first message on a new topic allocates its counters.
  bool send(std::string_view topic, std::string_view type, const void* data, std::size_t size) noexcept;

  // whether some subscriber's subscription matches `topic` (reads pending subscription notices)
  bool has_subscribers(std::string_view topic) { return subscriber_count(topic) > 0; }
  // how many subscriptions match `topic`: one per subscriber socket (an attach point counts
  // once, however many observers it serves)
  int subscriber_count(std::string_view topic);

  // counters of one topic (zero if nothing was sent on it)
  TopicCounters counters(std::string_view topic) const;

  // counters of every topic sent on, by topic name
  std::vector<std::pair<std::string, TopicCounters>> all_counters() const;

  // the ZMQ_XPUB socket (readable when a subscription notice is pending)
  zmq::socket_t& socket() { return socket_; }

  // the topics this publisher carries, with their message types (full protobuf names), in
  // the order declared: a typed Publisher declares its topic when it is made
  void declare(std::string topic, std::string type) { declared_.emplace_back(std::move(topic), std::move(type)); }
  const std::vector<std::pair<std::string, std::string>>& declared() const { return declared_; }

 private:
  void read_subscriptions();

  zmq::socket_t socket_;
  std::string endpoint_;
  std::string node_;
  bool wait_when_full_ = false;
  std::map<std::string, TopicCounters, std::less<>> counters_;
  std::multiset<std::string, std::less<>> subscriptions_;  // prefixes, once per subscriber asking
  std::vector<std::pair<std::string, std::string>> declared_;  // (topic, type)
};

// one received bus message; its frames are reused by ByteSubscriber::receive(RawMessage&, ...)
struct RawMessage {
  zmq::message_t topic_frame;
  zmq::message_t type_frame;
  zmq::message_t payload_frame;

  std::string_view topic() const { return topic_frame.to_string_view(); }
  std::string_view type() const { return type_frame.to_string_view(); }
  const void* payload() const { return payload_frame.data(); }
  std::size_t payload_size() const { return payload_frame.size(); }
};

// a subscriber: connects to any number of publishers (or an attach point) and receives the
// topics it subscribed to, exactly (ZeroMQ filters by prefix; this class checks the topic frame)
class ByteSubscriber {
 public:
  ByteSubscriber();
  ByteSubscriber(const ByteSubscriber&) = delete;
  ByteSubscriber& operator=(const ByteSubscriber&) = delete;

  // connects to a publisher's or an attach point's endpoint (the publisher need not exist
  // yet: ZeroMQ retries); throws config::Error if the endpoint is malformed
  void connect(const std::string& endpoint);

  // undoes connect(endpoint) (zmq::error_t if it was not connected)
  void disconnect(const std::string& endpoint);

  // receives `topic` from now on (a late joiner gets only later messages); throws
  // std::logic_error when conflating and another topic is already subscribed
  void subscribe(const std::string& topic);

  // stops receiving `topic` (its counters are kept)
  void unsubscribe(const std::string& topic);

  // messages queued per publisher before that publisher sees this subscriber as full; takes
  // effect for connections made after the call, so call it before connect()
  void set_receive_hwm(int messages);

  // latest-only delivery: receive() returns the newest message waiting and counts the older
  // ones as dropped. Only for a subscriber of a single topic (others' messages would be
  // skipped too): throws std::logic_error if more than one topic is subscribed. ZMQ_CONFLATE
  // itself cannot be used: it keeps one frame, not one multipart message.
  void set_conflate(bool conflate);
  bool conflating() const { return conflate_; }

  // waits up to timeout_ms (0: do not wait, -1: forever) for a message on a subscribed topic.
  // A message with a wrong number of frames counts as malformed and is skipped; a message on
  // a topic that only shares a prefix with a subscribed one is skipped silently. Never
  // throws on bad input. nullopt on timeout, or when a signal interrupts the wait.
  std::optional<RawMessage> receive(int timeout_ms);

  // the same into `out`, reusing its frames; false on timeout or signal
  bool receive(RawMessage& out, int timeout_ms);

  // counters of one topic (zero if not subscribed)
  TopicCounters counters(std::string_view topic) const;

  // counters of every topic subscribed to, by topic name
  std::vector<std::pair<std::string, TopicCounters>> all_counters() const;

  // for the typed layer: a message received on `topic` turned out malformed (wrong type,
  // parse failure): moves it from received to malformed
  void count_rejected(std::string_view topic) noexcept;

  // for the typed layer: a message of `topic` that came another way (the loop's hop)
  void count_received(std::string_view topic) noexcept;

  // for the typed layer: a jump in header.seq on `topic`, `lost` messages missing
  void count_gap(std::string_view topic, std::uint64_t lost) noexcept;

  // receives a signal interrupted (libzmq's EINTR: the receive returns nothing yet, or is
  // retried inside a multipart message): never an error, no message lost
  std::uint64_t interruptions() const { return interruptions_; }

  // the ZMQ_SUB socket, for zmq::poll over several sockets
  zmq::socket_t& socket() { return socket_; }

 private:
  enum class Read { none, interrupted, skipped, ok };
  Read read_one(RawMessage& out, int timeout_ms);

  zmq::socket_t socket_;
  bool conflate_ = false;
  std::map<std::string, TopicCounters, std::less<>> counters_;
  std::set<std::string, std::less<>> subscribed_;
  RawMessage newer_;        // conflation: the message read after the one kept
  zmq::message_t extra_;    // frames past the third of a malformed message
  std::uint64_t interruptions_ = 0;
};

}  // namespace enact::bus
