#include "core/rt/histogram.h"

#include <algorithm>
#include <bit>
#include <cmath>

namespace enact::rt {
namespace {

// layout: values below kLinear get a bucket each; each later octave [2^k, 2^(k+1)) is cut
// into kSubBuckets equal buckets of width 2^(k - kSubBits)
constexpr int kSubBits = 6;
constexpr std::int64_t kSubBuckets = std::int64_t{1} << kSubBits;
constexpr std::int64_t kLinear = 2 * kSubBuckets;
constexpr int kFirstOctave = kSubBits + 1;
constexpr int kOctaves = 34 - kFirstOctave;
constexpr std::size_t kBuckets = static_cast<std::size_t>(kLinear + kOctaves * kSubBuckets);

std::size_t bucket_of(std::int64_t ns) {
  if (ns < kLinear) return static_cast<std::size_t>(ns);
  const auto octave = static_cast<int>(std::bit_width(static_cast<std::uint64_t>(ns))) - 1;
  const std::int64_t sub = (ns >> (octave - kSubBits)) - kSubBuckets;
  return static_cast<std::size_t>(kLinear + (octave - kFirstOctave) * kSubBuckets + sub);
}

// the middle of a bucket: at most half a bucket width, 1/128 of its lower bound, from any
// value in it
std::int64_t representative(std::size_t bucket) {
  const auto b = static_cast<std::int64_t>(bucket);
  if (b < kLinear) return b;
  const auto octave = static_cast<int>((b - kLinear) / kSubBuckets) + kFirstOctave;
  const std::int64_t sub = (b - kLinear) % kSubBuckets;
  const int width_bits = octave - kSubBits;
  const std::int64_t lower = (kSubBuckets + sub) << width_bits;
  return lower + ((std::int64_t{1} << width_bits) - 1) / 2;
}

}  // namespace

LatencyHistogram::LatencyHistogram() : counts_(kBuckets, 0) {}

void LatencyHistogram::record(std::int64_t ns) {
  if (ns < 0) {
    ++early_;
    ns = 0;
  }
  min_ns_ = count_ ? std::min(min_ns_, ns) : ns;
  max_ns_ = count_ ? std::max(max_ns_, ns) : ns;
  ++counts_[bucket_of(std::min(ns, kMaxTrackedNs))];
  ++count_;
  sum_ns_ += static_cast<double>(ns);
}

std::int64_t LatencyHistogram::percentile(double p) const {
  if (count_ == 0) return 0;
  // the rank of the wanted sample, 1..count
  const double clamped = std::isnan(p) ? 0.0 : std::clamp(p, 0.0, 100.0);
  const auto wanted = static_cast<std::uint64_t>(std::ceil(clamped / 100.0 * static_cast<double>(count_)));
  const std::uint64_t rank = std::clamp<std::uint64_t>(wanted, 1, count_);
  if (rank == 1) return min_ns_;
  if (rank == count_) return max_ns_;
  // walk the buckets to the one holding that rank; min and max bound the answer
  std::uint64_t seen = 0;
  for (std::size_t b = 0; b < counts_.size(); ++b) {
    seen += counts_[b];
    if (seen >= rank) return std::clamp(representative(b), min_ns_, max_ns_);
  }
  return max_ns_;
}

double LatencyHistogram::mean_ns() const { return count_ ? sum_ns_ / static_cast<double>(count_) : 0.0; }

void LatencyHistogram::reset() {
  std::fill(counts_.begin(), counts_.end(), std::uint64_t{0});
  count_ = 0;
  early_ = 0;
  min_ns_ = 0;
  max_ns_ = 0;
  sum_ns_ = 0.0;
}

void LatencyHistogram::merge(const LatencyHistogram& other) {
  if (other.count_ == 0) return;
  for (std::size_t b = 0; b < counts_.size(); ++b) counts_[b] += other.counts_[b];
  min_ns_ = count_ ? std::min(min_ns_, other.min_ns_) : other.min_ns_;
  max_ns_ = count_ ? std::max(max_ns_, other.max_ns_) : other.max_ns_;
  count_ += other.count_;
  early_ += other.early_;
  sum_ns_ += other.sum_ns_;
}

}  // namespace enact::rt
