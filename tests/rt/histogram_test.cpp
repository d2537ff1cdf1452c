// The latency histogram: percentiles within the stated relative error (1/128) of the exact
// sample of the same rank, exact min and max, merge, early samples, no allocation.
#include "core/rt/histogram.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "tests/support/alloc_guard.h"

namespace enact::rt {
namespace {

const std::vector<double> kPercentiles = {0.0, 0.1, 1.0, 10.0, 25.0, 50.0, 75.0, 90.0, 99.0, 99.9, 99.99, 100.0};

// the exact sample of rank ceil(p / 100 * n) (at least 1)
std::int64_t exact_percentile(std::vector<std::int64_t> sorted, double p) {
  std::sort(sorted.begin(), sorted.end());
  const auto n = sorted.size();
  const auto rank = std::clamp<std::size_t>(static_cast<std::size_t>(std::ceil(p / 100.0 * static_cast<double>(n))), 1, n);
  return sorted[rank - 1];
}

LatencyHistogram histogram_of(const std::vector<std::int64_t>& values) {
  LatencyHistogram h;
  for (const std::int64_t v : values) h.record(v);
  return h;
}

void expect_within_stated_error(const std::vector<std::int64_t>& values) {
  const LatencyHistogram h = histogram_of(values);
  for (const double p : kPercentiles) {
    const std::int64_t exact = exact_percentile(values, p);
    const std::int64_t got = h.percentile(p);
    EXPECT_LE(std::abs(got - exact), exact / 128) << "p" << p << ": exact " << exact << ", got " << got;
  }
  EXPECT_EQ(h.percentile(0.0), h.min());
  EXPECT_EQ(h.percentile(100.0), h.max());
  EXPECT_EQ(h.min(), *std::min_element(values.begin(), values.end()));
  EXPECT_EQ(h.max(), *std::max_element(values.begin(), values.end()));
  EXPECT_EQ(h.count(), values.size());
}

TEST(LatencyHistogram, UniformOneToAMillion) {
  std::vector<std::int64_t> values(1'000'000);
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = static_cast<std::int64_t>(i) + 1;
  expect_within_stated_error(values);
  EXPECT_DOUBLE_EQ(histogram_of(values).mean_ns(), 500'000.5);
}

TEST(LatencyHistogram, Bimodal) {
  // most ticks wake ~2 us late, a few ~300 us (a preempted loop), shuffled
  std::mt19937_64 rng(7);
  std::normal_distribution<double> fast(2'000.0, 150.0), slow(300'000.0, 20'000.0);
  std::vector<std::int64_t> values;
  for (int i = 0; i < 100'000; ++i) values.push_back(std::max<std::int64_t>(0, std::llround(i % 50 ? fast(rng) : slow(rng))));
  std::shuffle(values.begin(), values.end(), rng);
  expect_within_stated_error(values);
}

TEST(LatencyHistogram, ConstantIsExactEverywhere) {
  const std::vector<std::int64_t> values(1000, 123'457);
  const LatencyHistogram h = histogram_of(values);
  for (const double p : kPercentiles) EXPECT_EQ(h.percentile(p), 123'457) << "p" << p;
  EXPECT_DOUBLE_EQ(h.mean_ns(), 123'457.0);
}

TEST(LatencyHistogram, SmallValuesAreExact) {
  std::vector<std::int64_t> values;
  for (std::int64_t v = 0; v < 128; ++v) values.push_back(v);
  const LatencyHistogram h = histogram_of(values);
  for (const double p : kPercentiles) EXPECT_EQ(h.percentile(p), exact_percentile(values, p)) << "p" << p;
}

TEST(LatencyHistogram, EmptyReportsZero) {
  const LatencyHistogram h;
  EXPECT_EQ(h.count(), 0u);
  EXPECT_EQ(h.percentile(50.0), 0);
  EXPECT_EQ(h.min(), 0);
  EXPECT_EQ(h.max(), 0);
  EXPECT_EQ(h.mean_ns(), 0.0);
}

TEST(LatencyHistogram, MergeEqualsRecordingBoth) {
  std::mt19937_64 rng(11);
  std::uniform_int_distribution<std::int64_t> a_dist(-50, 50'000), b_dist(1'000, 5'000'000);
  LatencyHistogram a, b, both;
  for (int i = 0; i < 20'000; ++i) {
    const std::int64_t va = a_dist(rng), vb = b_dist(rng);
    a.record(va);
    b.record(vb);
    both.record(va);
    both.record(vb);
  }
  a.merge(b);
  EXPECT_EQ(a.count(), both.count());
  EXPECT_EQ(a.early(), both.early());
  EXPECT_EQ(a.min(), both.min());
  EXPECT_EQ(a.max(), both.max());
  EXPECT_DOUBLE_EQ(a.mean_ns(), both.mean_ns());
  for (double p = 0.0; p <= 100.0; p += 0.5) EXPECT_EQ(a.percentile(p), both.percentile(p)) << "p" << p;
}

TEST(LatencyHistogram, NegativeValuesAreEarlyAndCountAsZero) {
  LatencyHistogram h;
  h.record(-5);
  h.record(-1);
  h.record(10);
  EXPECT_EQ(h.count(), 3u);
  EXPECT_EQ(h.early(), 2u);
  EXPECT_EQ(h.min(), 0);
  EXPECT_EQ(h.percentile(50.0), 0);
  EXPECT_EQ(h.max(), 10);
  h.reset();
  EXPECT_EQ(h.count(), 0u);
  EXPECT_EQ(h.early(), 0u);
}

TEST(LatencyHistogram, HugeValuesSaturateButMaxStaysExact) {
  LatencyHistogram h;
  h.record(1'000);
  h.record(LatencyHistogram::kMaxTrackedNs * 4);
  EXPECT_EQ(h.max(), LatencyHistogram::kMaxTrackedNs * 4);
  EXPECT_EQ(h.percentile(100.0), LatencyHistogram::kMaxTrackedNs * 4);
}

TEST(LatencyHistogram, RecordPercentileAndMergeAllocateNothing) {
  LatencyHistogram h, other;
  other.record(42);
  std::vector<int> v;
  std::size_t histogram_allocations = 0, vector_allocations = 0;
  std::int64_t sink = 0;
  {
    enact::test::AllocGuard guard;
    for (std::int64_t i = -10; i < 100'000; ++i) h.record(i * 37);
    sink += h.percentile(99.9);
    h.merge(other);
    h.reset();
    histogram_allocations = guard.allocations();
    v.push_back(1);
    vector_allocations = guard.allocations() - histogram_allocations;
  }
  EXPECT_EQ(histogram_allocations, 0u);
  EXPECT_GT(vector_allocations, 0u);
  EXPECT_GT(sink, 0);
}

}  // namespace
}  // namespace enact::rt
