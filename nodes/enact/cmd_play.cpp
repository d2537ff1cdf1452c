// enact play FILE: republish a recording on the bus with its recorded timing.
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>

#include "core/bus/bytes.h"
#include "core/config/suggest.h"
#include "core/session/session.h"
#include "core/graph/launcher_pipe.h"
#include "core/graph/sockets.h"
#include "core/graph/stop.h"
#include "core/replay/player.h"
#include "core/config/env.h"
#include "core/config/format.h"
#include "core/record/reader.h"
#include "core/rt/clock.h"
#include "nodes/enact/commands.h"
#include "nodes/enact/play_clock.h"

namespace enact::cli {
namespace {

constexpr const char* kPlayHelp = R"(usage: enact play FILE [--rate R] [--loop] [--topics T...] [--start-offset S] [--delay S]
                  [--remap FROM:=TO]... [--paused] [--name NODE] [--wait S]

Republish a recording's messages with their recorded timing, so any node consumes them as
if live (docs/recording-and-replay.md). Each message goes out, byte for byte, from the
endpoint of the node that published it (ipc://$ENACT_GRAPH_DIR/<node>.pub), or from NODE's
with --name (as `enact launch` passes to a node). Run alone, it is a graph of its own named
play:FILE (a session: its own folder, an attach point, a registry entry), which observers
find like any other (enact topic, a viewer, a logger, --graph play:FILE).

On a terminal: Space pauses and resumes, s (while paused) publishes one message; the
progress line gives the recording's position and total ("12.3 / 40.0 s"). Not on a
terminal: a progress line every 5 s.

options:
  --rate R          speed factor (default 1); 0 = as fast as the subscribers take them
                    (flow control: nothing is dropped)
  --loop            start again at the end
  --topics T...     only these topics
  --start-offset S  skip the first S seconds
  --delay S         wait S s before the first message (after --wait; like ros2 bag play --delay)
  --remap FROM:=TO  publish topic FROM as TO (repeatable)
  --paused          start paused (on a terminal: Space plays; else Enter)
  --name NODE       publish everything as node NODE
  --wait S          wait up to S s for a subscriber of every topic before playing (default 5; said
                    when it waits, and whether they came)
  --check           check the options and the recording, play nothing
)";

// every topic of `topics` is in the recording (UsageError naming the closest and the rest)
void require_topics(const record::Reader& r, const std::vector<std::string>& topics) {
  std::vector<std::string> recorded;
  std::string list;
  for (const auto& [id, c] : r.channels()) {
    if (std::find(recorded.begin(), recorded.end(), c.topic) != recorded.end()) continue;
    recorded.push_back(c.topic);
    list += (list.empty() ? "" : ", ") + c.topic;
  }
  for (const std::string& t : topics) {
    if (std::find(recorded.begin(), recorded.end(), t) == recorded.end()) {
      throw UsageError("no topic '" + t + "' in " + r.path() + config::did_you_mean(t, recorded) + " (topics: " + list + ")");
    }
  }
}

// what `enact play` was asked to do: the player's options and the command's own
struct PlayCommand {
  std::string file;
  graph::PlayOptions play;
  double rate = 1.0, delay_s = 0.0;
  bool loop = false, paused = false, check = false, help = false;
};

PlayCommand parse_play(int argc, char** argv) {
  PlayCommand o;
  // list and repeatable options first
  o.play.topics = take_list(argc, argv, "--topics");
  for (std::string& t : o.play.topics) t = topic_name(t);
  for (const std::string& r : take_repeated(argc, argv, "--remap")) {
    const std::size_t at = r.find(":=");
    if (at == std::string::npos || at == 0 || at + 2 == r.size()) throw UsageError("--remap needs FROM:=TO, got '" + r + "'");
    o.play.remap[topic_name(r.substr(0, at))] = topic_name(r.substr(at + 2));
  }
  const Args a = parse(argc, argv, 2, {"rate", "start-offset", "name", "wait", "delay"}, {"loop", "paused", "check"});
  o.help = a.flag("help");
  if (o.help) return o;
  if (a.positional.size() != 1) throw UsageError("give exactly one recording");
  o.file = a.positional[0];
  o.rate = a.number("rate", 1.0), o.play.offset_s = a.number("start-offset", 0.0), o.play.wait_s = a.number("wait", 5.0), o.delay_s = a.number("delay", 0.0);
  if (o.rate < 0.0 || o.play.offset_s < 0.0 || o.play.wait_s < 0.0 || o.delay_s < 0.0) throw UsageError("--rate, --start-offset, --wait and --delay must be >= 0");
  o.play.as_node = a.get("name", "");
  o.loop = a.flag("loop"), o.paused = a.flag("paused"), o.check = a.flag("check");
  return o;
}

// the progress line: the recording's position and span ("12.3 / 40.0 s"), a few times a
// second on a terminal, every 5 s otherwise, and at once when paused or resumed
struct PlayProgress {
  const TerminalKeys& keys;
  std::int64_t first_ns;
  double total_s;
  bool tty = isatty(2);
  std::uint64_t sent = 0;
  std::int64_t last_log = first_ns, next_progress = 0;
  bool paused_shown = false;

