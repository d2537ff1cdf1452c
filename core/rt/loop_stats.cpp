#include "core/rt/loop_stats.h"

#include <cstdio>

namespace enact::rt {
namespace {

double us(std::int64_t ns) { return static_cast<double>(ns) / 1000.0; }

}  // namespace

LoopSummary summarize(const LoopStats& stats, double rate_hz) {
  LoopSummary s;
  s.rate_hz = rate_hz;
  s.jitter_p50_ns = stats.jitter.percentile(50.0);
  s.jitter_p99_ns = stats.jitter.percentile(99.0);
  s.jitter_p999_ns = stats.jitter.percentile(99.9);
  s.jitter_max_ns = stats.jitter.max();
  s.latency_p50_ns = stats.latency.percentile(50.0);
  s.latency_p99_ns = stats.latency.percentile(99.0);
  s.latency_p999_ns = stats.latency.percentile(99.9);
  s.latency_max_ns = stats.latency.max();
  s.overruns = stats.overruns;
  s.ticks = stats.ticks;
  return s;
}

std::string format(const LoopSummary& s) {
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "%.0f Hz loop: %llu ticks, %llu overruns. Wake-up jitter p50 %.2f us, p99 %.2f us, "
                "p99.9 %.2f us, max %.2f us. Tick latency p50 %.2f us, p99 %.2f us, p99.9 %.2f us, max %.2f us.",
                s.rate_hz, static_cast<unsigned long long>(s.ticks), static_cast<unsigned long long>(s.overruns),
                us(s.jitter_p50_ns), us(s.jitter_p99_ns), us(s.jitter_p999_ns), us(s.jitter_max_ns),
                us(s.latency_p50_ns), us(s.latency_p99_ns), us(s.latency_p999_ns), us(s.latency_max_ns));
  return buf;
}

}  // namespace enact::rt
