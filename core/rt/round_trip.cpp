#include "core/rt/round_trip.h"

namespace enact::rt {

void RoundTrip::sent(std::uint64_t seq, std::int64_t sent_ns) {
  close();
  open_ = true;
  seq_ = seq;
  sent_ns_ = sent_ns;
  ++requests_;
}

bool RoundTrip::reply(std::uint64_t seq, std::int64_t now_ns) {
  if (!open_ || seq != seq_) {
    ++stale_;
    return false;
  }
  open_ = false;
  last_rtt_ns_ = now_ns - sent_ns_;
  rtt_.record(last_rtt_ns_);
  return true;
}

void RoundTrip::close() {
  if (open_) ++unanswered_;
  open_ = false;
}

}  // namespace enact::rt
