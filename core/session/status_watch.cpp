#include "core/session/status_watch.h"

#include <cmath>

#include "core/graph/topics.h"

namespace enact::graph {

StatusWatch::StatusWatch(const std::string& attach_endpoint, const bus::ClientKeys& keys, double silence_s)
    : statuses_(bytes_, kNodeStatus), silence_ns_(std::llround(silence_s * 1e9)) {
  bus::attach_connect(bytes_.socket(), attach_endpoint, keys);
}

std::vector<std::string> StatusWatch::hung(std::int64_t now_ns) {
  // not asked for a while: this process was held up (SIGSTOP, swapped out), and what it
  // missed meanwhile says nothing about the nodes. Every silence starts over
  if (now_ns - last_call_ns_ > silence_ns_ / 4) {
    for (auto& [node, last_ns] : last_ns_) last_ns = now_ns;
  }
  last_call_ns_ = now_ns;
  while (statuses_.receive(status_, 0)) {
    last_ns_[status_.node()] = now_ns;
    latest_ns_ = now_ns;
  }
  std::vector<std::string> out;
  if (now_ns - latest_ns_ > silence_ns_ / 2) return out;  // nobody reports: not theirs to answer for
  for (auto it = last_ns_.begin(); it != last_ns_.end();) {
    if (now_ns - it->second <= silence_ns_) {
      ++it;
      continue;
    }
    out.push_back(it->first);
    it = last_ns_.erase(it);
  }
  return out;
}

}  // namespace enact::graph
