#pragma once
// The typed layer of the bus: Publisher<Msg> and Subscriber<Msg> over the byte layer, for
// the stream messages of msgs/ (every one has `Header header = 1`). The publisher fills the
// header and serialises into a buffer it reuses; the subscriber checks the type name,
// parses, and counts sequence gaps per publishing node.
#include <algorithm>
#include <climits>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/bus/bytes.h"
#include "core/bus/loop_link.h"
#include "core/rt/clock.h"
#include "msgs/common.pb.h"

#include <google/protobuf/arena.h>

namespace enact::bus {

// publishes Msg on one topic. One Publisher per topic and node: it owns the topic's sequence.
template <class Msg>
class Publisher {
 public:
  // publishes on `topic` through `bytes` (which must outlive it), declared there
  Publisher(BytePublisher& bytes, std::string topic)
      : bytes_(bytes), topic_(std::move(topic)), type_(Msg::descriptor()->full_name()) {
    bytes_.declare(topic_, std::string(type_));
  }
  ~Publisher() { send_held(); }
  Publisher(const Publisher&) = delete;
  Publisher& operator=(const Publisher&) = delete;

  // fills msg.header (seq: +1 per call, from 1; stamp_ns: now, only if 0; source: the node
  // name of the BytePublisher), serialises and sends without blocking. false when the message
  // was dropped (a subscriber's queue is full): its seq is used anyway, so subscribers see
  // the drop as a gap. Allocates nothing once the buffer has grown to the largest message
  // size (the header's source string is set once per message object).
  // A message object reused for the next publish keeps its stamp: set header.stamp_ns to
  // the sample time, or to 0 for "now", before each call.
  bool publish(Msg& msg) {
    send_held();  // a copy still held goes first: none is ever lost
    // header
    msgs::Header& h = *msg.mutable_header();
    h.set_seq(++seq_);
    if (h.stamp_ns() == 0) h.set_stamp_ns(rt::now_ns());
    if (h.source() != bytes_.node()) h.set_source(bytes_.node());
    // serialise into the buffer, grown only for a message larger than any before
    const std::size_t size = msg.ByteSizeLong();
    if (size > buffer_.size()) buffer_.resize(size);
    msg.SerializeWithCachedSizesToArray(buffer_.data());
    // over the loop's hop alone when it went there (its reader waits for it): the bus copy,
    // for every observer, is held until the loop has its answer (send_held). Without a peer on
    // the hop (not yet connected, a simulator restarting) the bus carries the loop: at once
    if (hop_ && hop_->send(buffer_.data(), size)) {
      held_ = size;
      return true;
    }
    return bytes_.send(topic_, type_, buffer_.data(), size);
  }

  // with a hop: sends the bus copy of the last message published, if it is still held. A loop
  // calls it once it has its answer (or gave up on it), before it publishes again: the
  // observers' copy (a ZeroMQ send, its I/O thread woken) then costs the round trip nothing
  bool send_held() {
    if (held_ == 0) return true;
    return bytes_.send(topic_, type_, buffer_.data(), std::exchange(held_, 0));
  }

  // as publish(msg), numbered `seq` (the number the loop gave it, which a copy sent over its
  // own hop carries too); the next publish() counts on from it
  bool publish(Msg& msg, std::uint64_t seq) {
    seq_ = seq - 1;
    return publish(msg);
  }

  // every message published from now on goes over `hop` too (the loop's same-host link,
  // which must outlive this publisher), its bus copy held until send_held() or the next
  // publish (sent at once when the hop has no peer); nullptr: the bus alone
  void also_over(LoopLink* hop) { hop_ = hop; }

  // header.seq of the last message published (0 before the first)
  std::uint64_t last_seq() const { return seq_; }

  const std::string& topic() const { return topic_; }

  // this topic's counters on the BytePublisher
  TopicCounters counters() const { return bytes_.counters(topic_); }

 private:
  BytePublisher& bytes_;
  std::string topic_;
  std::string_view type_;  // Msg's full name, owned by its descriptor
  std::uint64_t seq_ = 0;
  std::vector<std::uint8_t> buffer_;
  LoopLink* hop_ = nullptr;
  std::size_t held_ = 0;  // the size of the bus copy held in buffer_ (0: none)
};

// msg sent over a same-host link, serialised into `buffer` (LoopLink::kMaxMessage bytes, the
// most a link message holds): false when it was not sent (larger than that, no peer, the
// peer's queue full). Allocates nothing, never blocks: the loop's answer
template <class Msg>
bool send_over(LoopLink& link, const Msg& msg, std::uint8_t (&buffer)[LoopLink::kMaxMessage]) {
  const std::size_t size = msg.ByteSizeLong();
  if (size > sizeof buffer) return false;
  msg.SerializeWithCachedSizesToArray(buffer);
  return link.send(buffer, size);
}

// a message a loop parses again and again without allocating. Parsing into a reused message
// frees its parts first (Protobuf's Clear() deletes the sub-messages: header, vectors) and
// makes them again, a few allocations a message; this one lives on an arena with a block of
// its own, emptied before each parse. Use the message fresh() returns until the next call.
// The first parse on a thread other than the constructor's may allocate (the arena's part
// for that thread), none after.
template <class Msg, std::size_t kBlockBytes = 8192>
class ReusedMessage {
 public:
  ReusedMessage() : arena_(options(block_)), msg_(google::protobuf::Arena::CreateMessage<Msg>(&arena_)) {}
  ReusedMessage(const ReusedMessage&) = delete;
  ReusedMessage& operator=(const ReusedMessage&) = delete;

