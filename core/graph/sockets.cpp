#include "core/graph/sockets.h"

#include <poll.h>

#include <algorithm>
#include <cstdlib>

#include "core/config/env.h"
#include "core/graph/launcher_pipe.h"
#include "core/graph/process.h"
#include "core/graph/stop.h"
#include "core/rt/clock.h"

namespace enact::graph {

bool wait_readable(zmq::socket_t& socket, std::int64_t deadline_ns) {
  // ZMQ_FD is edge-triggered: check ZMQ_EVENTS before every wait
  const int fd = socket.get(zmq::sockopt::fd);
  while (true) {
    if (socket.get(zmq::sockopt::events) & ZMQ_POLLIN) return true;
    const std::int64_t left = deadline_ns - rt::now_ns();
    if (left <= 0 || stop_requested()) return false;
    pollfd p{fd, POLLIN, 0};
    const timespec ts{static_cast<time_t>(left / 1'000'000'000), static_cast<long>(left % 1'000'000'000)};
    ppoll(&p, 1, &ts, nullptr);
  }
}

bool await_subscribers(bus::BytePublisher& out, const char* topic, int count, std::int64_t deadline_ns) {
  while (out.subscriber_count(topic) < count && rt::now_ns() < deadline_ns && !stop_requested()) rt::sleep_until_ns(rt::now_ns() + 2'000'000);
  return out.subscriber_count(topic) >= count;
}

void wait_for_subscribers(bus::BytePublisher& out, const char* topic, int count, const std::string& node, const std::string& who, bool before_ready) {
  if (count <= 0) return;
  // a short grace for subscribers already on their way, then the wait is announced
  if (await_subscribers(out, topic, count, rt::now_ns() + 200'000'000)) return;
  if (before_ready) tell_launcher("wait " + std::to_string(kObserversWait_s));
  const char* attach = std::getenv(env::kAttach);
  say(node, "waiting up to " + std::to_string(static_cast<int>(kObserversWait_s)) + " s for " + std::to_string(count) + " " + who + " of " + topic +
                (attach ? " (they attach at " + std::string(attach) + ")" : ""));
  const bool came = await_subscribers(out, topic, count, rt::now_ns() + static_cast<std::int64_t>(kObserversWait_s * 1e9));
  const int n = out.subscriber_count(topic);
  if (!came) say(node, std::to_string(n) + " of " + std::to_string(count) + " " + who + " listening to " + topic + " after " + std::to_string(static_cast<int>(kObserversWait_s)) + " s; running anyway");
  else say(node, std::to_string(n) + " " + who + " listening to " + topic + "; starting");
}

bool wait_for_loop_peer(bus::LoopLink& link, const std::string& node, const std::string& peer) {
  if (link.wait_for_peer(rt::now_ns() + 200'000'000)) return true;
  tell_launcher("wait " + std::to_string(kObserversWait_s));
  say(node, "waiting up to " + std::to_string(static_cast<int>(kObserversWait_s)) + " s for " + peer + " on the loop link " + link.path());
  const std::int64_t give_up = rt::now_ns() + static_cast<std::int64_t>(kObserversWait_s * 1e9);
  while (!stop_requested() && rt::now_ns() < give_up && !link.wait_for_peer(std::min(give_up, rt::now_ns() + 100'000'000))) {
  }
  if (!link.connected()) say(node, peer + " did not connect to the loop link in " + std::to_string(static_cast<int>(kObserversWait_s)) + " s; running anyway");
  return link.connected();
}

void add_counters(msgs::NodeStatus& status, const bus::BytePublisher& out, const std::vector<std::pair<std::string, bus::TopicCounters>>& received) {
  status.clear_topics();
  for (const auto& [topic, c] : out.all_counters()) {
    auto* t = status.add_topics();
    t->set_topic(topic);
    t->set_sent(c.sent);
    t->set_dropped(c.dropped);
  }
  for (const auto& [topic, c] : received) {
    auto* t = status.add_topics();
    t->set_topic(topic);
    t->set_received(c.received);
    t->set_dropped(c.dropped + c.lost);
    t->set_malformed(c.malformed);
  }
}

}  // namespace enact::graph
