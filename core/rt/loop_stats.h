#pragma once
// Statistics of a real-time loop, kept by the loop (fixed memory, allocation-free updates),
// and their summary for NodeStatus and for people.
#include <cstdint>
#include <string>

#include "core/rt/histogram.h"

namespace enact::rt {

struct LoopStats {
  LatencyHistogram jitter;   // wake-up lateness: woke - deadline (ns)
  LatencyHistogram latency;  // tick latency: wake-up to the end of the tick's work, e.g. force written (ns)
  std::uint64_t overruns = 0;  // deadlines missed (late wake-ups and skipped deadlines)
  std::uint64_t ticks = 0;     // wake-ups
};

struct LoopSummary {
  double rate_hz = 0.0;
  std::int64_t jitter_p50_ns = 0, jitter_p99_ns = 0, jitter_p999_ns = 0, jitter_max_ns = 0;
  std::int64_t latency_p50_ns = 0, latency_p99_ns = 0, latency_p999_ns = 0, latency_max_ns = 0;
  std::uint64_t overruns = 0, ticks = 0;
};

// the percentiles of the stats (to the histogram's 1/128 relative error), at the given loop rate
LoopSummary summarize(const LoopStats& stats, double rate_hz);

// one paragraph for people, times in us with 2 decimals, e.g. "5000 Hz loop: 10000 ticks,
// 0 overruns. Wake-up jitter p50 1.20 us, p99 ... Tick latency p50 ..."
std::string format(const LoopSummary& summary);

}  // namespace enact::rt
