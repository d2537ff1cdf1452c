// enact play FILE: republish a recording on the bus with its recorded timing.
#include <unistd.h>

#include <filesystem>
#include <cstdlib>
#include <cstdio>
#include <iostream>
#include <map>
#include <memory>

#include "core/bus/bytes.h"
#include "core/graph/session.h"
#include "core/graph/node.h"
#include "core/graph/params.h"
#include "core/record/reader.h"
#include "core/rt/clock.h"
#include "nodes/enact/commands.h"

namespace enact::cli {
namespace {

constexpr const char* kHelp = R"(usage: enact play FILE [--rate R] [--loop] [--topics T...] [--start-offset S]
                  [--remap FROM:=TO]... [--paused] [--name NODE] [--wait S]

Republish a recording's messages with their recorded timing, so any node consumes them as
if live (README, "Recording and replay"). Each message goes out, byte for byte, from the
endpoint of the node that published it (ipc://$ENACT_GRAPH_DIR/<node>.pub), or from NODE's
with --name (as `enact launch` passes to a node). Run alone, it is a graph of its own named
play:FILE (a session: its own folder, an attach point, a registry entry), which observers
find like any other (enact topic, a viewer, a logger, --graph play:FILE). Progress on the
terminal.

options:
  --rate R          speed factor (default 1); 0 = as fast as the subscribers take them
                    (flow control: nothing is dropped)
  --loop            start again at the end
  --topics T...     only these topics
  --start-offset S  skip the first S seconds
  --remap FROM:=TO  publish topic FROM as TO (repeatable)
  --paused          wait for Enter before playing
  --name NODE       publish everything as node NODE
  --wait S          wait up to S s for a subscriber of every topic before playing (default 5)
  --check           check the options and the recording, play nothing
)";

}  // namespace

int play(int argc, char** argv) {
  // list and repeatable options first
  const std::vector<std::string> topics = take_list(argc, argv, "--topics");
  std::map<std::string, std::string> remap;
  std::vector<char*> rest;
  for (int i = 0; i < argc; ++i) {
    const std::string s = argv[i];
    if (s == "--remap") {
      const std::string r = i + 1 < argc ? argv[++i] : "";
      const std::size_t at = r.find(":=");
      if (at == std::string::npos || at == 0 || at + 2 == r.size()) throw UsageError("--remap needs FROM:=TO, got '" + r + "'");
      remap[r.substr(0, at)] = r.substr(at + 2);
    } else {
      rest.push_back(argv[i]);
    }
  }
  const Args a = parse(static_cast<int>(rest.size()), rest.data(), 2, {"rate", "start-offset", "name", "wait"}, {"loop", "paused", "check"});
  if (a.flag("help")) {
    std::fputs(kHelp, stdout);
    return 0;
  }
  if (a.positional.size() != 1) throw UsageError("give exactly one recording");
  const double rate = a.number("rate", 1.0), offset_s = a.number("start-offset", 0.0), wait_s = a.number("wait", 5.0);
  if (rate < 0.0 || offset_s < 0.0 || wait_s < 0.0) throw UsageError("--rate, --start-offset and --wait must be >= 0");
  const std::string as_node = a.get("name", "");
  record::Reader r(a.positional[0]);
  if (a.flag("check")) return 0;  // options and recording are good (enact launch checks its nodes)
  auto wanted = [&](std::string_view topic) {
    if (topics.empty()) return true;
    for (const auto& t : topics) {
      if (t == topic) return true;
    }
    return false;
  };
  auto out_topic = [&](const std::string& topic) {
    const auto it = remap.find(topic);
    return it == remap.end() ? topic : it->second;
  };

  // one publisher per recorded node (or one for all, as --name)
  graph::install_stop_handlers();
  std::map<std::string, std::unique_ptr<bus::BytePublisher>> pubs;
  std::unique_ptr<graph::GraphSession> session;
  const bool standalone = std::getenv("ENACT_GRAPH_DIR") == nullptr;
  if (standalone) {
    graph::SessionOptions so;
    so.supervised = false;
    so.numbered = true;
    session = std::make_unique<graph::GraphSession>("play:" + std::filesystem::path(a.positional[0]).filename().string(), a.positional[0], so);
  }
  auto publisher = [&](const record::Channel& c) -> bus::BytePublisher& {
    const auto p = c.metadata.find("publisher");
    const std::string node = !as_node.empty() ? as_node : p != c.metadata.end() && !p->second.empty() ? p->second : "play";
    auto& slot = pubs[node];
    if (!slot) {
      slot = std::make_unique<bus::BytePublisher>(session ? session->node_endpoint(node) : graph::node_endpoint(node), bus::PublisherOptions{.node = node, .send_hwm = 1000});
      if (session) session->attach().add_publisher(node, slot->endpoint());
    }
    const auto s = r.schemas().find(c.schema_id);
    if (s != r.schemas().end()) {
      slot->declare(out_topic(c.topic), s->second.name);
      if (session) session->attach().declare_topic(out_topic(c.topic), s->second.name, node);
    }
    return *slot;
  };
  std::map<std::uint16_t, bus::BytePublisher*> by_channel;
  for (const auto& [id, c] : r.channels()) {
    if (wanted(c.topic)) by_channel[id] = &publisher(c);
  }
  if (by_channel.empty() && !r.channels().empty()) throw UsageError("none of the topics given is in " + r.path());
  for (const auto& [node, pub] : pubs) graph::announce_topics(*pub);
  graph::report_ready();
  if (session) std::cerr << "enact play: graph " << session->name() << ": observers attach at " << session->endpoint() << "\n";
  // the subscribers connect: ZeroMQ drops what is sent before they do
  const std::int64_t give_up = rt::now_ns() + static_cast<std::int64_t>(wait_s * 1e9);
  auto all_heard = [&] {
    for (const auto& [id, pub] : by_channel) {
      if (!pub->has_subscribers(out_topic(r.channels().at(id).topic))) return false;
    }
    return true;
  };
  while (!all_heard() && rt::now_ns() < give_up && !graph::stop_requested()) rt::sleep_until_ns(rt::now_ns() + 5'000'000);
  if (a.flag("paused")) {
    std::cerr << "enact play: paused; press Enter to play " << r.path() << "\n";
    std::string line;
    std::getline(std::cin, line);
  }

  const bool tty = isatty(2);
  std::uint64_t sent = 0;
  do {
    std::int64_t t0 = -1, wall0 = 0, next_progress = 0;
    std::int64_t last_log = 0;
    r.for_each([&](const record::Message& m) {
      if (graph::stop_requested()) return false;
      if (t0 < 0) {
        t0 = m.log_time_ns + static_cast<std::int64_t>(offset_s * 1e9);
        wall0 = rt::now_ns();
      }
      if (m.log_time_ns < t0 || !wanted(m.topic)) return true;
      auto c = by_channel.find(m.channel->id);
      if (c == by_channel.end()) c = by_channel.emplace(m.channel->id, &publisher(*m.channel)).first;
      // recorded timing, scaled; rate 0: no pause
      if (rate > 0.0) rt::sleep_until_ns(wall0 + static_cast<std::int64_t>(static_cast<double>(m.log_time_ns - t0) / rate));
      const std::string topic = out_topic(std::string(m.topic));
      // flow control: a full subscriber queue waits, nothing is dropped
      while (!c->second->send(topic, m.schema_name, m.data.data(), m.data.size()) && !graph::stop_requested()) rt::sleep_until_ns(rt::now_ns() + 50'000);
      ++sent;
      last_log = m.log_time_ns;
      const std::int64_t now = rt::now_ns();
      if (now >= next_progress) {
        next_progress = now + (tty ? 250'000'000 : 5'000'000'000);
        std::fprintf(stderr, tty ? "\renact play: %8.2f s  %10llu messages   " : "enact play: %.2f s, %llu messages\n",
                     static_cast<double>(last_log - t0) * 1e-9, static_cast<unsigned long long>(sent));
      }
      return true;
    });
  } while (a.flag("loop") && !graph::stop_requested());
  if (tty) std::fputs("\n", stderr);
  std::fprintf(stderr, "enact play: %llu messages republished from %s\n", static_cast<unsigned long long>(sent), r.path().c_str());
  for (const auto& d : r.damage()) std::fprintf(stderr, "enact play: %s: %s\n", r.path().c_str(), d.c_str());
  // let the last messages leave before the sockets close
  rt::sleep_until_ns(rt::now_ns() + 200'000'000);
  return 0;
}

}  // namespace enact::cli