  void show(const PlayClock& clock) {
    const std::int64_t now = rt::now_ns();
    if (now < next_progress && clock.paused() == paused_shown) return;
    next_progress = now + (tty ? 250'000'000 : 5'000'000'000);
    paused_shown = clock.paused();
    const char* state = clock.paused() ? (keys.active() ? "  paused (Space plays, s steps)" : "  paused") : (keys.active() ? "  (Space pauses)" : "");
    std::fprintf(stderr, tty ? "\renact play: %6.1f / %.1f s  %10llu messages%s\033[K" : "enact play: %.1f / %.1f s, %llu messages%s\n",
                 static_cast<double>(last_log - first_ns) * 1e-9, total_s, static_cast<unsigned long long>(sent), state);
  }
};

}  // namespace

int play(int argc, char** argv) {
  const PlayCommand o = parse_play(argc, argv);
  if (o.help) {
    std::fputs(kPlayHelp, stdout);
    return 0;
  }
  record::Reader r(o.file);
  require_topics(r, o.play.topics);
  if (o.check) return 0;  // options and recording are good (enact launch checks its nodes)

  graph::install_stop_handlers();
  std::unique_ptr<graph::GraphSession> session;
  const bool standalone = std::getenv(env::kGraphDir) == nullptr;
  if (standalone) {
    graph::SessionOptions so;
    so.supervised = false;
    so.numbered = true;
    session = std::make_unique<graph::GraphSession>("play:" + std::filesystem::path(o.file).filename().string(), o.file, so);
  }
  graph::Player player(r, o.play, session.get());
  graph::report_ready();
  if (session) std::cerr << "enact play: graph " << session->name() << ": observers attach at " << session->endpoint() << "\n";
  player.wait_for_subscribers([](const std::string& line) { std::cerr << "enact play: " << line << "\n"; });

  const auto [first_ns, last_ns] = r.time_span();
  TerminalKeys keys(standalone);
  PlayProgress progress{keys, first_ns, static_cast<double>(last_ns - first_ns) * 1e-9};
  PlayClock clock(o.rate, keys, [&] { progress.show(clock); });
  if (o.paused && keys.active()) {
    clock.set_paused(true);
  } else if (o.paused) {
    std::cerr << "enact play: paused; press Enter to play " << r.path() << "\n";
    std::string line;
    std::getline(std::cin, line);
  }
  // --delay: the subscribers settle before the first message (`ros2 bag play --delay`)
  const std::int64_t delay_end = rt::now_ns() + static_cast<std::int64_t>(o.delay_s * 1e9);
  while (rt::now_ns() < delay_end && !graph::stop_requested()) rt::sleep_until_ns(std::min(delay_end, rt::now_ns() + 50'000'000));
  const graph::PlayTiming timing{[&](std::int64_t t) { clock.restart(t); }, [&](std::int64_t t) { return clock.wait(t); }};
  do {
    player.play_once(timing, [&](std::int64_t log_ns) {
      ++progress.sent;
      progress.last_log = log_ns;
      progress.show(clock);
    });
  } while (o.loop && !graph::stop_requested());
  if (progress.tty) std::fputs("\n", stderr);
  std::fprintf(stderr, "enact play: %llu messages republished from %s\n", static_cast<unsigned long long>(progress.sent), r.path().c_str());
  for (const auto& d : r.damage()) std::fprintf(stderr, "enact play: %s: %s\n", r.path().c_str(), d.c_str());
  // let the last messages leave before the sockets close
  rt::sleep_until_ns(rt::now_ns() + 200'000'000);
  return 0;
}

}  // namespace enact::cli
