// Loop statistics: the summary takes its percentiles from the histograms and the text
// gives them in microseconds with two decimals.
#include "core/rt/loop_stats.h"

#include <gtest/gtest.h>

#include <string>

namespace enact::rt {
namespace {

TEST(LoopStats, SummaryAndText) {
  LoopStats stats;
  for (int i = 0; i < 1000; ++i) stats.jitter.record(i == 999 ? 40'100 : 100);  // exact below 128 ns
  for (int i = 0; i < 1000; ++i) stats.latency.record(12'345);
  stats.ticks = 1000;
  stats.overruns = 2;
  const LoopSummary s = summarize(stats, 5000.0);
  EXPECT_EQ(s.jitter_p50_ns, 100);
  EXPECT_EQ(s.jitter_p99_ns, 100);
  EXPECT_EQ(s.jitter_max_ns, 40'100);
  EXPECT_EQ(s.latency_p999_ns, 12'345);  // bounded by the exact max
  EXPECT_EQ(s.ticks, 1000u);
  EXPECT_EQ(s.overruns, 2u);
  const std::string text = format(s);
  EXPECT_NE(text.find("5000 Hz"), std::string::npos) << text;
  EXPECT_NE(text.find("1000 ticks, 2 overruns"), std::string::npos) << text;
  EXPECT_NE(text.find("p50 0.10 us"), std::string::npos) << text;
  EXPECT_NE(text.find("max 40.10 us"), std::string::npos) << text;
  EXPECT_NE(text.find("max 12.35 us"), std::string::npos) << text;
}

}  // namespace
}  // namespace enact::rt
