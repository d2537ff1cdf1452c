#pragma once
// Which nodes of a graph hang: every node publishes node/status once a second, and one that
// stays silent for longer than silence_s while others still report has stopped (a deadlock,
// SIGSTOP, a livelock outside its loop). When no node reports at all, or the watcher itself
// was held up, nobody is accused.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/bus/bytes.h"
#include "core/bus/client.h"
#include "core/bus/typed.h"
#include "msgs/node_status.pb.h"

namespace enact::graph {

class StatusWatch {
 public:
  // subscribes to node/status at a graph's attach endpoint, with `keys` (bus::attach_connect)
  explicit StatusWatch(const std::string& attach_endpoint, const bus::ClientKeys& keys = {}, double silence_s = 3.0);

  // reads what arrived (never waits) and returns the nodes silent for longer than silence_s
  // at now_ns while another node reported within the last silence_s / 2; each silence is
  // returned once (the node is watched again from its next report). Call it often (the
  // launcher: every 50 ms): after a pause longer than silence_s / 4 (this process was held
  // up) every silence starts over.
  std::vector<std::string> hung(std::int64_t now_ns);

 private:
  bus::ByteSubscriber bytes_;
  bus::Subscriber<msgs::NodeStatus> statuses_;
  msgs::NodeStatus status_;
  std::int64_t silence_ns_;
  std::map<std::string, std::int64_t> last_ns_;  // when each node last reported (our clock)
  std::int64_t latest_ns_ = 0;                    // when any node last reported
  std::int64_t last_call_ns_ = 0;                 // the previous hung()
};

}  // namespace enact::graph
