#pragma once
// A virtual observer for discrimination tasks: it answers a two-interval trial ("which
// interval had the larger value?") correctly with the probability its psychometric function
// gives at the trial's difference, so a whole procedure, fit and analysis can be run and
// checked before anyone is recruited. Its function's threshold (the JND) is the ground
// truth of the tests. Each answer draws from a stream derived from the observer's seed and
// the trial's index, so a resumed run answers exactly as an uninterrupted one.
#include <cstdint>

#include "core/psychophysics/psychometric.h"

namespace enact::psychophysics {

struct VirtualObserver {
  PsychometricFunction function;
  std::uint64_t seed = 1;

  // the answer to trial `trial_index` (from 0) at difference `difference` (x's unit):
  // true when correct
  bool correct(std::uint64_t trial_index, double difference) const;
  // the interval it names (1 or 2), given the interval that held the larger value
  int chosen_interval(std::uint64_t trial_index, double difference, int larger_interval) const;
};

}  // namespace enact::psychophysics
