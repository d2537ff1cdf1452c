#pragma once
// Tactile down-sampling: the model runs at kHz rates, Braille cells cannot follow (Metec
// cells: rise time about 24 ms), so pin frames are emitted at a lower rate. Allocates nothing.
#include <cstdint>
#include <string>

namespace enact::haptics {

enum class TactileMode : std::uint8_t {
  sample,  // the pins of the step the frame falls on
  any,     // a pin is up when it was up at any step since the last frame (no brief contact lost)
};

struct TactileParams {
  double period_s = 0.024;  // default: the cells' rise time
  TactileMode mode = TactileMode::sample;
};

TactileMode parse_tactile_mode(const std::string& text);  // throws std::invalid_argument

class TactileDownsampler {
 public:
  // steps per frame = round(period_s * rate_hz), at least 1
  void configure(const TactileParams& params, double rate_hz);
  void reset();
  // one model step; true when a frame is due, then frame() holds it
  bool push(std::uint32_t pins);
  std::uint32_t frame() const { return frame_; }
  std::int64_t steps_per_frame() const { return steps_per_frame_; }

 private:
  TactileMode mode_ = TactileMode::sample;
  std::int64_t steps_per_frame_ = 1;
  std::int64_t count_ = 0;
  std::uint32_t accumulated_ = 0;
  std::uint32_t frame_ = 0;
};

}  // namespace enact::haptics
