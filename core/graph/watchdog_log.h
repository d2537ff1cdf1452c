#pragma once
// Watchdog episodes of a node, said once each: a line when one begins and a line when it
// ends, with its duration; counted for the node's summary and its node/status.
#include <cstdint>
#include <string>

#include "msgs/node_status.pb.h"

namespace enact::graph {

class WatchdogLog {
 public:
  // `node` prefixes the lines; `what` says what the watchdog did, e.g. "pins lowered"
  WatchdogLog(std::string node, std::string what);

  // whether the watchdog is tripped at now_ns: a change begins or ends an episode (and says so)
  void update(bool tripped, std::int64_t now_ns);

  std::uint64_t episodes() const { return episodes_; }
  // the longest episode so far, ended or still going at the last update, s
  double longest_s() const;
  bool tripped() const { return tripped_; }

  // "N watchdog episodes (longest X s; WHAT)" or "no watchdog episode"
  std::string summary() const;

  // episodes and the longest one into a node status
  void fill(msgs::NodeStatus& status) const;

 private:
  std::string node_, what_;
  bool tripped_ = false;
  std::int64_t since_ns_ = 0, last_ns_ = 0, longest_ns_ = 0;
  std::uint64_t episodes_ = 0;
};

// the verdict on a loop's run, one line for people: the deadlines missed, the longest force
// cut (watchdog episode), and whether this machine held the rate: at most 0.1 % of the
// deadlines missed and the force never cut. Into `status` too (deadlines, verdict).
std::string rate_verdict(double rate_hz, std::uint64_t deadlines, std::uint64_t missed, const WatchdogLog& cuts);
void fill_verdict(msgs::NodeStatus& status, double rate_hz, std::uint64_t deadlines, std::uint64_t missed, const WatchdogLog& cuts);
// the verdict on a run in simulated time: `ticks` at rate_hz took `wall_ns` of the wall clock
std::string simulated_verdict(double rate_hz, std::uint64_t ticks, std::int64_t wall_ns);

}  // namespace enact::graph
