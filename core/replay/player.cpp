#include "core/replay/player.h"

#include <algorithm>

#include "core/config/format.h"
#include "core/graph/launcher_pipe.h"
#include "core/graph/graph_dir.h"
#include "core/graph/sockets.h"
#include "core/graph/stop.h"
#include "core/session/session.h"
#include "core/rt/clock.h"

namespace enact::graph {

bool PlayOptions::wanted(std::string_view topic) const { return topics.empty() || std::find(topics.begin(), topics.end(), topic) != topics.end(); }

std::string PlayOptions::out_topic(const std::string& topic) const {
  const auto it = remap.find(topic);
  return it == remap.end() ? topic : it->second;
}

Player::Player(record::Reader& r, PlayOptions options, GraphSession* session)
    : r_(r), o_(std::move(options)), session_(session), first_ns_(r.time_span().first) {
  for (const auto& [id, c] : r_.channels()) {
    if (o_.wanted(c.topic)) of(c);
  }
  for (const auto& [node, pub] : pubs_) announce_topics(*pub);
}

Player::~Player() = default;

bus::BytePublisher& Player::publisher(const record::Channel& c) {
  const auto p = c.metadata.find("publisher");
  const std::string node = !o_.as_node.empty() ? o_.as_node : p != c.metadata.end() && !p->second.empty() ? p->second : "play";
  auto& slot = pubs_[node];
  if (!slot) {
    // flow control: a recording is not a device, and it loses nothing to a subscriber that
    // is not reading yet (the simulator waiting for its observers): send() refuses while a
    // subscriber's queue is full and play_once tries again. Observers attached through the
    // session's attach point never hold it: the attach point drops for a slow observer
    slot = std::make_unique<bus::BytePublisher>(session_ ? session_->node_endpoint(node) : node_endpoint(node),
                                                bus::PublisherOptions{.node = node, .send_hwm = 1000, .refuse_when_full = true});
    if (session_) session_->attach().add_publisher(node, slot->endpoint());
  }
  const auto s = r_.schemas().find(c.schema_id);
  if (s != r_.schemas().end()) {
    slot->declare(o_.out_topic(c.topic), s->second.name);
    if (session_) session_->attach().declare_topic(o_.out_topic(c.topic), s->second.name, node);
  }
  return *slot;
}

bus::BytePublisher& Player::of(const record::Channel& c) {
  auto it = by_channel_.find(c.id);
  if (it == by_channel_.end()) it = by_channel_.emplace(c.id, &publisher(c)).first;
  return *it->second;
}

bool Player::all_heard() const {
  for (const auto& [id, pub] : by_channel_) {
    if (!pub->has_subscribers(o_.out_topic(r_.channels().at(id).topic))) return false;
  }
  return true;
}

void Player::wait_for_subscribers(const std::function<void(const std::string&)>& log) const {
  const std::int64_t give_up = rt::now_ns() + static_cast<std::int64_t>(o_.wait_s * 1e9);
  const std::int64_t grace = std::min(give_up, rt::now_ns() + 200'000'000);
  while (!all_heard() && rt::now_ns() < grace && !stop_requested()) rt::sleep_until_ns(rt::now_ns() + 5'000'000);
  if (all_heard() || o_.wait_s <= 0.0) return;
  log("waiting up to " + config::number(o_.wait_s) + " s for a subscriber of every topic played (--wait S)");
  while (!all_heard() && rt::now_ns() < give_up && !stop_requested()) rt::sleep_until_ns(rt::now_ns() + 5'000'000);
  log(all_heard() ? "every topic has a subscriber; playing" : "a topic still has no subscriber; playing anyway (what is sent before one listens is lost)");
}

void Player::play_once(const PlayTiming& timing, const std::function<void(std::int64_t log_ns)>& sent) {
  bool started = false;
  const std::int64_t from_ns = first_ns_ + static_cast<std::int64_t>(o_.offset_s * 1e9);
  r_.for_each([&](const record::Message& m) {
    if (m.log_time_ns < from_ns || !o_.wanted(m.topic)) return true;
    if (!started) timing.restart(m.log_time_ns), started = true;
    bus::BytePublisher& pub = of(*m.channel);
    if (!timing.wait(m.log_time_ns)) return false;
    const std::string topic = o_.out_topic(std::string(m.topic));
    // flow control: a full subscriber queue waits, nothing is dropped
    while (!pub.send(topic, m.schema_name, m.data.data(), m.data.size()) && !stop_requested()) rt::sleep_until_ns(rt::now_ns() + 50'000);
    sent(m.log_time_ns);
    return !stop_requested();
  });
}

}  // namespace enact::graph