  // an empty message to parse into (the one before is gone)
  Msg& fresh() {
    arena_.Reset();
    msg_ = google::protobuf::Arena::CreateMessage<Msg>(&arena_);
    return *msg_;
  }
  const Msg& operator*() const { return *msg_; }
  const Msg* operator->() const { return msg_; }

 private:
  static google::protobuf::ArenaOptions options(char* block) {
    google::protobuf::ArenaOptions o;
    o.initial_block = block;
    o.initial_block_size = kBlockBytes;
    return o;
  }
  alignas(16) char block_[kBlockBytes];
  google::protobuf::Arena arena_;
  Msg* msg_;
};

// receives Msg on one topic. Counters live on the ByteSubscriber, per topic.
//
// receive() takes every message off the ByteSubscriber's socket and skips those of other
// topics: give each Subscriber its own ByteSubscriber, or, to read several topics from one
// socket, call ByteSubscriber::receive() and hand each message to the matching accept().
template <class Msg>
class Subscriber {
 public:
  // subscribes `bytes` (which must outlive it) to `topic`
  Subscriber(ByteSubscriber& bytes, std::string topic)
      : bytes_(bytes), topic_(std::move(topic)), type_(Msg::descriptor()->full_name()) {
    bytes_.subscribe(topic_);
  }

  // waits up to timeout_ms (0: do not wait, -1: forever) for the next valid message.
  // Messages of the wrong type or that fail to parse are counted malformed and skipped;
  // never throws on bad input. nullopt on timeout, or when a signal interrupts the wait.
  std::optional<Msg> receive(int timeout_ms) {
    Msg msg;
    if (!receive(msg, timeout_ms)) return std::nullopt;
    return msg;
  }

  // the same into `out`, reusing its memory; false on timeout or signal
  bool receive(Msg& out, int timeout_ms) {
    const std::int64_t deadline_ns = rt::now_ns() + std::int64_t{timeout_ms} * 1'000'000;
    for (int wait_ms = timeout_ms; bytes_.receive(raw_, wait_ms);) {
      if (accept(raw_, out)) return true;
      // a skipped message does not extend the wait
      if (timeout_ms >= 0) wait_ms = rt::ms_until(deadline_ns);
    }
    return false;
  }

  // decodes `raw` into `out` if it is a valid message of this topic: false (and nothing
  // counted) for another topic; false and counted malformed for a wrong type name or a
  // payload that does not parse. Counts header.seq gaps per source node.
  bool accept(const RawMessage& raw, Msg& out) {
    if (raw.topic() != topic_) return false;
    if (raw.type() != type_ || raw.payload_size() > INT_MAX ||
        !out.ParseFromArray(raw.payload(), static_cast<int>(raw.payload_size()))) {
      bytes_.count_rejected(topic_);
      return false;
    }
    track(out.header());
    return true;
  }

  // decodes a payload of this topic that came another way (the loop's hop) into `out`:
  // counted received, or malformed when it does not parse; sequence gaps counted as above
  bool accept_payload(const void* data, std::size_t size, Msg& out) {
    if (size > INT_MAX || !out.ParseFromArray(data, static_cast<int>(size))) {
      bytes_.count_received(topic_);
      bytes_.count_rejected(topic_);
      return false;
    }
    bytes_.count_received(topic_);
    track(out.header());
    return true;
  }

  const std::string& topic() const { return topic_; }

  // this topic's counters on the ByteSubscriber
  TopicCounters counters() const { return bytes_.counters(topic_); }

 private:
  struct SourceSeq {
    std::string source;
    std::uint64_t last_seq = 0;
  };

  // a jump past last_seq + 1 is a gap; so is a smaller seq past 1 (the publisher restarted:
  // a new stream, whose messages before this one were lost). A first message (late join) or
  // seq 0 (not filled) are not. A conflating subscriber skips on purpose: its skips are
  // counted as dropped, not as gaps.
  void track(const msgs::Header& h) {
    if (h.seq() == 0) return;
    for (SourceSeq& s : sources_) {
      if (s.source != h.source()) continue;
      const std::uint64_t expected = h.seq() > s.last_seq ? s.last_seq + 1 : 1;
      if (h.seq() > expected && !bytes_.conflating()) bytes_.count_gap(topic_, h.seq() - expected);
      s.last_seq = h.seq();
      return;
    }
    sources_.push_back({h.source(), h.seq()});
  }

  ByteSubscriber& bytes_;
  std::string topic_;
  std::string_view type_;  // Msg's full name, owned by its descriptor
  RawMessage raw_;
  std::vector<SourceSeq> sources_;
};

}  // namespace enact::bus
