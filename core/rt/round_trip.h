#pragma once
// One arm of a round-trip measurement: each tick sends a numbered request and takes as its
// answer only the reply that carries that number. A reply to an earlier request (it came
// after its tick gave up) is stale: counted, never taken for the answer of a later tick, so
// one late reply cannot turn every later round trip into a send + receive.
#include <cstdint>

#include "core/rt/histogram.h"

namespace enact::rt {

class RoundTrip {
 public:
  // request `seq` left at sent_ns (a request still open is closed first, unanswered)
  void sent(std::uint64_t seq, std::int64_t sent_ns);
  // a reply numbered `seq` came at now_ns: true when it answers the open request (its round
  // trip is recorded and the request closed); false for any other reply (counted stale)
  bool reply(std::uint64_t seq, std::int64_t now_ns);
  // the tick gives up: an open request counts as unanswered
  void close();

  // round trips of the answered requests, ns
  const LatencyHistogram& rtt() const { return rtt_; }
  std::uint64_t requests() const { return requests_; }
  std::uint64_t answered() const { return rtt_.count(); }
  std::uint64_t stale() const { return stale_; }
  std::uint64_t unanswered() const { return unanswered_; }
  // the round trip of the last answered request, ns
  std::int64_t last_rtt_ns() const { return last_rtt_ns_; }

 private:
  LatencyHistogram rtt_;
  bool open_ = false;
  std::uint64_t seq_ = 0;
  std::int64_t sent_ns_ = 0;
  std::int64_t last_rtt_ns_ = 0;
  std::uint64_t requests_ = 0, stale_ = 0, unanswered_ = 0;
};

}  // namespace enact::rt
