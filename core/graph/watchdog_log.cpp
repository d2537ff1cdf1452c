#include "core/graph/watchdog_log.h"

#include <algorithm>
#include <cstdio>
#include <utility>

#include "core/graph/process.h"

namespace enact::graph {
namespace {

std::string seconds(double s) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3f s", s);
  return text;
}

}  // namespace

WatchdogLog::WatchdogLog(std::string node, std::string what) : node_(std::move(node)), what_(std::move(what)) {}

void WatchdogLog::update(bool tripped, std::int64_t now_ns) {
  last_ns_ = now_ns;
  if (tripped == tripped_) return;
  tripped_ = tripped;
  if (tripped) {
    since_ns_ = now_ns;
    ++episodes_;
    say(node_, "watchdog: episode " + std::to_string(episodes_) + " began, " + what_);
    return;
  }
  longest_ns_ = std::max(longest_ns_, now_ns - since_ns_);
  say(node_, "watchdog: episode " + std::to_string(episodes_) + " ended after " + seconds(static_cast<double>(now_ns - since_ns_) * 1e-9));
}

double WatchdogLog::longest_s() const {
  const std::int64_t going_ns = tripped_ ? last_ns_ - since_ns_ : 0;
  return static_cast<double>(std::max(longest_ns_, going_ns)) * 1e-9;
}

std::string WatchdogLog::summary() const {
  if (episodes_ == 0) return "no watchdog episode";
  return std::to_string(episodes_) + " watchdog episode" + (episodes_ == 1 ? "" : "s") + " (longest " + seconds(longest_s()) + "; " + what_ +
         ")";
}

std::string rate_verdict(double rate_hz, std::uint64_t deadlines, std::uint64_t missed, const WatchdogLog& cuts) {
  const double fraction = static_cast<double>(missed) / static_cast<double>(std::max<std::uint64_t>(deadlines, 1));
  const bool held = fraction <= 0.001 && cuts.episodes() == 0;
  char line[256];
  std::snprintf(line, sizeof line, "%s %.0f Hz: %llu of %llu deadlines missed (%.3f %%), %s", held ? "this machine held" : "this machine did NOT hold",
                rate_hz, static_cast<unsigned long long>(missed), static_cast<unsigned long long>(deadlines), 100.0 * fraction,
                cuts.episodes() == 0 ? "the force never cut" : ("the force cut " + std::to_string(cuts.episodes()) + " times, the longest " +
                                                                 seconds(cuts.longest_s())).c_str());
  std::string out = line;
  if (!held) out += " (enact doctor says what this machine holds and what to change)";
  return out;
}

void fill_verdict(msgs::NodeStatus& status, double rate_hz, std::uint64_t deadlines, std::uint64_t missed, const WatchdogLog& cuts) {
  status.set_deadlines(deadlines);
  status.set_deadlines_missed(missed);
  status.set_verdict(rate_verdict(rate_hz, deadlines, missed, cuts));
}

void WatchdogLog::fill(msgs::NodeStatus& status) const {
  status.set_watchdog_episodes(episodes_);
  status.set_watchdog_longest_s(longest_s());
}

std::string simulated_verdict(double rate_hz, std::uint64_t ticks, std::int64_t wall_ns) {
  const double model_s = static_cast<double>(ticks) / rate_hz, wall_s = static_cast<double>(wall_ns) * 1e-9;
  char line[160];
  std::snprintf(line, sizeof line, "simulated time: %.3f s of the model in %.3f s, %.1f times real time, no deadline to miss", model_s, wall_s,
                wall_s > 0.0 ? model_s / wall_s : 0.0);
  return line;
}

}  // namespace enact::graph
