#include "core/devices/hand.h"

#include <utility>

namespace enact::devices {

HandSource::~HandSource() = default;

void HandSource::feel_pins(const float*, int, int) noexcept {}

ScriptedHand::ScriptedHand(task::Trajectory path) : path_(std::move(path)) {}

void ScriptedHand::reset(const HandStart& start) noexcept { start_m_ = start.start_m; }

math::Vec3 ScriptedHand::target(std::int64_t time_ns, const HandFeel&) noexcept {
  if (path_.t_s.empty()) return start_m_;
  return path_.at(static_cast<double>(time_ns) * 1e-9);
}

}  // namespace enact::devices
