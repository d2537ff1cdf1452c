#include "core/haptics/tactile.h"

#include <cmath>
#include <stdexcept>

namespace enact::haptics {

TactileMode parse_tactile_mode(const std::string& text) {
  if (text == "sample") return TactileMode::sample;
  if (text == "any") return TactileMode::any;
  throw std::invalid_argument("unknown tactile mode '" + text + "' (use sample or any)");
}

void TactileDownsampler::configure(const TactileParams& params, double rate_hz) {
  mode_ = params.mode;
  steps_per_frame_ = std::max<std::int64_t>(1, std::llround(params.period_s * rate_hz));
  reset();
}

void TactileDownsampler::reset() {
  count_ = 0;
  accumulated_ = 0;
  frame_ = 0;
}

bool TactileDownsampler::push(std::uint32_t pins) {
  accumulated_ = mode_ == TactileMode::any ? accumulated_ | pins : pins;
  // the first step emits a frame, then one every steps_per_frame
  if (count_++ % steps_per_frame_ != 0) return false;
  frame_ = accumulated_;
  accumulated_ = 0;
  return true;
}

}  // namespace enact::haptics
