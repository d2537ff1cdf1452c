#include "core/graph/watchdog_log.h"

#include <algorithm>
#include <cstdio>
#include <utility>

#include "core/graph/node.h"

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

void WatchdogLog::fill(msgs::NodeStatus& status) const {
  status.set_watchdog_episodes(episodes_);
  status.set_watchdog_longest_s(longest_s());
}

}  // namespace enact::graph
