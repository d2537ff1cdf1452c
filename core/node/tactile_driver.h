#pragma once
// The tactile display driver: one component whichever host runs it. enact-tactile
// (node/tactile.h) wires it to the bus: tactile/frame in, tactile/shown out, a watchdog that
// lowers the pins while frames stop; the co-located container (node/colocated.h) calls it in
// its tick: the frame the model made, then what the pins show for observers and for a
// virtual subject's fingertip. Both print its summary line when it ends.
#include <cstdint>
#include <string>

#include "core/devices/device.h"

namespace enact::node {

// what the pins show at a time: tactile/shown's content (trivially copyable: SPSC queues)
struct PinsShown {
  std::int64_t time_ns = 0;
  float level[32] = {};          // 0 = down .. 1 = up, pins 0 .. rows * cols
  devices::PinMotion motion;     // from the last frame on, where the device knows it
  bool moves = false;            // whether `motion` is known
  std::uint64_t frame_seq = 0;   // the tactile/frame the pins follow (0: none yet)
};

class TactileDriver {
 public:
  // drives `device` (configured: graph::make_tactile_device, from the tactile table's
  // parameters), which outlives it
  explicit TactileDriver(devices::TactileDevice& device) : device_(device) {}

  int rows() const { return device_.rows(); }
  int cols() const { return device_.cols(); }
  int pins() const { return device_.rows() * device_.cols(); }

  // output on, every pin down
  void activate();
  // a frame's pins from now_ns on (bit i: pin i up); frame_seq names it in what is shown.
  // On the loop: allocates nothing, never blocks
  void apply(std::int64_t now_ns, std::uint32_t pins, std::uint64_t frame_seq) noexcept;
  // every pin down from now_ns, until the next frame (a watchdog's action)
  void lower(std::int64_t now_ns) noexcept;
  // what the pins show at now_ns, levels[0 .. pins()) (a virtual subject's fingertip, every
  // tick); on the loop: allocates nothing
  void levels(std::int64_t now_ns, float* out) const noexcept;
  // the same with the pins' motion (tactile/shown's content), into out
  void show(std::int64_t now_ns, PinsShown& out) const noexcept;
  // every pin down, output off
  void deactivate() noexcept;
  // "N frames applied; <extra>pins lowered.": the line both hosts print at the end (extra,
  // the host's own counts, each ending in "; ")
  std::string summary(const std::string& extra = "") const;

 private:
  devices::TactileDevice& device_;
  std::uint64_t applied_ = 0;
  std::uint64_t frame_seq_ = 0;
};

// a tactile/frame's levels as pins (up: level above one half), pins 0 .. count
std::uint32_t pins_up(const float* levels, int levels_count, int count) noexcept;

}  // namespace enact::node
