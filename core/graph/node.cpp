#include "core/graph/node.h"

#include <poll.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "core/bus/context.h"
#include "core/bus/endpoints.h"
#include "core/config/yaml.h"
#include "core/graph/launcher_pipe.h"
#include "core/graph/topics.h"
#include "core/config/env.h"
#include "core/rt/clock.h"
#include "core/rt/profile.h"

namespace enact::graph {
namespace {

std::atomic<bool> g_stop{false};
bool g_loop_cpu_own = false;
void on_stop(int) {
  // the first request arms the grace period: SIGALRM's default action ends the process
  if (!g_stop.exchange(true)) alarm(kStopGrace_s);
}

}  // namespace

std::vector<std::string> nodes_not_announced(const msgs::GraphInfo& info) {
  std::vector<std::string> out;
  for (const std::string& node : info.param_nodes()) {
    const std::string board = kParamValues + node;
    if (std::none_of(info.topics().begin(), info.topics().end(), [&](const auto& t) { return t.name() == board; })) out.push_back(node);
  }
  return out;
}

std::string graph_dir() {
  const char* dir = std::getenv(env::kGraphDir);
  std::string out = dir && *dir ? dir : "/tmp/enact-" + std::to_string(getuid());
  std::error_code ec;
  std::filesystem::create_directories(out, ec);
  return out;
}

std::string node_endpoint(const std::string& name) { return bus::ipc_endpoint(graph_dir(), name); }

void install_stop_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_stop;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

bool stop_requested() { return g_stop.load(std::memory_order_relaxed); }

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

void add_counters(msgs::NodeStatus& status, const bus::BytePublisher& out, const bus::ByteSubscriber* in) {
  status.clear_topics();
  for (const auto& [topic, c] : out.all_counters()) {
    auto* t = status.add_topics();
    t->set_topic(topic);
    t->set_sent(c.sent);
    t->set_dropped(c.dropped);
  }
  if (!in) return;
  for (const auto& [topic, c] : in->all_counters()) {
    auto* t = status.add_topics();
    t->set_topic(topic);
    t->set_received(c.received);
    t->set_dropped(c.dropped + c.lost);
    t->set_malformed(c.malformed);
  }
}

void apply_rt_profile(const std::string& node) {
  const char* text = std::getenv(env::kRtProfile);
  if (!text) return;
  const rt::NodeProfile profile = rt::NodeProfile::from_env(text);
  const rt::NodeProfileReport report = rt::apply_node_profile(profile);
  g_loop_cpu_own = report.pinned && profile.sharing == 1;
  bus::set_io_threads({report.io_cpus, report.io_fifo_priority});
  say(node, report.summary());
}

bool loop_cpu_own() { return g_loop_cpu_own; }

rt::GraphClock graph_clock() {
  const char* text = std::getenv(env::kClock);
  if (!text) return rt::GraphClock::real;
  const auto clock = rt::parse_clock(text);
  if (!clock) throw config::Error(std::string(env::kClock) + "='" + text + "' names no clock\n  fix: real or simulated (the launcher sets it from the launch file's clock: entry or --clock)");
  return *clock;
}

void say(const std::string& node, const std::string& text) {
  std::fprintf(stderr, "%s: %s\n", node.c_str(), text.c_str());
  std::fflush(stderr);
}

}  // namespace enact::graph
