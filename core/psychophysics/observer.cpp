#include "core/psychophysics/observer.h"

#include "core/math/random.h"

namespace enact::psychophysics {

bool VirtualObserver::correct(std::uint64_t trial_index, double difference) const {
  math::Random r(math::derive_seed(seed, trial_index));
  return r.uniform() < function.probability(difference);
}

int VirtualObserver::chosen_interval(std::uint64_t trial_index, double difference, int larger_interval) const {
  return correct(trial_index, difference) ? larger_interval : 3 - larger_interval;
}

}  // namespace enact::psychophysics
