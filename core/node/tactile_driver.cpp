#include "core/node/tactile_driver.h"

#include <algorithm>

namespace enact::node {

void TactileDriver::activate() { device_.activate(); }

void TactileDriver::apply(std::int64_t now_ns, std::uint32_t pins, std::uint64_t frame_seq) noexcept {
  device_.write(now_ns, pins);
  frame_seq_ = frame_seq;
  ++applied_;
}

void TactileDriver::lower(std::int64_t now_ns) noexcept { device_.write(now_ns, 0u); }

void TactileDriver::levels(std::int64_t now_ns, float* out) const noexcept { device_.shown(now_ns, out, pins()); }

void TactileDriver::show(std::int64_t now_ns, PinsShown& out) const noexcept {
  out.time_ns = now_ns;
  levels(now_ns, out.level);
  out.moves = device_.motion(out.motion);
  out.frame_seq = frame_seq_;
}

void TactileDriver::deactivate() noexcept { device_.deactivate(); }

std::string TactileDriver::summary(const std::string& extra) const {
  return std::to_string(applied_) + " frames applied; " + extra + "pins lowered.";
}

std::uint32_t pins_up(const float* levels, int levels_count, int count) noexcept {
  std::uint32_t bits = 0;
  for (int i = 0; i < std::min(count, levels_count); ++i) bits |= levels[i] > 0.5f ? 1u << i : 0u;
  return bits;
}

}  // namespace enact::node
