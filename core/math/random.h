#pragma once
// A small, seeded, platform-independent random generator for simulations that must be
// reproducible: the same seed gives the same numbers with any compiler or standard library
// (std::normal_distribution and std::shuffle do not promise that). SplitMix64 (Steele, Lea
// and Flood, "Fast splittable pseudorandom number generators", OOPSLA 2014): a 64-bit
// state advanced by the golden-ratio increment 0x9e3779b97f4a7c15 and mixed by two
// xor-shift-multiply rounds. Header only; allocates nothing.
#include <cmath>
#include <cstdint>

namespace enact::math {

class Random {
 public:
  explicit Random(std::uint64_t seed = 0) : state_(seed) {}

  // the next 64 random bits
  std::uint64_t next() noexcept {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }

  // uniform in [0, 1), 53 random bits
  double uniform() noexcept { return static_cast<double>(next() >> 11) * 0x1.0p-53; }

  // uniform integer in [0, n), n > 0 (the modulo bias is below 2^-40 for n < 2^24)
  std::uint64_t below(std::uint64_t n) noexcept { return next() % n; }

  // standard normal (mean 0, sd 1), by the Box-Muller transform; the second value of each
  // pair is kept for the next call
  double normal() noexcept {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    const double u1 = 1.0 - uniform();  // (0, 1]: log is finite
    const double u2 = uniform();
    const double r = std::sqrt(-2.0 * std::log(u1));
    const double angle = 2.0 * 3.14159265358979323846 * u2;
    spare_ = r * std::sin(angle);
    has_spare_ = true;
    return r * std::cos(angle);
  }

 private:
  std::uint64_t state_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

// a seed for stream `index` of a parent seed (a different, well-mixed seed per index)
inline std::uint64_t derive_seed(std::uint64_t seed, std::uint64_t index) noexcept {
  Random r(seed ^ (0xd1b54a32d192ed03ULL * (index + 1)));
  return r.next();
}

}  // namespace enact::math
