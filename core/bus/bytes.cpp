#include "core/bus/bytes.h"

#include <cerrno>
#include <chrono>
#include <stdexcept>

#include "core/bus/context.h"
#include "core/bus/endpoints.h"
#include "core/config/yaml.h"
#include "core/rt/clock.h"

namespace enact::bus {
namespace {

// a bus message has exactly these frames: topic, type, payload
constexpr int kFrames = 3;

// XPUB subscription notices: one frame, this byte then the subscribed prefix
constexpr char kSubscribe = 1;
constexpr char kUnsubscribe = 0;

template <class Map>
TopicCounters find_counters(const Map& counters, std::string_view topic) {
  const auto it = counters.find(topic);
  return it == counters.end() ? TopicCounters{} : it->second;
}

template <class Map>
std::vector<std::pair<std::string, TopicCounters>> list_counters(const Map& counters) {
  return {counters.begin(), counters.end()};
}

}  // namespace

bool send_frame(zmq::socket_t& socket, const void* data, std::size_t size, zmq::send_flags flags, bool wait) {
  if (socket.send(zmq::const_buffer(data, size), flags)) return true;
  const std::int64_t give_up = wait ? rt::now_ns() + static_cast<std::int64_t>(kFullWait_s * 1e9) : 0;
  while (rt::now_ns() < give_up) {
    rt::sleep_until_ns(rt::now_ns() + 20'000);
    if (socket.send(zmq::const_buffer(data, size), flags)) return true;
  }
  return false;
}

BytePublisher::BytePublisher(const std::string& endpoint, PublisherOptions options)
    : socket_(make_socket(zmq::socket_type::xpub)), node_(std::move(options.node)) {
  validate_endpoint(endpoint, "publisher endpoint");
  if (options.send_hwm < 1) {
    throw config::Error("publisher '" + endpoint + "': send_hwm must be >= 1, got " + std::to_string(options.send_hwm) +
                        "\n  fix: give the number of messages queued per subscriber, e.g. 1000");
  }
  // never block, and never let one subscriber hold back the others: a subscriber whose
  // queue is full loses the message alone (ZeroMQ's default XPUB behaviour, no
  // ZMQ_XPUB_NODROP); it sees the jump in header.seq and counts it as a gap
  socket_.set(zmq::sockopt::sndhwm, options.send_hwm);
  socket_.set(zmq::sockopt::xpub_nodrop, options.refuse_when_full || options.wait_when_full);
  wait_when_full_ = options.wait_when_full;
  if (wait_when_full_) socket_.set(zmq::sockopt::linger, kFullLinger_ms);
  // every subscriber's subscribe and unsubscribe notice, not just the first and last: counted
  socket_.set(zmq::sockopt::xpub_verboser, true);
  try {
    socket_.bind(endpoint);
  } catch (const zmq::error_t& e) {
    throw config::Error("publisher endpoint '" + endpoint + "': cannot bind: " + e.what() +
                        "\n  fix: choose a free port (or * for any), or an ipc path no other node binds");
  }
  endpoint_ = socket_.get(zmq::sockopt::last_endpoint);
}

bool BytePublisher::send(std::string_view topic, std::string_view type, const void* data, std::size_t size) noexcept {
  auto it = counters_.find(topic);
  if (it == counters_.end()) it = counters_.emplace(std::string(topic), TopicCounters{}).first;
  TopicCounters& c = it->second;
  // three frames, none blocking; a subscriber whose queue is full at the first frame gets
  // none of them (the high-water mark counts whole messages). Only a socket error refuses
  constexpr auto more = zmq::send_flags::dontwait | zmq::send_flags::sndmore;
  try {
    if (!send_frame(socket_, topic.data(), topic.size(), more, wait_when_full_)) {
      ++c.dropped;
      return false;
    }
    socket_.send(zmq::const_buffer(type.data(), type.size()), more);
    socket_.send(zmq::const_buffer(data, size), zmq::send_flags::dontwait);
  } catch (const zmq::error_t&) {
    ++c.dropped;
    return false;
  }
  ++c.sent;
  return true;
}

void BytePublisher::read_subscriptions() {
  // the XPUB socket reports each subscriber's subscriptions (verboser)
  zmq::message_t notice;
  for (Received got; (got = recv_frame(socket_, notice, zmq::recv_flags::dontwait)) != Received::none;) {
    if (got == Received::interrupted) continue;
    const std::string_view n = notice.to_string_view();
    if (n.empty()) continue;
    const std::string_view prefix = n.substr(1);
    if (n.front() == kSubscribe) subscriptions_.emplace(prefix);
    if (n.front() == kUnsubscribe) {
      const auto it = subscriptions_.find(prefix);
      if (it != subscriptions_.end()) subscriptions_.erase(it);
    }
  }
}

int BytePublisher::subscriber_count(std::string_view topic) {
  read_subscriptions();
  int n = 0;
  for (const std::string& prefix : subscriptions_) n += topic.starts_with(prefix) ? 1 : 0;
  return n;
}

TopicCounters BytePublisher::counters(std::string_view topic) const { return find_counters(counters_, topic); }

std::vector<std::pair<std::string, TopicCounters>> BytePublisher::all_counters() const { return list_counters(counters_); }

ByteSubscriber::ByteSubscriber() : socket_(make_socket(zmq::socket_type::sub)) {}

void ByteSubscriber::connect(const std::string& endpoint) {
  validate_endpoint(endpoint, "subscriber endpoint");
  socket_.connect(endpoint);
}

void ByteSubscriber::disconnect(const std::string& endpoint) { socket_.disconnect(endpoint); }

void ByteSubscriber::subscribe(const std::string& topic) {
  if (conflate_ && !subscribed_.empty() && !subscribed_.contains(topic)) {
    throw std::logic_error("bus: a conflating subscriber takes a single topic; cannot add '" + topic + "'");
  }
  if (!subscribed_.insert(topic).second) return;
  counters_.try_emplace(topic);
  socket_.set(zmq::sockopt::subscribe, topic);
}

void ByteSubscriber::unsubscribe(const std::string& topic) {
  if (subscribed_.erase(topic) == 0) return;
  socket_.set(zmq::sockopt::unsubscribe, topic);
}

void ByteSubscriber::set_receive_hwm(int messages) { socket_.set(zmq::sockopt::rcvhwm, messages); }

void ByteSubscriber::set_conflate(bool conflate) {
  if (conflate && subscribed_.size() > 1) {
    throw std::logic_error("bus: conflation needs a subscriber of a single topic; this one has " +
                           std::to_string(subscribed_.size()));
  }
  conflate_ = conflate;
}

ByteSubscriber::Read ByteSubscriber::read_one(RawMessage& out, int timeout_ms) {
  // wait for the first frame; a whole multipart message arrives at once
  Received got = recv_frame(socket_, out.topic_frame, zmq::recv_flags::dontwait);
  if (got == Received::none) {
    if (timeout_ms == 0) return Read::none;
    zmq::pollitem_t item{socket_.handle(), 0, ZMQ_POLLIN, 0};
    try {
      if (zmq::poll(&item, 1, std::chrono::milliseconds(timeout_ms)) == 0) return Read::none;
    } catch (const zmq::error_t& e) {
      if (e.num() == EINTR) return Read::interrupted;
      throw;
    }
    got = recv_frame(socket_, out.topic_frame, zmq::recv_flags::dontwait);
    if (got == Received::none) return Read::skipped;
  }
  if (got == Received::interrupted) {
    ++interruptions_;
    return Read::interrupted;
  }
  // read every frame, keeping the first three: a multipart message is delivered whole, so
  // its other frames are there (a signal only delays them)
  int frames = 1;
  bool more = out.topic_frame.more();
  zmq::message_t* const slots[] = {&out.type_frame, &out.payload_frame};
  for (; more; ++frames) {
    zmq::message_t& frame = frames < kFrames ? *slots[frames - 1] : extra_;
    while (recv_frame(socket_, frame, zmq::recv_flags::none) == Received::interrupted) ++interruptions_;
    more = frame.more();
  }
  // exact topic, then shape
  const auto it = counters_.find(out.topic());
  if (it == counters_.end() || !subscribed_.contains(out.topic())) return Read::skipped;
  if (frames != kFrames) {
    ++it->second.malformed;
    return Read::skipped;
  }
  ++it->second.received;
  return Read::ok;
}

bool ByteSubscriber::receive(RawMessage& out, int timeout_ms) {
  // wait until the deadline itself: milliseconds rounded up, and again if zmq_poll (whose
  // clock may be a millisecond stale) returns before it
  const std::int64_t deadline_ns = rt::now_ns() + std::int64_t{timeout_ms} * 1'000'000;
  const auto wait_ms = [&] { return timeout_ms < 0 ? -1 : rt::ms_until(deadline_ns); };
  Read r = Read::skipped;
  while ((r = read_one(out, wait_ms())) == Read::skipped || (r == Read::none && wait_ms() != 0)) {
  }
  if (r != Read::ok) return false;
  if (!conflate_) return true;
  // conflation: keep the newest message already waiting, count the older ones as dropped
  TopicCounters& c = counters_.find(out.topic())->second;
  for (Read next; (next = read_one(newer_, 0)) != Read::none;) {
    if (next != Read::ok) continue;
    --c.received;
    ++c.dropped;
    std::swap(out, newer_);
  }
  return true;
}

std::optional<RawMessage> ByteSubscriber::receive(int timeout_ms) {
  RawMessage m;
  if (!receive(m, timeout_ms)) return std::nullopt;
  return m;
}

TopicCounters ByteSubscriber::counters(std::string_view topic) const { return find_counters(counters_, topic); }

std::vector<std::pair<std::string, TopicCounters>> ByteSubscriber::all_counters() const {
  return list_counters(counters_);
}

void ByteSubscriber::count_rejected(std::string_view topic) noexcept {
  const auto it = counters_.find(topic);
  if (it == counters_.end()) return;
  if (it->second.received > 0) --it->second.received;
  ++it->second.malformed;
}

void ByteSubscriber::count_received(std::string_view topic) noexcept {
  const auto it = counters_.find(topic);
  if (it != counters_.end()) ++it->second.received;
}

void ByteSubscriber::count_gap(std::string_view topic, std::uint64_t lost) noexcept {
  const auto it = counters_.find(topic);
  if (it == counters_.end()) return;
  ++it->second.gaps;
  it->second.lost += lost;
}

}  // namespace enact::bus
