#pragma once
// A latency histogram with fixed memory: log-linear buckets (HdrHistogram's layout), exact
// from 0 to 127 ns, then 64 equal buckets per power of two up to 2^34 ns (about 17 s).
// All memory is allocated by the constructor; record, percentile, merge and reset
// allocate nothing and never throw, so it can live in the real-time loop.
//
// Guaranteed error: percentile() returns a value within 1/128 (0.79 %) of the true sample
// of that rank (|returned - true| <= true / 128), exact below 128 ns; p0 and p100 are the
// exact min and max. Values of 2^34 ns or more are counted in the top bucket (max() stays
// exact).
#include <cstdint>
#include <vector>

namespace enact::rt {

class LatencyHistogram {
 public:
  // the largest value a bucket resolves; larger values share the top bucket
  static constexpr std::int64_t kMaxTrackedNs = (std::int64_t{1} << 34) - 1;

  // an empty histogram (allocates its buckets, about 15 kB)
  LatencyHistogram();

  // count one sample; a negative value is recorded as 0 and counted in early()
  void record(std::int64_t ns);
  // the sample of rank ceil(p / 100 * count()) (at least 1), to the error stated above;
  // p is clamped to [0, 100]; 0 when empty
  std::int64_t percentile(double p) const;
  // the smallest and largest sample, exact (negative samples count as 0); 0 when empty
  std::int64_t min() const { return count_ ? min_ns_ : 0; }
  std::int64_t max() const { return count_ ? max_ns_ : 0; }
  // the number of samples, and how many of them were negative
  std::uint64_t count() const { return count_; }
  std::uint64_t early() const { return early_; }
  // the mean of the samples (negatives as 0); 0 when empty
  double mean_ns() const;
  // forget every sample
  void reset();
  // add every sample of `other`: the same as having recorded them here
  void merge(const LatencyHistogram& other);

 private:
  std::vector<std::uint64_t> counts_;
  std::uint64_t count_ = 0;
  std::uint64_t early_ = 0;
  std::int64_t min_ns_ = 0;
  std::int64_t max_ns_ = 0;
  double sum_ns_ = 0.0;
};

}  // namespace enact::rt
